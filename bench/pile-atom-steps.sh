#!/bin/bash
# Atom-steps per pile observable: the paper's schedule (§3.2: discs of 20 mm appended at 100 mm one every
# sqrt(4 r_U/|g|), settle a fixed 600 ms, nothing removed) against demsa's settling criterion with removal of the
# particles that fall off the pedestal ([pile] settle_speed, settle_quantile, settle_window, remove_fallen), with the
# paper's pour ("criterion") and with a central stream (discs of 32 mm appended at the stream's fill height, the
# discs below it present at the start: "stream"). The paper's pedestal (r_cy = 50 mm), particle set 1, the
# one-at-a-time baseline of issue 15 (E = 1e8 Pa, nu = 0.3, mu_PP = 1.3, mu_PW = 1.15, e_r = 0.4,
# mu_R,PP = mu_R,PW = 0.275, cdt), one LIGGGHTS rank per run. Each schedule runs once per packing seed (the study
# seed draws the radii and the positions), so that the angles' run-to-run noise is measured beside the difference
# between schedules; the same seeds on both sides also give paired differences.
#
# Usage: bench/pile-atom-steps.sh [DEMSA] [--seeds "S1 S2 ..."] [--jobs J] [--schedules "paper criterion stream"]
#                                 [--settle-speed S] [--settle-quantile Q] [--settle-window W]
#                                 [--stream-fill-height H | "N1=H1 N2=H2 ..."] [--stream-disc-radius R]
#                                 [PARTICLE COUNTS...]
#   defaults: build/orchestrator/demsa, seeds "20240501 7 11", 1 job, all three schedules, the quickstart's
#   criterion (settle_speed 0.02, settle_quantile 0.95, settle_window 0.05 s) for the criterion and the stream, the
#   stream's fill_height 0.06 m (one value for every count, or one per count) and disc_radius 0.032 m (the
#   quickstart's), counts 1200 2400.
#   Atom-steps do not depend on the load, so --jobs 2 may run two cases at once; CPU seconds then do.
# Prints one row per run: particles, schedule, seed, steps, atom-steps (sum over the LIGGGHTS `run`s of steps x
# atoms at the end of each, from the log), loop CPU seconds, angle (§3.3), the robust estimator's angle, pile height,
# settled, removed; then per particle count and schedule the mean atom-steps and their ratio to the paper's, the
# mean angle (both estimators), the sample standard deviation of single runs, the difference to the paper's mean
# angle with its standard error, and the mean paired difference (same seed) with its standard error.
set -euo pipefail
demsa=build/orchestrator/demsa
seeds=(20240501 7 11)
jobs=1
schedules=(paper criterion stream)
settle_speed=0.02
settle_quantile=0.95
settle_window=0.05
stream_fill_height=0.06
stream_disc_radius=0.032
counts=()
while [ $# -gt 0 ]; do
  case $1 in
    --seeds) read -r -a seeds <<< "$2"; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --schedules) read -r -a schedules <<< "$2"; shift 2 ;;
    --settle-speed) settle_speed=$2; shift 2 ;;
    --settle-quantile) settle_quantile=$2; shift 2 ;;
    --settle-window) settle_window=$2; shift 2 ;;
    --stream-fill-height) stream_fill_height=$2; shift 2 ;;
    --stream-disc-radius) stream_disc_radius=$2; shift 2 ;;
    -h|--help) sed -n '2,25p' "$0"; exit 0 ;;
    -*) echo "pile-atom-steps: unknown option '$1'" >&2; exit 2 ;;
    *) if [[ $1 =~ ^[0-9]+$ ]]; then counts+=("$1"); else demsa=$1; fi; shift ;;
  esac
done
[ ${#counts[@]} -eq 0 ] && counts=(1200 2400)
[[ $jobs =~ ^[1-9][0-9]*$ ]] || { echo "pile-atom-steps: --jobs: expected a positive integer, got '$jobs'" >&2; exit 2; }
for s in "${schedules[@]}"; do
  case $s in paper|criterion|stream) ;; *) echo "pile-atom-steps: unknown schedule '$s' (paper, criterion, stream)" >&2; exit 2 ;; esac
done
# The stream's fill height for N particles: the one value, or the N=H entry for N.
fill_height_for() {
  local n=$1 entry
  if [[ $stream_fill_height != *=* ]]; then echo "$stream_fill_height"; return; fi
  for entry in $stream_fill_height; do
    if [ "${entry%%=*}" = "$n" ]; then echo "${entry#*=}"; return; fi
  done
  echo "pile-atom-steps: --stream-fill-height '$stream_fill_height' has no entry for $n particles" >&2
  return 1
}

for n in "${counts[@]}"; do
  h=$(fill_height_for "$n") || exit 2
  [[ $h =~ ^[0-9]*\.?[0-9]+$ ]] || { echo "pile-atom-steps: --stream-fill-height: '$h' for $n particles is not a height in m" >&2; exit 2; }
done
demsa=$(realpath "$demsa")
work=$(mktemp -d -t pile-atom-steps.XXXXXX)
echo "# settle_speed $settle_speed, settle_quantile $settle_quantile, settle_window $settle_window (criterion, stream), stream fill_height $stream_fill_height, disc_radius $stream_disc_radius; work dir $work; load average $(cat /proc/loadavg); $(date -u '+%Y-%m-%d %H:%M UTC')"

