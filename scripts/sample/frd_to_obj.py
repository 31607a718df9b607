#!/usr/bin/env python3
"""Convert a CalculiX ASCII result file (.frd) into an OBJ sequence.

Standard library only.  Reads the node block (2C), the element block (3C) and
every nodal result block (100C) named DISP, and writes

  OUTDIR/frame_000.obj   undeformed geometry (node coordinates)
  OUTDIR/frame_001.obj   coordinates + displacement of the 1st DISP block
  ...
  OUTDIR/times.csv       frame,frd_block,time,max_disp

Vertex i (1-based in OBJ) is the i-th node, in ascending node number, among
the nodes used by the shell elements (for a plain shell model that is every
node of the 2C block).  Faces follow in ascending element number: 4-node
shells (frd type 9, qu4, written by ccx for S4/S4R) as quads "f a b c d",
3-node shells (frd type 7, tr3, for S3) as triangles.  Every frame has the
same face lines.  The first line of each OBJ is a comment naming the source
file, the frame and its time.  frd_block in times.csv is the 1-based index of
the DISP block in the .frd (0 for the undeformed frame 0); max_disp is the
largest displacement magnitude |u| over the written nodes.

A gzip-compressed input (name ending in .gz) is read directly.

usage: frd_to_obj.py [-q] INPUT.frd[.gz] OUTDIR
"""
import gzip
import math
import os
import sys

# frd element type -> (name, number of nodes)
FRD_ELEMENTS = {1: ("he8", 8), 2: ("pe6", 6), 3: ("te4", 4), 4: ("he20", 20),
                5: ("pe15", 15), 6: ("te10", 10), 7: ("tr3", 3), 8: ("tr6", 6),
                9: ("qu4", 4), 10: ("qu8", 8), 11: ("be2", 2), 12: ("be3", 3)}
SURFACE_TYPES = {7, 9}


class FrdError(Exception):
    pass


class Reader:
    def __init__(self, path):
        self.path = path
        opener = gzip.open if path.endswith(".gz") else open
        try:
            self.f = opener(path, "rt", encoding="ascii", errors="replace")
            self.f.read(1)
            self.f.seek(0)
        except OSError as e:
            raise FrdError("cannot read %s: %s" % (path, e))
        self.lineno = 0

    def next(self, what):
        line = self.f.readline()
        if not line:
            raise FrdError("%s: unexpected end of file while reading %s "
                           "(truncated .frd?)" % (self.path, what))
        self.lineno += 1
        return line.rstrip("\r\n")

    def fail(self, msg, line=None):
        s = "%s:%d: %s" % (self.path, self.lineno, msg)
        if line is not None:
            s += "\n    line: %r" % line
        raise FrdError(s)


def fixed_int(r, line, a, b, what):
    try:
        return int(line[a:b])
    except ValueError:
        r.fail("bad %s in columns %d-%d" % (what, a + 1, b), line)


def fixed_floats(r, line, start, count, what):
    vals = []
    for k in range(count):
        a = start + 12 * k
        field = line[a:a + 12]
        try:
            vals.append(float(field))
        except ValueError:
            r.fail("bad %s value %d (columns %d-%d)" % (what, k + 1, a + 1, a + 12), line)
    return vals


def header_format(r, line, what):
    """Format flag of a 2C/3C/100C header: 0 short, 1 long, 2 binary."""
    toks = line.split()
    try:
        fmt = int(toks[-1])
    except (ValueError, IndexError):
        r.fail("cannot read the format flag of the %s header" % what, line)
    if fmt == 2:
        r.fail("binary .frd blocks are not supported; write ASCII output "
               "(ccx writes ASCII unless *NODE FILE/*OUTPUT asks otherwise)", line)
    if fmt not in (0, 1):
        r.fail("unknown format flag %d in the %s header" % (fmt, what), line)
    return fmt


def read_nodes(r, header):
    fmt = header_format(r, header, "node block (2C)")
    w = 10 if fmt == 1 else 5
    nodes = {}
    while True:
        line = r.next("the node block")
        key = line[:3]
        if key == " -3":
            return nodes
        if key != " -1":
            r.fail("expected ' -1' node record or ' -3' end of node block", line)
        n = fixed_int(r, line, 3, 3 + w, "node number")
        if n in nodes:
            r.fail("node %d defined twice" % n, line)
        nodes[n] = fixed_floats(r, line, 3 + w, 3, "coordinate")


