#!/bin/bash
# CPU time per atom-step of a tiny pile (300 particles of set 1, E = 1e8 Pa, nu = 0.3, mu_PP = 1.3, mu_PW = 1.15,
# e_r = 0.4, 0.3 s of settling) under three rolling models, side by side: `cdt` (mu_r = 0.275), `viscous` with its
# compiled kernel and `viscous` through LIGGGHTS's generic path (mu_R,PP = 2.475e-6, mu_R,PW = 2.9e-6 s*m, the middle
# of Table 3). The three runs are interleaved, REPS rounds; prints every run and the medians with their ratios to cdt.
# One LIGGGHTS rank, runs one after another. cdt and compiled viscous run on the build of scripts/build-liggghts.sh,
# generic viscous on that of scripts/build-liggghts.sh --generic-viscous (same sources, the viscous kernel left out).
#
# Usage: bench/rolling-models.sh [DEMSA] [REPS]       (default: build/orchestrator/demsa, 3)
set -euo pipefail
demsa=$(realpath "${1:-build/orchestrator/demsa}")
reps=${2:-3}
repo=$(cd "$(dirname "$0")/.." && pwd)
prefix=$("$repo/scripts/build-liggghts.sh" --print-prefix)
compiled=$prefix/bin/liggghts
generic=$prefix-generic/bin/liggghts
[ -x "$compiled" ] || { echo "bench: $compiled missing: run scripts/build-liggghts.sh" >&2; exit 1; }
if [ ! -x "$generic" ]; then
  echo "# $generic missing (scripts/build-liggghts.sh --generic-viscous): the generic column is left out"
  generic=""
fi
work=$(mktemp -d -t rolling-models.XXXXXX)
echo "# work dir $work; load average $(cat /proc/loadavg)"
for model in cdt viscous; do
  if [ $model = cdt ]; then rolling='mu_r_pp = 0.275
mu_r_pw = 0.275'; contact=""; else rolling='mu_r_pp = 2.475e-6
mu_r_pw = 2.9e-6'; contact='[contact]
rolling_model = "viscous"'; fi
  cat >"$work/$model.toml" <<TOML
[study]
name = "rolling-models"
experiment = "pile"
seed = 20240501
[design]
method = "lhs"
samples = 2
[parameters]
E = { low = 1e8, high = 1e9, scale = "log" }
$contact
[material]
nu = 0.3
mu_pp = 1.3
mu_pw = 1.15
e_r = 0.4
$rolling
[pile]
preset = "set1"
particles = 300
fill_height = 0.06
settle_time = 0.3
[run]
ranks = 1
liggghts = "$compiled"
TOML
  "$demsa" case "$work/$model.toml" --set E=1e8 -o "$work/$model" >/dev/null
done

# One run: CPU seconds (user + system) over atom-steps (sum of steps x atoms over the `run`s of the log).
run() { # name exe dir
  local name=$1 exe=$2 dir=$3
  rm -f "$dir/log.liggghts" "$dir"/*.dump
  (cd "$dir" && /usr/bin/time -f "%U %S" -o time.txt "$exe" -in in.liggghts -log log.liggghts -screen screen.txt)
  local cpu asteps
  cpu=$(awk '{print $1 + $2}' "$dir/time.txt")
  asteps=$(awk '/^Loop time of/ {a += $9 * $12} END {printf "%.0f", a}' "$dir/log.liggghts")
  awk -v n="$name" -v c="$cpu" -v a="$asteps" 'BEGIN {printf "%-17s %8.2f %12d %9.4f\n", n, c, a, 1e6 * c / a}'
}
printf "%-17s %8s %12s %9s\n" run cpu_s atom_steps us_per_atom_step
results=$work/results.txt
for ((i = 1; i <= reps; i++)); do
  run cdt "$compiled" "$work/cdt" | tee -a "$results"
  run viscous-compiled "$compiled" "$work/viscous" | tee -a "$results"
  [ -z "$generic" ] || run viscous-generic "$generic" "$work/viscous" | tee -a "$results"
done
echo "# medians (us per atom-step) and ratios to cdt; load average $(cat /proc/loadavg)"
python3 - "$results" <<'PY'
import statistics, sys
rows = [line.split() for line in open(sys.argv[1])]
names = [n for n in ("cdt", "viscous-compiled", "viscous-generic") if any(r[0] == n for r in rows)]
med = {n: statistics.median(float(r[3]) for r in rows if r[0] == n) for n in names}
for n, m in med.items():
    print(f"{n:17s} {m:9.4f}  x{m / med['cdt']:.3f}")
PY
