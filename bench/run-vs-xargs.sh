#!/bin/bash
# Wall time of a study of N short real LIGGGHTS cases run by `demsa run` against the same run.sh files run by
# `xargs -P K` (K cases at once, as demsa's local executor). Prints both times and the ratio demsa / xargs.
#
#   bench/run-vs-xargs.sh [N=32] [K=cores] [build dir=build]
#
# Both sides run the same case folders (demsa --dry-run writes them; xargs runs copies), with 1 MPI rank each.
# demsa's time includes what it does beyond xargs: writing each case before its run, classifying, measuring the
# angle of repose, writing result.json and committing to the store. The analysis is left out (--no-analyze).
set -euo pipefail
N=${1:-32}
K=${2:-$(nproc)}
BUILD=${3:-build}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DEMSA=${DEMSA:-$ROOT/$BUILD/orchestrator/demsa}
[ -x "$DEMSA" ] || { echo "demsa not found at $DEMSA (build it, or set DEMSA)" >&2; exit 2; }
WORK=$(mktemp -d "${TMPDIR:-/tmp}/demsa-bench-XXXXXX")
trap 'rm -rf "$WORK"' EXIT

cat > "$WORK/study.toml" <<TOML
[study]
name = "bench-run-vs-xargs"
experiment = "pile"
seed = 11

[design]
method = "lhs"
samples = $N

[parameters]
mu_pp = { low = 0.3, high = 0.9 }
mu_r_pp = { low = 0.05, high = 0.3 }

[material]
E = 1e8

[pile]
particles = 120
settle_time = 0.1

[run]
ranks = 1
parallel = $K
retries = 0

[analysis]
metamodels = ["rbf-cubic"]
TOML

"$DEMSA" run "$WORK/study.toml" --dir "$WORK/xargs" --dry-run > /dev/null
"$DEMSA" run "$WORK/study.toml" --dir "$WORK/demsa" --dry-run > /dev/null

start=$(date +%s.%N)
find "$WORK/xargs/cases" -name run.sh | sort | xargs -P "$K" -I{} sh -c '{} > /dev/null 2>&1 || true'
xargs_s=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')

start=$(date +%s.%N)
"$DEMSA" run "$WORK/study.toml" --dir "$WORK/demsa" --no-analyze --quiet > "$WORK/demsa.out" || true
demsa_s=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')

done_count=$("$DEMSA" status "$WORK/demsa" --json | sed -n 's/.*"done": \([0-9]*\).*/\1/p')
printf 'cases %d, K %d, load before: %s\n' "$N" "$K" "$(cut -d' ' -f1-3 /proc/loadavg)"
printf 'xargs -P %d: %.1f s\n' "$K" "$xargs_s"
printf 'demsa run:  %.1f s (%s of %d done)\n' "$demsa_s" "$done_count" "$N"
printf 'ratio demsa/xargs: %.3f\n' "$(awk -v a="$demsa_s" -v b="$xargs_s" 'BEGIN { print a / b }')"
