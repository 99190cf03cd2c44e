#!/usr/bin/env bash
# Two LIGGGHTS builds on the same case folders (written by `demsa case`), started together, each pinned to one of
# the two cores, the cores swapped from one round to the next: on a machine whose cores do not run at one speed, the
# geometric mean of a case's ratios over an even number of rounds cancels a constant bias of the cores
# (docs/explanation/benchmarks.md, "Profile-guided and link-time optimisation"). Prints one line per run: round,
# case, the core of A, A's and B's CPU-s (user + system), A / B, whether the file COMPARED is byte-identical, the load.
#
# Usage: bench/pinned-pairs.sh ROUNDS A_LIGGGHTS B_LIGGGHTS CASE_DIR...
#   COMPARED=FILE  the output compared (default pile_final.dump; drum_snapshots.dump for a drum)
#   WORK=DIR       where the runs go (default a new folder in /tmp)
set -euo pipefail
(($# >= 4)) || { sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
rounds=$1 a=$(realpath "$2") b=$(realpath "$3")
shift 3
compared=${COMPARED:-pile_final.dump}
work=${WORK:-$(mktemp -d /tmp/pinned-pairs.XXXXXX)}
mkdir -p "$work"
echo "# start $(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg); A $a; B $b; runs in $work"
echo "# round case core_of_A cpu_A cpu_B A/B $compared load"
for ((r = 1; r <= rounds; r++)); do
  for c in "$@"; do
    name=$(basename "$c")
    for k in A B; do rm -rf "$work/$name-$k" && cp -r "$c" "$work/$name-$k"; done
    core_a=$(((r + 1) % 2)) core_b=$((r % 2))
    (cd "$work/$name-A" && /usr/bin/time -f "%U %S" -o cpu.txt taskset -c "$core_a" "$a" -in in.liggghts \
      -log log.liggghts -screen screen.txt >/dev/null 2>&1) &
    (cd "$work/$name-B" && /usr/bin/time -f "%U %S" -o cpu.txt taskset -c "$core_b" "$b" -in in.liggghts \
      -log log.liggghts -screen screen.txt >/dev/null 2>&1) &
    wait
    ca=$(awk '{print $1 + $2}' "$work/$name-A/cpu.txt") cb=$(awk '{print $1 + $2}' "$work/$name-B/cpu.txt")
    same=$(cmp -s "$work/$name-A/$compared" "$work/$name-B/$compared" && echo same || echo DIFFERENT)
    echo "$r $name $core_a $ca $cb $(awk -v x="$ca" -v y="$cb" 'BEGIN {printf "%.3f", x / y}') $same" \
      "$(cut -d' ' -f1 /proc/loadavg)"
  done
done
echo "# end $(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg)"