schedule_keys() {
  local n=$2
  case $1 in
    paper) printf 'settle_speed = 0\nremove_fallen = false\n' ;;
    criterion) printf 'settle_speed = %s\nsettle_quantile = %s\nsettle_window = %s\nsettle_check_time = 0.01\nremove_fallen = true\n' \
      "$settle_speed" "$settle_quantile" "$settle_window" ;;
    stream) printf 'disc_radius = %s\nfill_height = %s\nsettle_speed = %s\nsettle_quantile = %s\nsettle_window = %s\nsettle_check_time = 0.01\nremove_fallen = true\n' \
      "$stream_disc_radius" "$(fill_height_for "$n")" "$settle_speed" "$settle_quantile" "$settle_window" ;;
  esac
}

# One run: writes its row to $work/rows/<n>-<schedule>-<seed>.
run_one() {
  local n=$1 schedule=$2 seed=$3
  local name=$schedule-$n-$seed
  cat > "$work/$name.toml" <<TOML
[study]
name = "pile-atom-steps"
experiment = "pile"
seed = $seed
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
$(schedule_keys "$schedule" "$n")
[run]
ranks = 1
TOML
  local dir=$work/$name
  "$demsa" case "$work/$name.toml" --set E=1e8 -o "$dir" > /dev/null
  "$dir/run.sh" > "$dir/run.out" 2>&1 || { echo "pile-atom-steps: $name failed (see $dir)" >&2; return 1; }
  local steps asteps cpu angle robust settled removed
  read -r steps asteps cpu < <(awk '/^Loop time of/ {c += $4; s += $9; a += $9 * $12} END {printf "%d %.0f %.1f\n", s, a, c}' "$dir/log.liggghts")
  angle=$("$demsa" postprocess pile "$dir" --estimator paper --json | python3 -c 'import json,sys; j=json.load(sys.stdin); print("%.2f %.1f" % (j["angle_deg"], 1e3*j["pile_height_m"]))')
  robust=$("$demsa" postprocess pile "$dir" --estimator robust --json | python3 -c 'import json,sys; print("%.2f" % json.load(sys.stdin)["angle_deg"])')
  settled=$(awk '$1 == "settled" {print $2}' "$dir/pile_settling.txt")
  removed=$(awk '$1 == "removed" {print $2}' "$dir/pile_settling.txt")
  read -r angle h_p <<< "$angle"
  printf "%-9s %-10s %9s %9s %12s %8s %7s %7s %7s %8s %8s\n" "$n" "$schedule" "$seed" "$steps" "$asteps" "$cpu" "$angle" \
    "$robust" "$h_p" "$settled" "$removed" | tee "$work/rows/$n-$schedule-$seed"
}

mkdir -p "$work/rows"
printf "%-9s %-10s %9s %9s %12s %8s %7s %7s %7s %8s %8s\n" particles schedule seed steps atom_steps cpu_s angle robust \
  h_P_mm settled removed
running=0
for n in "${counts[@]}"; do
  for schedule in "${schedules[@]}"; do
    for seed in "${seeds[@]}"; do
      run_one "$n" "$schedule" "$seed" &
      running=$((running + 1))
      if [ $running -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
    done
  done
done
wait
expected=$(( ${#counts[@]} * ${#schedules[@]} * ${#seeds[@]} ))
got=$(find "$work/rows" -type f | wc -l)
if [ "$got" -eq 0 ]; then echo "pile-atom-steps: no run finished (see $work)" >&2; exit 1; fi

echo "# summary: mean over seeds; ratio = mean atom-steps / the paper's; per angle estimator (paper §3.3, robust): sd ="
echo "# sample standard deviation of one run's angle; diff = mean angle - the paper schedule's mean angle, se = its"
echo "# standard error (sqrt(sd^2/k + sd_paper^2/k_paper)); paired = mean over seeds run by both of the difference of"
echo "# the same seed's angles, pse = its standard error (sd of the differences / sqrt(k))"
cat "$work"/rows/* | python3 -c '
import collections, math, sys
rows = collections.defaultdict(dict)
for line in sys.stdin:
    f = line.split()
    rows[(int(f[0]), f[1])][f[2]] = (float(f[4]), float(f[6]), float(f[7]))
def stats(v):
    m = sum(v) / len(v)
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else float("nan")
    return m, sd
print("%-9s %-10s %5s %12s %7s %-9s %8s %6s %7s %6s %7s %6s" % ("particles", "schedule", "runs", "atom_steps", "ratio",
      "estimator", "angle", "sd", "diff", "se", "paired", "pse"))
for n in sorted({k[0] for k in rows}):
    paper = rows.get((n, "paper"))
    pa = stats([r[0] for r in paper.values()]) if paper else None
    for s in ("paper", "criterion", "stream"):
        if (n, s) not in rows: continue
        v = rows[(n, s)]
        a, _ = stats([r[0] for r in v.values()])
        ratio = "%.3f" % (a / pa[0]) if pa else "-"
        for e, name in ((1, "paper"), (2, "robust")):
            m, sd = stats([r[e] for r in v.values()])
            diff = ses = paired = pses = "-"
            if paper and s != "paper":
                pm, psd = stats([r[e] for r in paper.values()])
                diff, ses = "%+.2f" % (m - pm), "%.2f" % math.sqrt(sd ** 2 / len(v) + psd ** 2 / len(paper))
                d = [v[k][e] - paper[k][e] for k in v if k in paper]
                if d:
                    dm, dsd = stats(d)
                    paired, pses = "%+.2f" % dm, "%.2f" % (dsd / math.sqrt(len(d)))
            print("%-9d %-10s %5d %12.3g %7s %-9s %8.2f %6.2f %7s %6s %7s %6s" % (n, s, len(v), a, ratio, name, m, sd, diff,
                  ses, paired, pses))
'
echo "# load average at the end $(cat /proc/loadavg)"
if [ "$got" -ne "$expected" ]; then echo "pile-atom-steps: $((expected - got)) of $expected runs failed (see $work)" >&2; exit 1; fi
