#!/bin/bash
# The cost of three rolling models on the same work: `cdt` (mu_r = 0.275), `viscous` with its compiled kernel and
# `viscous` through LIGGGHTS's generic path (mu_R,PP = 2.475e-6, mu_R,PW = 2.9e-6 s*m, the middle of Table 3).
# cdt and compiled viscous run on the build of scripts/build-liggghts.sh, generic viscous on that of
# scripts/build-liggghts.sh --generic-viscous (the same sources with the viscous kernel left out).
#
# The tiny pile: 300 particles of set 1, E = 1e8 Pa, nu = 0.3, mu_PP = 1.3, mu_PW = 1.15, e_r = 0.4, written by
# `demsa case` for each model (so each model's pair and wall fixes are demsa's own).
#
# Default mode (same state): the tiny pile is poured once with cdt for its whole schedule (the column, the appended
# disc and 0.3 s of settling; 285 pair contacts, still moving at the end) and written as a LIGGGHTS restart. Each model
# then runs, in one LIGGGHTS process, SEGMENTS segments of STEPS steps, every segment from that restart (`clear`,
# read_restart: the same atoms, velocities and contact histories). Short segments keep the work the same: without
# static rolling torque the viscous heap flattens, and in one run of 20,000 steps it lost half of its contacts
# (285 -> 145) while cdt's kept them (285 -> 302). The runs are interleaved over REPS rounds (the order rotates each
# round), one LIGGGHTS rank each, one after another. Per run: the CPU time (user + system) of the LIGGGHTS process,
# less the median CPU time of a 0-step run of the same model and input (start-up: MPI, and per segment reading the
# restart and the mesh and the first neighbour list), over atom-steps; pair contacts (overlapping pairs, compute
# contact/atom) and neighbour-list pairs at the start and (mean over the segments) at the end of a segment, and the
# number of list builds, so that the work can be seen to be the same; and the md5 of the final state (ids,
# positions, velocities, angular velocities at full precision), equal across rounds when the runs are deterministic.
# Then, unless IR_STEPS = 0, one run of SEGMENTS x IR_STEPS steps per model under valgrind's callgrind, counting the
# instructions executed inside LAMMPS_NS::Verlet::run (the time-step loops only, start-up excluded); instruction
# counts do not depend on the load of the machine. (`perf stat -e instructions` is used instead when the machine
# exposes that counter; it counts the whole process, so the count of a 0-step run is subtracted.)
#
# --whole-pile: the earlier measurement, each model pouring and settling its own pile (80,723 steps each, 2.41e7
# atom-steps); the piles differ (the viscous model holds no static rolling torque), so it compares different work.
#
# Usage: bench/rolling-models.sh [--whole-pile] [DEMSA] [REPS]   (default: build/orchestrator/demsa, 3)
#   environment: SEGMENTS (default 40), STEPS per segment (default 500), IR_STEPS per segment under callgrind (default
#   STEPS; 0 = no instruction counts), PACK_STEPS (settling steps before the restart, default 71695: all of them),
#   KEEP=1 keeps the work dir
set -euo pipefail
mode=same-state
if [ "${1:-}" = --whole-pile ]; then
  mode=whole-pile
  shift
fi
demsa=$(realpath "${1:-build/orchestrator/demsa}")
reps=${2:-3}
steps=${STEPS:-500}
ir_steps=${IR_STEPS:-$steps}
pack_steps=${PACK_STEPS:-71695}
segments=${SEGMENTS:-40}
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
[ "${KEEP:-0}" = 1 ] || trap 'rm -rf "$work"' EXIT
echo "# $mode; work dir $work; load average $(cat /proc/loadavg)"
echo "# compiled: $compiled"
[ -z "$generic" ] || echo "# generic:  $generic"

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

# The runs: name, binary, case folder.
names=(cdt viscous-compiled)
exes=("$compiled" "$compiled")
dirs=(cdt viscous)
if [ -n "$generic" ]; then
  names+=(viscous-generic)
  exes+=("$generic")
  dirs+=(viscous)
fi

# Medians of column 3 (us per atom-step) by name, with ratios to cdt; rows "name ... value" in $1.
medians() {
  python3 - "$1" "$2" <<'PY'
import statistics, sys
rows = [line.split() for line in open(sys.argv[1]) if line.strip()]
col = int(sys.argv[2])
names = [n for n in ("cdt", "viscous-compiled", "viscous-generic") if any(r[0] == n for r in rows)]
med = {n: statistics.median(float(r[col]) for r in rows if r[0] == n) for n in names}
for n, m in med.items():
    runs = " ".join(r[col] for r in rows if r[0] == n)
    print(f"{n:17s} median {m:10.4f}  x{m / med['cdt']:.3f}   runs: {runs}")
PY
}

