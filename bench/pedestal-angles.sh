#!/usr/bin/env bash
# The pedestal mesh against the angle (docs/explanation/benchmarks.md, "The pedestal mesh"): the 18 cases of
# bench/pedestal-angles.toml (the quickstart's piles at 6 design points × 3 packings), each run with the old pedestal
# (5 mm triangles everywhere, demsa's pedestal) by OLD_LIGGGHTS and with the lean one (the top's rings 12.5 mm apart
# inside the same 5 mm rim and side band, tried and not adopted) by NEW_LIGGGHTS, both meshes from bench/pedestal_stl.py,
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
python3 "$here/paired_angles.py" "$work" "$ids" old new
