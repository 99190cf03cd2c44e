#!/bin/bash
# Atom-steps per pile observable: the paper's schedule (§3.2: settle a fixed 600 ms, nothing removed) against the
# settling criterion with removal of the particles that fall off the pedestal ([pile] settle_speed, remove_fallen),
# at the paper's pedestal (r_cy = 50 mm), particle set 1, one-at-a-time baseline of issue 15 (E = 1e8 Pa, nu = 0.3,
# mu_PP = 1.3, mu_PW = 1.15, e_r = 0.4, mu_R,PP = mu_R,PW = 0.275, cdt). One LIGGGHTS rank per run, runs one after
# another.
#
# Usage: bench/pile-atom-steps.sh [DEMSA] [PARTICLE COUNTS...]     (default: build/orchestrator/demsa, 1200 2400)
# Prints one row per run: particles, schedule, steps, atom-steps (sum over runs of steps x atoms at the end of each
# `run`, from the LIGGGHTS log), loop CPU seconds, angle, pile height, settled, removed, and the ratio of the
# criterion's atom-steps to the paper's.
set -euo pipefail
demsa=${1:-build/orchestrator/demsa}
shift || true
counts=("$@")
[ ${#counts[@]} -eq 0 ] && counts=(1200 2400)
demsa=$(realpath "$demsa")
work=$(mktemp -d -t pile-atom-steps.XXXXXX)
echo "# work dir $work; load average $(cat /proc/loadavg)"
printf "%-9s %-10s %9s %12s %8s %7s %7s %8s %8s\n" particles schedule steps atom_steps cpu_s angle h_P_mm settled removed
for n in "${counts[@]}"; do
  declare -A atomsteps=()
  for schedule in paper criterion; do
    if [ "$schedule" = paper ]; then extra="settle_speed = 0
remove_fallen = false"; else extra="settle_speed = 0.02
remove_fallen = true"; fi
    cat > "$work/$schedule-$n.toml" <<TOML
[study]
name = "pile-atom-steps"
experiment = "pile"
seed = 20240501
[design]
method = "lhs"
samples = 2
[parameters]
E = { low = 1e8, high = 1e9, scale = "log" }
[material]
nu = 0.3
mu_pp = 1.3
mu_pw = 1.15
e_r = 0.4
mu_r_pp = 0.275
mu_r_pw = 0.275
[pile]
preset = "set1"
particles = $n
settle_time = 0.6
$extra
[run]
ranks = 1
TOML
    dir="$work/$schedule-$n"
    "$demsa" case "$work/$schedule-$n.toml" --set E=1e8 -o "$dir" > /dev/null
    "$dir/run.sh"
    read -r steps asteps cpu < <(awk '/^Loop time of/ {c += $4; s += $9; a += $9 * $12} END {printf "%d %.0f %.1f\n", s, a, c}' "$dir/log.liggghts")
    angle=$("$demsa" postprocess pile "$dir" --pedestal-radius 0.05 --json | python3 -c 'import json,sys; j=json.load(sys.stdin); print("%.2f %.1f" % (j["angle_deg"], 1e3*j["pile_height_m"]))')
    settled=$(awk '$1 == "settled" {print $2}' "$dir/pile_settling.txt")
    removed=$(awk '$1 == "removed" {print $2}' "$dir/pile_settling.txt")
    atomsteps[$schedule]=$asteps
    printf "%-9s %-10s %9s %12s %8s %7s %7s %8s %8s\n" "$n" "$schedule" "$steps" "$asteps" "$cpu" $angle "$settled" "$removed"
  done
  echo "# $n particles: criterion / paper atom-steps = $(python3 -c "print('%.3f' % (${atomsteps[criterion]} / ${atomsteps[paper]}))")"
done
echo "# load average at the end $(cat /proc/loadavg)"
