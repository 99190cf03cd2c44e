#!/usr/bin/env bash
# Two LIGGGHTS builds on the same case folders (written by `demsa case`), started together, each pinned to one of
# the two cores, the cores swapped from one round to the next: on a machine whose cores do not run at one speed, the
# geometric mean of a case's ratios over an even number of rounds cancels a constant bias of the cores
# (docs/explanation/benchmarks.md, "Profile-guided and link-time optimisation"). Prints one line per run: round,
# case, the core of A, A's and B's CPU-s (user + system), A / B, whether the file COMPARED is byte-identical, the load;
# then each case's geometric mean of A / B over its rounds, their median, and the cases' mean CPU-s summed (A over B:
# what a study of these cases costs with A against B).
#
# Usage: bench/pinned-pairs.sh ROUNDS A_LIGGGHTS B_LIGGGHTS CASE_DIR...
#   COMPARED=FILE  the output compared (default pile_final.dump; drum_snapshots.dump for a drum)
#   WORK=DIR       where the runs go (default a new folder in /tmp)
set -euo pipefail
(($# >= 4)) || { sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
rounds=$1 a=$(realpath "$2") b=$(realpath "$3")
shift 3
compared=${COMPARED:-pile_final.dump}
work=${WORK:-$(mktemp -d /tmp/pinned-pairs.XXXXXX)}
mkdir -p "$work"
: >"$work/pairs.txt"
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
      "$(cut -d' ' -f1 /proc/loadavg)" | tee -a "$work/pairs.txt"
  done
done
echo "# end $(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg)"
# The summary: a case's rounds by their geometric mean (it cancels a constant bias of the cores over an even number
# of rounds), the cases by their median, and a study's cost by each case's mean CPU-s summed.
awk '
  { n[$2]++; lr[$2] += log($6); a[$2] += $4; b[$2] += $5; if (!($2 in seen)) { seen[$2] = 1; order[++k] = $2 } }
  END {
    if (k == 0) exit
    for (i = 1; i <= k; i++) {
      c = order[i]; g[i] = exp(lr[c] / n[c]); ta += a[c] / n[c]; tb += b[c] / n[c]
      printf "# case %s: %d rounds, geometric mean A/B %.3f\n", c, n[c], g[i]
    }
    for (i = 1; i <= k; i++) for (j = i + 1; j <= k; j++) if (g[j] < g[i]) { t = g[i]; g[i] = g[j]; g[j] = t }
    median = k % 2 ? g[(k + 1) / 2] : (g[k / 2] + g[k / 2 + 1]) / 2
    printf "# %d case%s: median A/B %.3f; mean CPU-s summed: A %.1f, B %.1f, A/B %.3f\n", k, k == 1 ? "" : "s",
      median, ta, tb, ta / tb
  }' "$work/pairs.txt"
