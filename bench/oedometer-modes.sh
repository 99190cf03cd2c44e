#!/bin/bash
# One small oedometer sample in both plate modes (servo and the paper's trial-step loop): integration steps of the
# loading phase, wall time of the whole case, and the settlements s_i = z_0 - z_i of each mode and their difference.
# Prints a Markdown table (docs/explanation/benchmarks.md, "Oedometer plate modes").
#
# usage: bench/oedometer-modes.sh [DEMSA] [PARTICLES] [LOADS] [FILL_TIME]
#   DEMSA      demsa executable (default: demsa on PATH)
#   PARTICLES  particles in the box (default 600)
#   LOADS      TOML array of loads in N (default "[100.0, 400.0, 1100.0]")
#   FILL_TIME  pouring and settling before the first load in s (default 0.3)
set -euo pipefail
demsa=${1:-demsa}
particles=${2:-600}
loads=${3:-"[100.0, 400.0, 1100.0]"}
fill_time=${4:-0.3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

write_study() {  # mode file
  cat > "$2" <<TOML
[study]
name = "bench-oedometer-$1"
experiment = "oedometer"
seed = 5
[parameters]
E = { low = 1e8, high = 1e9, scale = "log" }
[material]
mu_r_pp = 0.005
mu_r_pw = 0.005
[oedometer]
particles = $particles
r_min = 2.5e-3
r_max = 3.5e-3
r_mean = 3.0e-3
r_sd = 0.25e-3
fill_time = $fill_time
loads = $loads
plate_mode = "$1"
load_tolerance = 1.0
servo_check_steps = 2000
servo_max_steps = 200000
trial_steps = 2000
relax_steps = 8000
trial_step0 = 0.05e-3
trial_reduction = 0.7
trial_floor = 0.02
max_trials = 400
TOML
}

declare -A wall steps zs
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
for mode in servo trial-step; do
  write_study "$mode" "$work/$mode.toml"
  "$demsa" case "$work/$mode.toml" --set E=2e8 -o "$work/$mode" > /dev/null
  start=$(date +%s.%N)
  status=0
  "$work/$mode/run.sh" > /dev/null 2>&1 || status=$?
  end=$(date +%s.%N)
  if [ "$status" -ne 0 ]; then echo "$mode: run.sh exited $status (see $work/$mode/screen.txt)" >&2; fi
  wall[$mode]=$(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.1f", b-a}')
  steps[$mode]=$(awk '!/^#/ && NF {s=$1} END{print s}' "$work/$mode/plate_history.txt")
  zs[$mode]=$(awk '!/^#/ && NF {printf "%s:%s:%s:%s ", $1, $2, $3, $4}' "$work/$mode/plate_states.txt")
done

echo "| mode | loading steps | wall time of the case [s] | load [N]: settlement s_i [mm] (force [N], converged) |"
echo "|---|---|---|---|"
for mode in servo trial-step; do
  row=$(echo "${zs[$mode]}" | awk '{ for (i = 1; i <= NF; ++i) { split($i, a, ":"); if (i == 1) z0 = a[2];
        printf "%s: %.4f (%.2f, %s); ", a[1], (z0 - a[2]) * 1000, a[3], a[4] } }')
  echo "| $mode | ${steps[$mode]} | ${wall[$mode]} | $row |"
done
echo
echo "Settlement difference trial-step − servo [mm]: $(paste <(echo "${zs[servo]}" | tr ' ' '\n') \
  <(echo "${zs[trial-step]}" | tr ' ' '\n') | awk -F'[:\t]' 'NF >= 8 { if (NR == 1) { zs0 = $2; zt0 = $6 }
  printf "%s N: %+.4f; ", $1, ((zt0 - $6) - (zs0 - $2)) * 1000 }')"
echo "($particles particles, E = 2e8 Pa, fill $fill_time s, 1 rank; load average before/after: $load_before / $(cut -d' ' -f1-3 /proc/loadavg))"
