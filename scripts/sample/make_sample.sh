#!/usr/bin/env bash
# Build the dynpm sample data set data/hat-rail/ from scratch with real FE tools:
#   gmsh (rail.geo -> shell mesh) -> gmsh_to_ccx.py (S4/S3 deck include)
#   -> CalculiX ccx (rail.inp, static NLGEOM plastic bending collapse)
#   -> frd_to_obj.py (OBJ sequence) -> check_frames.py, frd_fields.py (stress and plastic
#   strain at every output time) -> pack into data/hat-rail/
#
# usage: bash scripts/sample/make_sample.sh [OUTDIR]   (default: data/hat-rail)
# env:   NPROC (threads for ccx, default 2), KEEP=1 keeps the work directory,
#        WORKDIR (default: a fresh mktemp directory),
#        SKIP_CCX=1 reuses rail.frd/rail.dat/ccx.log already in WORKDIR (re-pack only)
# needs: gmsh, ccx (Debian: gmsh, calculix-ccx), python3, tar, xz, gzip
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${1:-$root/data/hat-rail}
nproc=${NPROC:-2}
py=${PYTHON:-python3}

for tool in gmsh ccx "$py" tar xz gzip; do
    command -v "$tool" >/dev/null || { echo "make_sample.sh: '$tool' not found (apt-get install gmsh calculix-ccx)" >&2; exit 1; }
done

work=${WORKDIR:-$(mktemp -d "${TMPDIR:-/tmp}/dynpm-sample.XXXXXX")}
mkdir -p "$work"
if [[ "${KEEP:-0}" != 1 && -z "${WORKDIR:-}" ]]; then trap 'rm -rf "$work"' EXIT; fi
echo "make_sample.sh: working in $work"

gmsh_version=$(gmsh --version 2>&1 | tail -n 1)
ccx_version=$(ccx -v 2>&1 | grep -o 'Version [0-9.]*' | head -n 1 || true)
[[ -n "$ccx_version" ]] || ccx_version="(unknown version)"

# 1. mesh
echo "== gmsh $gmsh_version: rail.geo"
gmsh -2 "$here/rail.geo" -format inp -o "$work/rail_gmsh.inp" > "$work/gmsh.log" 2>&1 \
    || { tail -n 20 "$work/gmsh.log" >&2; echo "make_sample.sh: gmsh failed" >&2; exit 1; }
"$py" "$here/gmsh_to_ccx.py" "$work/rail_gmsh.inp" "$work/rail_mesh.inp"

# 2. solve
echo "== CalculiX ccx $ccx_version: rail.inp ($nproc threads)"
cp "$here/rail.inp" "$work/rail.inp"
t0=$(date +%s)
if [[ "${SKIP_CCX:-0}" == 1 && -n "${WORKDIR:-}" && -s "$work/rail.frd" ]]; then
    echo "(SKIP_CCX=1: reusing $work/rail.frd)"
else
    ( cd "$work" && OMP_NUM_THREADS=$nproc CCX_NPROC_STIFFNESS=$nproc ccx -i rail > ccx.log 2>&1 ) \
        || { tail -n 30 "$work/ccx.log" >&2; echo "make_sample.sh: ccx failed" >&2; exit 1; }
fi
t1=$(date +%s)
if grep -q '\*ERROR' "$work/ccx.log" || ! grep -q 'Job finished' "$work/ccx.log"; then
    grep -m5 -A3 '\*ERROR' "$work/ccx.log" >&2 || tail -n 30 "$work/ccx.log" >&2
    echo "make_sample.sh: ccx did not finish the job" >&2; exit 1
fi
echo "ccx wall time: $((t1 - t0)) s"

# 3. convert and check
"$py" "$here/frd_to_obj.py" "$work/rail.frd" "$work/obj"
summary=$("$py" "$here/check_frames.py" "$work/obj" 26)
echo "check: $summary"
eval "$summary"   # frames= nodes= quads= triangles= max_disp= final_time=
ntotal=$((quads + triangles))
tri_pct=$(awk -v t="$triangles" -v n="$ntotal" 'BEGIN{printf "%.1f", 100*t/n}')
fields=$("$py" "$here/frd_fields.py" "$work/rail.frd")
echo "fields: $fields"
eval "$fields"   # field_times= mises_min= mises_max= peeq_min= peeq_max= ... peeq_max_z= other_blocks=
peeq_note=""
[[ "$peeq_min" == -* ]] && peeq_note=" (below 0 where the extrapolation to the nodes undershoots)"
(( field_times == frames - 1 )) || { echo "make_sample.sh: stress output at $field_times of $((frames - 1)) times" >&2; exit 1; }
tip_force=$(awk '/total force/{getline; getline; f=$2} END{printf "%.2f", f/1000}' "$work/rail.dat")
peak_force=$(awk '/total force/{getline; getline; if($2>m)m=$2} END{printf "%.2f", m/1000}' "$work/rail.dat")

# 4. pack (reproducible: sorted names, fixed mtime/owner, single-threaded xz, gzip -n)
mkdir -p "$out"
rm -f "$out/frames.tar.xz" "$out/rail.frd.gz" "$out/preview.png"
tar --sort=name --mtime=@0 --owner=0 --group=0 --numeric-owner --format=gnu \
    -C "$work/obj" -cf - $(cd "$work/obj" && ls frame_*.obj) times.csv \
    | xz -9e -T1 > "$out/frames.tar.xz"
