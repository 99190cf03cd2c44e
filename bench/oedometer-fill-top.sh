#!/usr/bin/env bash
# The settled fill of oedometer cases, as the plate meets it (docs/how-to/cost.md, "A held-out paper-size first
# load"): runs each case folder (written by `demsa case`) only up to the end of its fill, dumps the particles, and
# prints per case the fill's void ratio (plate_states.txt's settled packing, as the case itself records it), the five
# highest particles (centre x, y, their gap to the nearest side wall, radius, top below the highest), the k-th highest
# top below the highest, the spread of the top over a 10 x 10 grid of columns, and the solid fraction in layers below
# the highest top. What sets a dense fill's first load is the question; this prints what a probe could read of it.
#
# Usage: bench/oedometer-fill-top.sh LIGGGHTS CASE_DIR...
#   LIGGGHTS  a LIGGGHTS executable (e.g. "$(scripts/build-liggghts.sh --print-prefix)/bin/liggghts")
#   WORK=DIR  where the runs go (default a new folder in /tmp); each case is copied there, its folder left as it is
#   RANKS=N   MPI ranks (default 1): a fill is the same to the last digit only with the rank count of the run compared
set -euo pipefail
(($# >= 2)) || { sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
liggghts=$(realpath "$1")
shift
lib=$(dirname "$(dirname "$liggghts")")/lib
work=${WORK:-$(mktemp -d /tmp/oedometer-fill-top.XXXXXX)}
mkdir -p "$work"
ranks=${RANKS:-1}
[[ $ranks =~ ^[1-9][0-9]*$ ]] || { echo "RANKS=$ranks: give a positive whole number" >&2; exit 2; }
launch=()
if ((ranks > 1)); then
  launch=(mpirun --bind-to none -np "$ranks")
  [[ $(id -u) != 0 ]] || launch+=(--allow-run-as-root)
fi
for c in "$@"; do
  [[ -f $c/in.liggghts && -f $c/oedometer_fill.liggghts && -f $c/case.json ]] ||
    { echo "$c: not an oedometer case folder (no in.liggghts, oedometer_fill.liggghts or case.json)" >&2; exit 2; }
  d=$work/$(basename "$(realpath "$c")")
  rm -rf "$d" && cp -r "$c" "$d"
  # The case's own script up to and including its fill, then the particles.
  sed '/^include *oedometer_fill.liggghts/q' "$d/in.liggghts" > "$d/fill.in"
  echo "write_dump      all custom fill.dump id x y z radius" >> "$d/fill.in"
  (cd "$d" && LD_LIBRARY_PATH=$lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} "${launch[@]}" "$liggghts" -in fill.in \
    -log log.liggghts -screen screen.txt > /dev/null) ||
    { echo "$c: LIGGGHTS failed (see $d/log.liggghts)" >&2; exit 1; }
done
python3 - "$work" "$@" <<'EOF'
import json, math, os, statistics, sys

work = sys.argv[1]
for case in sys.argv[2:]:
    d = os.path.join(work, os.path.basename(os.path.realpath(case)))
    side = json.load(open(os.path.join(d, "case.json")))["oedometer"]["box_side_m"]
    lines = open(os.path.join(d, "fill.dump")).read().splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
    p = [tuple(float(v) for v in l.split()[1:5]) for l in lines[start:] if l.strip()]  # x, y, z, radius
    p.sort(key=lambda q: q[2] + q[3], reverse=True)
    zmax = p[0][2] + p[0][3]
    h = side / 2
    below = lambda q: (zmax - q[2] - q[3]) * 1e3
    wall_gap = lambda q: (h - max(abs(q[0]), abs(q[1])) - q[3]) * 1e3
    mm = lambda v: f"{round(v, 2) + 0.0:.2f}"  # no "-0.00" for a particle at the wall or at the top
    print(f"{case}: {open(os.path.join(d, 'plate_states.txt')).readline().strip()}")
    print("  highest (x, y [mm], gap to a side wall [mm], r [mm], below the highest [mm]): " + "; ".join(
        f"({q[0]*1e3:.1f}, {q[1]*1e3:.1f}) {mm(wall_gap(q))} {q[3]*1e3:.2f} {mm(below(q))}" for q in p[:5]))
    print("  k-th highest below the highest [mm]: " +
          ", ".join(f"{k}: {mm(below(p[k-1]))}" for k in (2, 3, 5, 10, 20, 50)))
    n = 10
    column = {}
    for q in p:
        key = tuple(min(n - 1, max(0, int((c + h) / side * n))) for c in q[:2])
        column[key] = max(column.get(key, -math.inf), q[2] + q[3])
    tops = [(zmax - t) * 1e3 for t in column.values()]
    print(f"  {n} x {n} columns' tops below the highest [mm]: median {statistics.median(tops):.2f}, "
          f"lowest {max(tops):.2f}, sd {statistics.pstdev(tops):.2f}")
    layers = []
    for lo, hi in ((0, 5), (5, 10), (10, 20), (20, 30), (30, 40)):
        v = sum(4.0 / 3.0 * math.pi * q[3]**3 for q in p if zmax - hi * 1e-3 < q[2] <= zmax - lo * 1e-3)
        layers.append(f"{lo}-{hi} mm {v / (side * side * (hi - lo) * 1e-3):.3f}")
    print("  solid fraction of the centres' layers below the highest: " + ", ".join(layers))
EOF
