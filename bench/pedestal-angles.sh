#!/usr/bin/env bash
# The pedestal mesh against the angle (docs/explanation/benchmarks.md, "The pedestal mesh"): the 18 cases of
# bench/pedestal-angles.toml (the quickstart's piles at 6 design points × 3 packings), each run with the old pedestal
# (5 mm triangles everywhere, demsa's until 2026-12-04) by OLD_LIGGGHTS and with the lean one (the top's rings 12.5 mm
# apart inside the same 5 mm rim and side band, demsa's since) by NEW_LIGGGHTS, both meshes from bench/pedestal_stl.py,
# paired by bench/liggghts-builds.sh. Prints its rate table, then per design point the
# angles of the three packings with each pedestal, the packing noise (the pooled within-point standard deviation,
# 12 degrees of freedom per pedestal) and the paired differences new − old.
#
# Usage: bench/pedestal-angles.sh DEMSA OLD_LIGGGHTS NEW_LIGGGHTS [WORK]
#   e.g. bench/pedestal-angles.sh build/orchestrator/demsa /usr/bin/liggghts \
#          $(scripts/build-liggghts.sh --print-prefix)/bin/liggghts /tmp/pedestal-angles
# Environment: JOBS (default 2) as in bench/liggghts-builds.sh. WORK (default a temporary folder) keeps the runs.
set -euo pipefail
(($# >= 3)) || { sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
demsa=$(realpath "$1")
old=$2
new=$3
work=${4:-$(mktemp -d)}
mkdir -p "$work"
study=$here/pedestal-angles.toml
ids=0,1000001,1000002,1,1001001,1001002,2,1002001,1002002,3,1003001,1003002,4,1004001,1004002,5,1005001,1005002
# The quickstart's pedestal (50 mm radius, 5 mm high): 5 mm triangles on the top as on the rim (old), or the top's
# rings 12.5 mm apart (new).
python3 "$here/pedestal_stl.py" 0.05 0.005 0.005 0.005 "$work/pedestal-old.stl"
python3 "$here/pedestal_stl.py" 0.05 0.005 0.005 0.0125 "$work/pedestal-new.stl"
WORK=$work "$here/liggghts-builds.sh" "$demsa" "$study" "$ids" \
  "old=$old@s|file pedestal.stl|file $work/pedestal-old.stl|" "new=$new@s|file pedestal.stl|file $work/pedestal-new.stl|"
python3 - "$work" "$ids" <<'PY'
import math, statistics, sys
work, ids = sys.argv[1], sys.argv[2].split(",")
angle = lambda name, k: float(open(f"{work}/{name}-{k}/angle.txt").read())
points = [ids[i:i + 3] for i in range(0, len(ids), 3)]
print("| design point | old pedestal [deg] (3 packings) | new pedestal [deg] | new − old per packing | mean new − old |")
print("|---|---|---|---|---|")
ss = {"old": 0.0, "new": 0.0}
diffs = []
for p, ks in enumerate(points):
    a = {n: [angle(n, k) for k in ks] for n in ("old", "new")}
    for n in a:
        m = statistics.mean(a[n]); ss[n] += sum((x - m) ** 2 for x in a[n])
    d = [y - x for x, y in zip(a["old"], a["new"])]
    diffs += d
    f = lambda v: ", ".join(f"{x:.2f}" for x in v)
    print(f"| {p} | {f(a['old'])} | {f(a['new'])} | {', '.join(f'{x:+.2f}' for x in d)} | {statistics.mean(d):+.2f} |")
dof = len(ids) - len(points)
for n in ss:
    print(f"packing noise, {n} pedestal: pooled sd {math.sqrt(ss[n] / dof):.2f} deg ({dof} degrees of freedom)")
md, sd = statistics.mean(diffs), statistics.stdev(diffs)
print(f"new − old over the {len(diffs)} cases: mean {md:+.2f} deg, sd {sd:.2f} deg, standard error {sd / math.sqrt(len(diffs)):.2f} deg")
mo = [statistics.mean([angle("old", k) for k in ks]) for ks in points]
mn = [statistics.mean([angle("new", k) for k in ks]) for ks in points]
print("per-point means new − old:", ", ".join(f"{b - a:+.2f}" for a, b in zip(mo, mn)))
PY