def read_elements(r, header):
    fmt = header_format(r, header, "element block (3C)")
    w = 10 if fmt == 1 else 5
    per_line = 10 if fmt == 1 else 15
    elems = {}
    while True:
        line = r.next("the element block")
        key = line[:3]
        if key == " -3":
            return elems
        if key != " -1":
            r.fail("expected ' -1' element record or ' -3' end of element block", line)
        e = fixed_int(r, line, 3, 3 + w, "element number")
        t = fixed_int(r, line, 3 + w, 8 + w, "element type")
        if t not in FRD_ELEMENTS:
            r.fail("element %d has unknown frd element type %d" % (e, t), line)
        if e in elems:
            r.fail("element %d defined twice" % e, line)
        nn = FRD_ELEMENTS[t][1]
        conn = []
        while len(conn) < nn:
            cl = r.next("the nodes of element %d" % e)
            if cl[:3] != " -2":
                r.fail("expected ' -2' node list of element %d (%s, %d nodes)"
                       % (e, FRD_ELEMENTS[t][0], nn), cl)
            body = cl[3:]
            k = 0
            while k * w < len(body.rstrip()) and k < per_line and len(conn) < nn:
                field = body[k * w:(k + 1) * w]
                try:
                    conn.append(int(field))
                except ValueError:
                    r.fail("bad node number in the node list of element %d" % e, cl)
                k += 1
        elems[e] = (t, conn)


def read_result(r, header):
    """Read one 100C block; return (name, time, step, {node: values})."""
    # (1X,' 100','C',6A1,E12.5,I12,20A1,I2,I5,10A1,I2)
    setname = header[6:12].strip()
    try:
        time = float(header[12:24])
    except ValueError:
        r.fail("bad time value in columns 13-24 of the 100C header", header)
    fmt = header_format(r, header, "result block (100C)")
    w = 10 if fmt == 1 else 5
    line = r.next("the result block header")
    if line[:3] != " -4":
        r.fail("expected ' -4' after the 100C header", line)
    toks = line[3:].split()
    if len(toks) < 2:
        r.fail("bad ' -4' record", line)
    name = toks[0]
    try:
        ncomp = int(toks[1])
    except ValueError:
        r.fail("bad component count in ' -4' record", line)
    ncomp_data = 0
    values = {}
    while True:
        line = r.next("result block %s" % name)
        key = line[:3]
        if key == " -5":
            # ' -5' component lines; components with type flag 1 in column
            # "ictype" that are 'ALL' are not stored in the data lines
            toks = line[3:].split()
            if not (len(toks) >= 5 and toks[0].upper() == "ALL"):
                ncomp_data += 1
            continue
        if key == " -3":
            break
        if key != " -1":
            r.fail("expected ' -1' data record or ' -3' end of block %s" % name, line)
        n = fixed_int(r, line, 3, 3 + w, "node number")
        body_start = 3 + w
        have = (len(line.rstrip()) - body_start) // 12
        need = ncomp_data if ncomp_data else ncomp
        if have < min(need, 6):
            r.fail("data line of node %d in block %s has %d values, expected %d "
                   "(truncated line?)" % (n, name, max(have, 0), min(need, 6)), line)
        vals = fixed_floats(r, line, body_start, min(need, 6), name)
        while len(vals) < need:
            cl = r.next("continuation of node %d in block %s" % (n, name))
            if cl[:3] != " -2":
                r.fail("expected ' -2' continuation line for node %d in %s" % (n, name), cl)
            more = (len(cl.rstrip()) - body_start) // 12
            vals += fixed_floats(r, cl, body_start, min(more, need - len(vals), 6), name)
            if more <= 0:
                r.fail("empty continuation line", cl)
        if n in values:
            r.fail("node %d appears twice in block %s" % (n, name), line)
        values[n] = vals
    return name, time, setname, values


def read_frd(path, names=("DISP",)):
    """Return nodes, elements and {name: [(index, time, setname, {node: values})]} for the
    result blocks named in names (index: 1-based among the blocks of that name)."""
    r = Reader(path)
    nodes = elems = None
    blocks = {n: [] for n in names}
    saw_end = False
    with r.f:
        while True:
            line = r.f.readline()
            if not line:
                break
            r.lineno += 1
            line = line.rstrip("\r\n")
            if not line.strip():
                continue
            head = line[:6]
            if head == "    1C" or head[:5] in ("    1",):
                continue  # 1C / 1U / 1P header and parameter lines
            if head == "    2C":
                if nodes is not None:
                    r.fail("second node block (2C); only one mesh per file is supported", line)
                nodes = read_nodes(r, line)
            elif head == "    3C":
                if elems is not None:
                    r.fail("second element block (3C); only one mesh per file is supported", line)
                elems = read_elements(r, line)
            elif head == "  100C":
                if nodes is None:
                    r.fail("result block before the node block", line)
                name, time, setname, values = read_result(r, line)
                name = name.upper()
                if name in blocks:
                    k = len(blocks[name]) + 1
                    if name == "DISP" and any(len(v) < 3 for v in values.values()):
                        r.fail("DISP block %d has fewer than 3 components" % k)
                    blocks[name].append((k, time, setname, values))
            elif line.strip() == "9999":
                saw_end = True
                break
            else:
                r.fail("unexpected line outside any block", line)
    if nodes is None:
        raise FrdError("%s: no node block (2C) found; is this a CalculiX .frd?" % path)
    if elems is None:
        raise FrdError("%s: no element block (3C) found" % path)
    if not saw_end:
        print("frd_to_obj.py: warning: %s has no closing '9999' line (truncated?)" % path,
              file=sys.stderr)
    return nodes, elems, blocks


