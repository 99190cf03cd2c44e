#!/bin/sh
# `demsa plan` over four studies of seven parameters, 50 truths, pinned to one core (docs/explanation/benchmarks.md, "Which
# experiments to run"; goal: <= 60 s). The studies are those of examples/calibration/ after `demsa run` of each.
# Usage: bench/plan-speed.sh DEMSA [RUNS] [STUDY ...]   (default studies: examples/calibration/{pile,pile-rough,
# incline,drawdown}). Prints the median wall and CPU (user + sys) seconds over RUNS runs and the load average.
set -eu
demsa=$1
runs=${2:-3}
shift $(($# < 2 ? $# : 2))
[ "$#" -gt 0 ] || set -- examples/calibration/pile examples/calibration/pile-rough examples/calibration/incline \
  examples/calibration/drawdown
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
echo "load before: $(cat /proc/loadavg)"
i=0
while [ "$i" -lt "$runs" ]; do
  /usr/bin/time -f "%e %U %S" -o "$dir/t" taskset -c 0 "$demsa" plan "$@" --truths 50 --no-plots --out "$dir/plan" \
    >"$dir/out" 2>"$dir/err" || { echo "exit $?: $(tail -n 1 "$dir/err")"; exit 1; }
  tail -n 1 "$dir/t" | awk '{printf "%s %.2f\n", $1, $2 + $3}' >>"$dir/times"
  i=$((i + 1))
done
echo "load after: $(cat /proc/loadavg)"
echo "studies: $*"
echo "median wall $(cut -d' ' -f1 "$dir/times" | median) s, CPU $(cut -d' ' -f2 "$dir/times" | median) s over $runs runs"
sed -n '/^expected/,/^  (outside/p' "$dir/out"