gzip -9n -c "$work/rail.frd" > "$work/rail.frd.gz"
frd_note=""
frd_mb=$(awk -v b="$(stat -c %s "$work/rail.frd.gz")" 'BEGIN{printf "%.1f", b/1e6}')
if (( $(stat -c %s "$work/rail.frd.gz") < 8000000 )); then
    cp "$work/rail.frd.gz" "$out/rail.frd.gz"
    frd_note="- \`rail.frd.gz\` (${frd_mb} MB) — CalculiX's own ASCII result file (gzip -9n): node block,
  ${quads} S4 (frd type 9) and ${triangles} S3 (frd type 7) shells, then for each of the
  $((frames - 1)) output times a DISP block (\`*NODE FILE, OUTPUT=2D\`: U), a STRESS block (6
  components) and a PE block (equivalent plastic strain) (\`*EL FILE, OUTPUT=2D\`: S, PEEQ)${other_blocks:+,
  and the ${other_blocks} block ccx adds to S (its stress error estimate, in %)}. The element
  results are extrapolated from the integration points to the shell's own nodes, one value
  per node (so they need not lie on the hardening curve). dynpm reads STRESS as the node
  field \`S_MISES\` (von Mises, MPa) and PE as \`PEEQ\`${other_blocks:+, and ${other_blocks} by its name}."
else
    frd_note="- (the compressed .frd, ${frd_mb} MB, exceeded 8 MB and is not shipped; re-run the script to get it)"
fi
last=$(printf 'frame_%03d.obj' $((frames - 1)))
if "$py" "$here/render_png.py" "$work/preview.png" "$work/obj/frame_000.obj" "$work/obj/$last"; then
    cp "$work/preview.png" "$out/preview.png"
fi
sed -n '2,$p' "$work/obj/times.csv" > "$work/times.body"

cat > "$out/README.md" <<README
# hat-rail — a sheet-metal hat-section rail bent to collapse (CalculiX)

Sample data for dynpm, made for this project by \`bash scripts/sample/make_sample.sh\`
(gmsh ${gmsh_version}, CalculiX ${ccx_version}, Debian packages \`gmsh\` and \`calculix-ccx\`).
Everything here is generated; re-running the script rebuilds it from the inputs in
\`scripts/sample/\` (\`rail.geo\`, \`rail.inp\`, \`gmsh_to_ccx.py\`, \`frd_to_obj.py\`,
\`frd_fields.py\`).

## The model
- **Geometry** (\`rail.geo\`, mm): an open top-hat profile swept 350 mm along z — hat top
  50 mm wide at y = 40, drafted walls down to feet 70 mm apart at y = 0, two 20 mm flanges;
  sharp bends (no bend radii). Crush initiators near the clamped end: a Ø18 hole in the top
  at z = 30 and a Ø12 hole through both walls at z = 75.
- **Mesh** (gmsh, 5.5 mm, frontal-Delaunay + blossom recombination): ${nodes} nodes,
  ${ntotal} shells = ${quads} quads (S4) + ${triangles} triangles (S3, ${tri_pct} %). The
  triangles are the free-meshed patch of the top face around the Ø18 hole (z = 18…42 mm);
  all other faces are quad-meshed. One connected, consistently oriented (manifold) sheet
  with boundary (flange edges, rail ends, hole rims).
- **Material**: steel, E = 210 GPa, ν = 0.3, elastic-plastic with isotropic hardening
  (true yield stress 200 MPa rising to 460 MPa at plastic strain 1.0); shell thickness 1.2 mm.
- **Loading**: end z = 0 clamped; the whole end section z = 350 is pushed 120 mm in +y
  (held in x, free along z). Static step with NLGEOM, automatic increments, output at 30
  equally spaced step times (time 1 … 30, tip displacement 4 mm per output). The hat top
  is compressed near the root: between the clamp and the top hole it buckles inward (about
  6 mm) while the walls bulge outward, forming a plastic hinge about which the rest of the
  rail swings up nearly rigidly (tip reaction peaks at ${peak_force} kN, then falls to
  ${tip_force} kN). No contact is modelled (none occurs at this stroke).
- **Frames**: ${frames} = the undeformed state + $((frames - 1)) output times; the largest nodal
  displacement grows monotonically to ${max_disp} mm (final frame).
- **Result fields** (in \`rail.frd.gz\`, per node, at every output time): von Mises stress
  and equivalent plastic strain (PEEQ).
  - last step (time ${final_time}): von Mises ${mises_min} … ${mises_max} MPa;
    PEEQ ${peeq_min} … ${peeq_max}${peeq_note};
  - largest over all times: von Mises ${mises_peak} MPa (time ${mises_peak_time});
    PEEQ ${peeq_peak} (time ${peeq_peak_time});
  - the last step's largest PEEQ is at z = ${peeq_max_z} mm (undeformed position), in the
    hinge near the clamp.

## Files
- \`frames.tar.xz\` — \`frame_000.obj … ${last}\` and \`times.csv\` (columns
  \`frame,frd_block,time,max_disp\`; frd_block = index of the DISP block in the .frd, 0 for
  the undeformed frame; max_disp = largest |u| in mm). Vertex i is the i-th node in
  ascending node number, faces in ascending element number (\`f a b c d\` quads,
  \`f a b c\` triangles), identical face lines in every frame, positions = node
  coordinates + displacement. Unpack with \`tar xJf frames.tar.xz\`.
${frd_note}
- \`preview.png\` — frame 0 and the last frame (\`scripts/sample/render_png.py\`).

## Frame table (times.csv)
\`\`\`
frame,frd_block,time,max_disp
$(cat "$work/times.body")
\`\`\`

## License
Made by the dynpm project with free tools from our own inputs; same license as the project.
README

echo "== wrote $out:"
ls -l "$out"
du -sh "$out"
