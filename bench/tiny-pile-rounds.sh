#!/usr/bin/env bash
# LIGGGHTS builds alternated on the tiny pile (docs/explanation/benchmarks.md, "The tiny pile of these screens"),
# one run at a time under nice -n 5: per round, each build's CPU-s (user + system); every final state is compared
# with the first build's first one (the pile's input must end with a write_dump of the state in %.17g to
# ${dumpdir}/final.txt).
#
# Usage: bench/tiny-pile-rounds.sh DIR ROUNDS NAME=LIGGGHTS [NAME=LIGGGHTS ...]
#   DIR holds pile.in, pedestal.stl and g300/ (gen_pile.py 300 0.001 0.0035 0.002 0.0005 12345 2e-6 2500 g300);
#   each run writes DIR/rr-NAME-ROUND/. Environment: TSETTLE (default 0.2 s of settling).
set -euo pipefail
(($# >= 3)) || { sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
dir=$(realpath "$1") rounds=$2
shift 2
cd "$dir"
ref=
for r in $(seq 1 "$rounds"); do
  line="round $r load $(cut -d' ' -f1 /proc/loadavg):"
  for b in "$@"; do
    name=${b%%=*} exe=${b#*=} d=rr-${b%%=*}-$r
    rm -rf "$d" && mkdir -p "$d"
    /usr/bin/time -f "%U %S" -o "$d/cpu.txt" nice -n 5 "$exe" -in pile.in -var gdir g300 -var tsettle "${TSETTLE:-0.2}" \
      -var dumpdir "$d" -log "$d/log" -screen "$d/screen"
    line="$line $name $(awk '{printf "%.2f", $1 + $2}' "$d/cpu.txt")"
    [[ -n $ref ]] || ref=$d/final.txt
    cmp -s "$d/final.txt" "$ref" || line="$line (final state differs from $ref)"
  done
  echo "$line"
done
echo "load after: $(cat /proc/loadavg)"
