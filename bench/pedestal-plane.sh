#!/usr/bin/env bash
# The pedestal top as a plane against the mesh (docs/explanation/benchmarks.md, "The pedestal top as a plane"): the
# 18 cases of bench/pedestal-plane.toml (the quickstart's piles at 6 design points × 3 packings, pedestal_top =
# "mesh"), each run as written and with its pedestal top turned into demsa's plane (pedestal_top = "plane": the
# primitive plane, the particles past the rim removed), by the same LIGGGHTS, paired by bench/liggghts-builds.sh.
# First checks that the edited scripts are those demsa writes for the plane. Prints the rate table, then per design
# point the angles of the three packings with each top, the packing noise, the paired differences plane − mesh and
# the CPU-seconds of the two.
#
# Usage: bench/pedestal-plane.sh DEMSA LIGGGHTS [WORK]
#   e.g. bench/pedestal-plane.sh build/orchestrator/demsa $(scripts/build-liggghts.sh --print-prefix)/bin/liggghts
# Environment: JOBS (default 2) as in bench/liggghts-builds.sh. WORK (default a temporary folder) keeps the runs.
set -euo pipefail
(($# >= 2)) || { sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
demsa=$(realpath "$1")
liggghts=$2
work=${3:-$(mktemp -d)}
mkdir -p "$work"
study=$here/pedestal-plane.toml
ids=0,1000001,1000002,1,1001001,1001002,2,1002001,1002002,3,1003001,1003002,4,1004001,1004002,5,1005001,1005002
plane='/^fix pedm /d;'\
's|^fix pedw .* mesh n_meshes 1 meshes pedm$|fix pedw        all wall/gran model hertz tangential history rolling_friction cdt primitive type 2 zplane ${pedestal_height}|;'\
's|^region  *fallen intersect 2 below_top off_radius$|region          fallen cylinder z 0.0 0.0 ${pedestal_radius} INF INF units box side out|'
# The edit is demsa's plane: case 0 of the study with pedestal_top = "plane", its comments aside.
sed 's/^pedestal_top = "mesh"/pedestal_top = "plane"/' "$study" >"$work/plane.toml"
rm -rf "$work/check-mesh" "$work/check-plane"
"$demsa" case "$study" --sample 0 -o "$work/check-mesh" >/dev/null
"$demsa" case "$work/plane.toml" --sample 0 -o "$work/check-plane" >/dev/null
sed -i -e "$plane" "$work/check-mesh/in.liggghts"
diff <(grep -v '^#' "$work/check-mesh/in.liggghts") <(grep -v '^#' "$work/check-plane/in.liggghts") >/dev/null ||
  { echo "pedestal-plane: the edit is not the script demsa writes for pedestal_top = \"plane\"" >&2; exit 1; }
WORK=$work "$here/liggghts-builds.sh" "$demsa" "$study" "$ids" "mesh=$liggghts" "plane=$liggghts@$plane"
python3 "$here/paired_angles.py" "$work" "$ids" mesh plane