if [ $mode = whole-pile ]; then
  # One run: CPU seconds (user + system) over atom-steps (sum of steps x atoms over the `run`s of the log).
  run() { # name exe dir
    local name=$1 exe=$2 dir=$3
    rm -f "$dir/log.liggghts" "$dir"/*.dump
    (cd "$dir" && /usr/bin/time -f "%U %S" -o time.txt "$exe" -in in.liggghts -log log.liggghts -screen screen.txt)
    local cpu asteps
    cpu=$(awk '{print $1 + $2}' "$dir/time.txt")
    asteps=$(awk '/^Loop time of/ {a += $9 * $12} END {printf "%.0f", a}' "$dir/log.liggghts")
    awk -v n="$name" -v c="$cpu" -v a="$asteps" 'BEGIN {printf "%-17s %8.2f %9.4f %12d\n", n, c, 1e6 * c / a, a}'
  }
  printf "%-17s %8s %9s %12s\n" run cpu_s us_per_as atom_steps
  results=$work/results.txt
  for ((i = 1; i <= reps; i++)); do
    for k in "${!names[@]}"; do
      run "${names[$k]}" "${exes[$k]}" "$work/${dirs[$k]}" | tee -a "$results"
    done
  done
  echo "# medians (us per atom-step) and ratios to cdt; load average $(cat /proc/loadavg)"
  medians "$results" 2
  exit 0
fi

# ---- same state: pour the cdt pile once, write it as a restart.
cdt_in=$work/cdt/in.liggghts
discs_line=$(grep -n '^include *pile_discs.liggghts' "$cdt_in" | cut -d: -f1)
data_line=$(grep -n '^read_data' "$cdt_in" | cut -d: -f1)
if [ -z "$discs_line" ] || [ -z "$data_line" ]; then
  echo "bench: unexpected layout of $cdt_in" >&2
  exit 1
fi
{
  head -n "$discs_line" "$cdt_in"
  echo "run             ${pack_steps}"
  echo "write_restart   $work/packing.restart"
} >"$work/cdt/pack.liggghts"
(cd "$work/cdt" && /usr/bin/time -f "%U %S" -o pack-time.txt "$compiled" -in pack.liggghts -log pack.log \
  -screen /dev/null >/dev/null)
echo "# packing: cdt, $(awk '/^Loop time of/ {s += $9} END {print s}' "$work/cdt/pack.log") steps," \
  "$(awk '{print $1 + $2}' "$work/cdt/pack-time.txt") s CPU -> packing.restart"

# The same-state input of each model: its own system, contact and wall lines (its case's in.liggghts up to the
# pouring, read_data replaced by read_restart), then `run 0` (the state at the start) and `run ${steps}`; all of it
# ${segments} times over (`clear` between), so that every segment starts from the packing and the models do not
# drift apart: each model changes the packing in its own way (without static rolling torque the viscous heap
# flattens and loses half its contacts in 20,000 steps), so one long run would time different work again.
for model in cdt viscous; do
  in=$work/$model/in.liggghts
  {
    sed -n "1,$((data_line - 1))p" "$in" | grep -v '^include *system.liggghts'
    # shellcheck disable=SC2016 # ${segments} is LIGGGHTS's variable, expanded by LIGGGHTS
    echo 'variable        segment loop ${segments}'
    echo 'label           segment_loop'
    echo 'clear'
    echo 'include         system.liggghts'
    echo "read_restart    $work/packing.restart"
    sed -n "$((data_line + 1)),$((discs_line - 1))p" "$in"
    cat <<'EOF'
# ---------------------------------------------------------------- bench: contacts at the start and the end
compute         bench_contact all contact/atom
compute         bench_contacts all reduce sum c_bench_contact
thermo_style    custom step atoms c_bench_contacts ke c_rke
thermo          1000000000
run             0
run             ${steps}
next            segment
jump            SELF segment_loop
write_dump      all custom final.dump id x y z vx vy vz omegax omegay omegaz modify sort id format "%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
EOF
  } >"$work/$model/bench.liggghts"
done

# One run: name exe dir steps [prefix command...]; writes log.liggghts and time.txt in dir.
launch() {
  local exe=$2 dir=$3 n=$4
  shift 4
  rm -f "$dir/log.liggghts" "$dir/final.dump"
  (cd "$dir" && /usr/bin/time -f "%U %S" -o time.txt "$@" "$exe" -in bench.liggghts -var steps "$n" \
    -var segments "$segments" -log log.liggghts -screen /dev/null >stdout.txt 2>stderr.txt) ||
    { echo "bench: $exe failed in $dir (see its log.liggghts, stderr.txt)" >&2; exit 1; }
}
# Facts of a finished run: cpu_s atom_steps atoms contacts0 contacts1 neigh0 neigh1 builds; the start values are
# those of the packing, the end values the means over the segments' ends.
facts() {
  local dir=$1
  awk -v cpu="$(awk '{print $1 + $2}' "$dir/time.txt")" '
    $1 == "Step" {thermo = 1; next}
    thermo && /^ *[0-9]/ {if (s0 == "") {s0 = $1; c0 = $3}; if ($1 != s0) {ce += $3; ne++}; next}
    {thermo = 0}
    /^Loop time of/ {asteps += $9 * $12; atoms = $12}
    /^Total # of neighbors/ {k++; if (k % 2) {if (n0 == "") n0 = $NF} else {n1 += $NF; m++}}
    /^Neighbor list builds/ {b += $NF}
    END {printf "%s %d %d %d %.0f %d %.0f %d\n", cpu, asteps, atoms, c0 / 2, ne ? ce / ne / 2 : c0 / 2, n0,
      m ? n1 / m : n0, b}' "$dir/log.liggghts"
}

# Start-up cost: 0-step runs, one per model per round, interleaved with the timed runs.
results=$work/results.txt
setups=$work/setups.txt
: >"$results"
: >"$setups"
printf "%-17s %5s %7s %8s %12s %5s %11s %11s %6s %s\n" run round cpu_s net_cpu_s atom_steps atoms contacts neighbours builds \
  final_state_md5
rows=$work/rows.txt
: >"$rows"
for ((i = 1; i <= reps; i++)); do
  for ((j = 0; j < ${#names[@]}; j++)); do
    k=$(((i - 1 + j) % ${#names[@]}))
    d=$work/${dirs[$k]}
    launch "${names[$k]}" "${exes[$k]}" "$d" 0
    echo "${names[$k]} $(facts "$d")" >>"$setups"
    launch "${names[$k]}" "${exes[$k]}" "$d" "$steps"
    echo "${names[$k]} $i $(facts "$d") $(md5sum <"$d/final.dump" | cut -c1-12)" >>"$rows"
  done
done
# Net CPU: a run's CPU less the median 0-step CPU of its model.
python3 - "$rows" "$setups" "$results" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1]) if l.strip()]
setups = [l.split() for l in open(sys.argv[2]) if l.strip()]
setup = {n: statistics.median(float(s[1]) for s in setups if s[0] == n) for n in {s[0] for s in setups}}
with open(sys.argv[3], "w") as out:
    for name, rnd, cpu, asteps, atoms, c0, c1, n0, n1, builds, md5 in rows:
        net = float(cpu) - setup[name]
        us = 1e6 * net / float(asteps)
        print(f"{name:17s} {rnd:>5s} {float(cpu):7.3f} {net:8.3f} {int(asteps):12d} {atoms:>5s} {c0:>5s}->{c1:<5s} "
              f"{n0:>5s}->{n1:<5s} {builds:>6s} {md5}")
        out.write(f"{name} {rnd} {us:.5f}\n")
for n in sorted(setup):
    print(f"# start-up (0-step runs, median): {n} {setup[n]:.3f} s CPU")
PY
echo "# CPU per atom-step (us, net of start-up): medians, ratios to cdt; load average $(cat /proc/loadavg)"
medians "$results" 2

[ "$ir_steps" -gt 0 ] || exit 0
# ---- instructions per atom-step, inside the time-step loop.
if perf stat -e instructions -x, -o /dev/null true 2>/dev/null &&
  ! perf stat -e instructions -x, true 2>&1 | grep -q 'not supported'; then
  counter=perf
else
  counter=callgrind
fi
echo "# instructions per atom-step ($counter, $segments segments of $ir_steps steps per run, inside the time-step loop)"
irs=$work/ir.txt
: >"$irs"
for k in "${!names[@]}"; do
  d=$work/${dirs[$k]}
  if [ $counter = perf ]; then
    # perf counts the whole process: the 0-step run's count is subtracted.
    launch "${names[$k]}" "${exes[$k]}" "$d" 0 perf stat -e instructions -x, -o "$d/perf0.txt"
    launch "${names[$k]}" "${exes[$k]}" "$d" "$ir_steps" perf stat -e instructions -x, -o "$d/perf.txt"
    ir=$(($(awk -F, '/instructions/ {print $1}' "$d/perf.txt") - $(awk -F, '/instructions/ {print $1}' "$d/perf0.txt")))
  else
    launch "${names[$k]}" "${exes[$k]}" "$d" "$ir_steps" valgrind --tool=callgrind --collect-atstart=no \
      "--toggle-collect=LAMMPS_NS::Verlet::run(int)" --callgrind-out-file="$d/callgrind.${names[$k]}.out" -q
    ir=$(awk '/^totals:/ {print $2}' "$d/callgrind.${names[$k]}.out")
  fi
  read -r _ asteps _ c0 c1 n0 n1 builds < <(facts "$d")
  awk -v n="${names[$k]}" -v ir="$ir" -v a="$asteps" -v c="$c0->$c1" -v nb="$n0->$n1" -v b="$builds" \
    'BEGIN {printf "%-17s %14.0f instructions %11d atom-steps %8.1f per atom-step  contacts %s neighbours %s builds %s\n",
      n, ir, a, ir / a, c, nb, b}' | tee -a "$irs"
done
awk '{v[NR] = $6; n[NR] = $1} END {for (i = 1; i <= NR; i++) printf "%-17s x%.3f\n", n[i], v[i] / v[1]}' "$irs"
