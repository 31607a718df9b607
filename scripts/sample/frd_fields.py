#!/usr/bin/env python3
"""Check the stress and plastic-strain output of a CalculiX .frd and print its ranges.

Standard library only (reads with frd_to_obj.py).  Every DISP block must have a
STRESS block (6 components) and a PE block (1 component) at the same time with a
value for every node of the DISP block; von Mises is computed from the stress
tensor, as dynpm's reader does (node field S_MISES; PE becomes PEEQ).  Prints one
line of shell assignments for make_sample.sh:

  field_times=N mises_min=X mises_max=X peeq_min=X peeq_max=X
  mises_peak=X mises_peak_time=T peeq_peak=X peeq_peak_time=T peeq_max_z=Z other_blocks="..."

*_min/*_max are the range over the nodes at the last output time, *_peak the
largest value over all times, peeq_max_z the undeformed z of the node with the
largest PEEQ at the last time; other_blocks names further result blocks (ccx writes
its ERROR estimate with S).

usage: frd_fields.py INPUT.frd[.gz]
"""
import gzip
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from frd_to_obj import FrdError, read_frd  # noqa: E402

KNOWN = ("DISP", "STRESS", "PE")


def von_mises(s):
    sxx, syy, szz, sxy, syz, szx = s[:6]
    return math.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2)
                     + 3.0 * (sxy * sxy + syz * syz + szx * szx))


def block_names(path):
    """Names of every result block in the file, in order of first appearance."""
    opener = gzip.open if path.endswith(".gz") else open
    names = []
    with opener(path, "rt", encoding="ascii", errors="replace") as f:
        for line in f:
            if line.startswith(" -4"):
                name = line[3:].split()[0].upper()
                if name not in names:
                    names.append(name)
    return names


def fmt(x):
    return "%.4g" % x


def main(argv):
    if len(argv) != 2:
        sys.exit(__doc__.strip().splitlines()[-1])
    path = argv[1]
    try:
        nodes, _, blocks = read_frd(path, KNOWN)
    except FrdError as e:
        sys.exit("frd_fields.py: error: %s" % e)
    disp, stress, pe = blocks["DISP"], blocks["STRESS"], blocks["PE"]
    if not disp:
        sys.exit("frd_fields.py: FAILED: %s has no DISP block" % path)
    stress_at = {t: v for _, t, _, v in stress}
    pe_at = {t: v for _, t, _, v in pe}
    mises_peak = peeq_peak = (-math.inf, 0.0)
    for k, t, _, d in disp:
        for what, at in (("STRESS", stress_at), ("PE", pe_at)):
            if t not in at:
                sys.exit("frd_fields.py: FAILED: no %s block at time %g (DISP block %d)"
                         % (what, t, k))
            lacking = [n for n in d if n not in at[t]]
            if lacking:
                sys.exit("frd_fields.py: FAILED: %s block at time %g has no value for node %d"
                         % (what, t, lacking[0]))
        if any(len(v) < 6 for v in stress_at[t].values()):
            sys.exit("frd_fields.py: FAILED: STRESS block at time %g has fewer than 6 "
                     "components" % t)
        order = sorted(d)
        mises = [von_mises(stress_at[t][n]) for n in order]
        peeq = [pe_at[t][n][0] for n in order]
        mises_peak = max(mises_peak, (max(mises), t))
        peeq_peak = max(peeq_peak, (max(peeq), t))
    peeq_max_node = order[peeq.index(max(peeq))]
    others = [n for n in block_names(path) if n not in KNOWN]
    print("field_times=%d mises_min=%s mises_max=%s peeq_min=%s peeq_max=%s "
          "mises_peak=%s mises_peak_time=%s peeq_peak=%s peeq_peak_time=%s peeq_max_z=%s "
          "other_blocks=\"%s\""
          % (len(disp), fmt(min(mises)), fmt(max(mises)), fmt(min(peeq)), fmt(max(peeq)),
             fmt(mises_peak[0]), fmt(mises_peak[1]), fmt(peeq_peak[0]), fmt(peeq_peak[1]),
             fmt(nodes[peeq_max_node][2]),
             " ".join(others)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
