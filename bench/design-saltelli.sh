#!/bin/sh
# `demsa design saltelli` at N = 2^17, d = 7 (CSV included), two binaries side by side (docs/explanation/benchmarks.md, section
# "Reproducible designs"). Usage: bench/design-saltelli.sh NEW_DEMSA [OLD_DEMSA] [RUNS] [BASE]
# Prints, per binary, the median wall and CPU (user + sys) seconds over RUNS alternating runs and the load average.
set -eu
new=$1
old=${2:-}
runs=${3:-5}
base=${4:-131072}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
time_one() { # binary tag
  status=0
  # One design (no replicate column), the file the recorded times were measured on.
  /usr/bin/time -f "%e %U %S" -o "$dir/t" "$1" design saltelli -N "$base" --dim 7 --seed 3 --replicates 1 \
    -o "$dir/$2.csv" >/dev/null 2>"$dir/$2.err" || status=$?
  [ "$status" -eq 0 ] || echo "$2: exit $status: $(tail -n 1 "$dir/$2.err")"
  tail -n 1 "$dir/t" | awk '{printf "%s %.2f\n", $1, $2 + $3}' >>"$dir/$2.times"
}
echo "load before: $(cat /proc/loadavg)"
i=0
while [ "$i" -lt "$runs" ]; do
  time_one "$new" new
  [ -n "$old" ] && time_one "$old" old
  i=$((i + 1))
done
echo "load after: $(cat /proc/loadavg)"
for tag in new old; do
  [ -f "$dir/$tag.times" ] || continue
  wall=$(cut -d' ' -f1 "$dir/$tag.times" | median)
  cpu=$(cut -d' ' -f2 "$dir/$tag.times" | median)
  echo "$tag: median wall $wall s, median cpu $cpu s over $(wc -l <"$dir/$tag.times") runs, $(wc -c <"$dir/$tag.csv") bytes"
done