def fmt_num(x):
    s = "%.7g" % x
    return "0" if s == "-0" else s


def convert(frd_path, outdir, quiet=False):
    nodes, elems, blocks = read_frd(frd_path)
    disp_blocks = blocks["DISP"]
    if not disp_blocks:
        raise FrdError("%s: no DISP result blocks (add *NODE FILE with U to the deck)" % frd_path)
    bad = sorted({t for t, _ in elems.values() if t not in SURFACE_TYPES})
    if bad:
        names = ", ".join("%d (%s)" % (t, FRD_ELEMENTS[t][0]) for t in bad)
        hint = ""
        if any(t in (1, 2, 4, 5) for t in bad):
            hint = ("; solid elements in the .frd usually mean ccx wrote the expanded "
                    "3-D shells (use *NODE FILE, OUTPUT=2D) or the model has solids")
        raise FrdError("%s: unsupported element types %s: only 4-node (9, qu4) and "
                       "3-node (7, tr3) shells are converted%s" % (frd_path, names, hint))
    used = sorted({n for _, c in elems.values() for n in c})
    missing = [n for n in used if n not in nodes]
    if missing:
        raise FrdError("%s: elements use node %d which is not in the node block"
                       % (frd_path, missing[0]))
    index = {n: i + 1 for i, n in enumerate(used)}
    enums = sorted(elems)
    nq = sum(1 for e in enums if elems[e][0] == 9)
    nt = len(enums) - nq
    face_lines = []
    for e in enums:
        face_lines.append("f " + " ".join(str(index[n]) for n in elems[e][1]) + "\n")
    faces = "".join(face_lines)

    for b, time, setname, disp in disp_blocks:
        lacking = [n for n in used if n not in disp]
        if lacking:
            raise FrdError("%s: DISP block %d (time %g) has no value for node %d"
                           % (frd_path, b, time, lacking[0]))

    os.makedirs(outdir, exist_ok=True)
    nframes = len(disp_blocks) + 1
    width = max(3, len(str(nframes - 1)))
    src = os.path.basename(frd_path)
    if src.endswith(".gz"):
        src = src[:-3]
    rows = []
    frames = [(0, 0, 0.0, None)] + [(i + 1, b, t, d) for i, (b, t, _, d) in enumerate(disp_blocks)]
    for frame, block, time, disp in frames:
        out = []
        maxd = 0.0
        for n in used:
            x, y, z = nodes[n]
            if disp is not None:
                u = disp[n]
                x, y, z = x + u[0], y + u[1], z + u[2]
                m = math.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
                if m > maxd:
                    maxd = m
            out.append("v %s %s %s\n" % (fmt_num(x), fmt_num(y), fmt_num(z)))
        what = "undeformed" if disp is None else "frd DISP block %d" % block
        head = ("# %s frame %d: time %s (%s); %d vertices, %d faces (%d quads, %d triangles)\n"
                % (src, frame, fmt_num(time), what, len(used), len(enums), nq, nt))
        name = os.path.join(outdir, "frame_%0*d.obj" % (width, frame))
        with open(name, "w", newline="\n") as f:
            f.write(head)
            f.writelines(out)
            f.write(faces)
        rows.append("%d,%d,%s,%s\n" % (frame, block, fmt_num(time), fmt_num(maxd)))
    with open(os.path.join(outdir, "times.csv"), "w", newline="\n") as f:
        f.write("frame,frd_block,time,max_disp\n")
        f.writelines(rows)
    if not quiet:
        print("frd_to_obj.py: %s -> %s: %d frames, %d vertices, %d quads, %d triangles, "
              "max |u| %s" % (frd_path, outdir, nframes, len(used), nq, nt, rows[-1].split(",")[3].strip()))
    return nframes, len(used), nq, nt


def main(argv):
    args = [a for a in argv[1:] if a != "-q"]
    quiet = len(args) != len(argv) - 1
    if len(args) != 2 or args[0].startswith("-"):
        sys.stderr.write(__doc__.strip().splitlines()[-1] + "\n")
        return 2
    try:
        convert(args[0], args[1], quiet)
    except FrdError as e:
        sys.stderr.write("frd_to_obj.py: error: %s\n" % e)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
