#!/usr/bin/env bash
# scripts/docs-pictures.sh [--studies DEMSA WORKDIR]: redraws the pictures of docs/images/.
#   (no option)  pipeline.png from pipeline.dot (graphviz `dot`; Debian: apt-get install graphviz).
#   --studies    also the pictures demsa draws itself, from the two tiny studies beside them (real LIGGGHTS runs,
#                about 3.5 min on two cores): pile-flanks.png (`demsa report`, report/pile_side.png) and
#                plan-widths.png (`demsa plan`, plan/plan_widths.png), scaled down by ImageMagick's `convert`.
# report.png (the quickstart's report) is a screenshot: docs/tutorials/quickstart.md says how it was made.
set -euo pipefail
cd "$(dirname "$0")/.."
images=docs/images
command -v dot >/dev/null || { echo "docs-pictures.sh: graphviz's dot is not installed" >&2; exit 2; }
dot -Tpng -Gdpi=96 "$images/pipeline.dot" -o "$images/pipeline.png"
echo "$images/pipeline.png"

(($# == 0)) && exit 0
[[ $# == 3 && $1 == --studies ]] || { echo "usage: scripts/docs-pictures.sh [--studies DEMSA WORKDIR]" >&2; exit 2; }
demsa=$2 work=$3
command -v convert >/dev/null || { echo "docs-pictures.sh: ImageMagick's convert is not installed" >&2; exit 2; }
mkdir -p "$work"
"$demsa" run "$images/pile-tiny.toml" --dir "$work/pile-tiny" --quiet
"$demsa" run "$images/incline-tiny.toml" --dir "$work/incline-tiny" --quiet
"$demsa" report "$work/pile-tiny" >/dev/null
# The plan's own check may fail (exit 1: truths whose posterior did not converge); its figure is drawn all the same.
"$demsa" plan "$work/pile-tiny" "$work/incline-tiny" --sd pile-tiny:angle=1 || (($? == 1))
convert "$work/pile-tiny/report/pile_side.png" -resize 640x -colors 128 "$images/pile-flanks.png"
convert "$work/pile-tiny/plan/plan_widths.png" -resize 760x -colors 64 "$images/plan-widths.png"
echo "$images/pile-flanks.png $images/plan-widths.png"
