#!/usr/bin/env bash
# Two LIGGGHTS builds on one case folder (written by `demsa case`), started together, one rank each, each under
# `perf record -F 199 -g`, so that both see the same load: prints their CPU-s (user + system, perf included) and
# atom-steps, and writes OUT/A/perf.data and OUT/B/perf.data for `perf report --no-children --sort symbol -n`
# (docs/explanation/benchmarks.md, "The mesh wall's exact shortcuts").
#
# Usage: bench/paired-builds.sh CASE_DIR OUT A_LIGGGHTS B_LIGGGHTS
set -euo pipefail
(($# == 4)) || { sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
case_dir=$(realpath "$1") out=$2
mkdir -p "$out"
echo "start $(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg)"
exes=("$3" "$4")
for k in 0 1; do
  d=$out/$([[ $k == 0 ]] && echo A || echo B)
  rm -rf "$d" && cp -r "$case_dir" "$d"
  (cd "$d" && /usr/bin/time -f "%U %S" -o cpu.txt nice -n 5 perf record -q -F 199 -g -o perf.data "${exes[$k]}" \
    -in in.liggghts -log log.liggghts -screen screen.txt >/dev/null 2>&1) &
done
wait
for k in A B; do
  steps=$(awk '/^Loop time of .* procs for [0-9]+ steps with [0-9]+ atoms/ {s += $9 * $12} END {printf "%.0f\n", s}' \
    "$out/$k/log.liggghts")
  echo "$k cpu $(awk '{print $1 + $2}' "$out/$k/cpu.txt") atom-steps $steps"
done
echo "end $(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg)"
