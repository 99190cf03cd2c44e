#!/usr/bin/env bash
# LIGGGHTS builds and settings side by side on the same cases (docs/explanation/benchmarks.md, "LIGGGHTS builds"): each case is
# written once by `demsa case` (one packing, one parameter point per sample) and run by every build from a copy of its
# folder, so the runs are paired. Prints, per build, the atom-steps per CPU-second (median over the cases), its ratio
# to the first build (median of the per-case ratios), and the paired differences of the measured angle (the study's
# estimator, `demsa measure`) against the first build; then the load average.
#
# Usage: bench/liggghts-builds.sh DEMSA STUDY.toml CASES NAME=LIGGGHTS[@SED] [NAME=LIGGGHTS[@SED] ...]
#   CASES: N (samples 1..N) or a comma-separated list of case ids (e.g. replicate cases: 0,1000001,1000002).
#   e.g. bench/liggghts-builds.sh build/orchestrator/demsa examples/quickstart.toml 4 \
#          debian=/usr/bin/liggghts project=$(scripts/build-liggghts.sh --print-prefix)/bin/liggghts
#   A setting: @SED is a sed script run on the copy's *.liggghts files before the run, e.g.
#          'skin2=/usr/bin/liggghts@s/^variable skin .*/variable skin equal 0.002/'
# Environment: JOBS (default 2) runs at a time, one rank each; WORK (default a temporary folder, removed) keeps the
# case folders when set.
set -euo pipefail
(($# >= 4)) || { sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
demsa=$(realpath "$1")
study=$(realpath "$2")
if [[ $3 == *,* ]]; then IFS=, read -ra ids <<<"$3"; else mapfile -t ids < <(seq 1 "$3"); fi
shift 3
builds=("$@")
jobs=${JOBS:-2}
if [[ -n ${WORK:-} ]]; then
  work=$WORK
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
for b in "${builds[@]}"; do
  spec=${b#*=}
  [[ $b == *=* && -x ${spec%%@*} ]] || { echo "liggghts-builds: '$b': expected NAME=EXECUTABLE[@SED]" >&2; exit 2; }
done
echo "load before: $(cat /proc/loadavg)"
for k in "${ids[@]}"; do
  [[ -d $work/case-$k ]] || "$demsa" case "$study" --sample "$k" -o "$work/case-$k" >/dev/null
done
# One run: copy the case (its LIGGGHTS scripts edited by the setting's sed script, if any), run the build in it on
# one rank, record CPU seconds, atom-steps and the angle (a drum's: its dynamic angle).
run_one() { # name executable[@sed] work k demsa
  local d=$3/$1-$4 exe=${2%%@*} edit=
  [[ $2 == *@* ]] && edit=${2#*@}
  rm -rf "$d"
  cp -r "$3/case-$4" "$d"
  if [[ -n $edit ]]; then
    sed -i -e "$edit" "$d"/*.liggghts
    cmp -s "$3/case-$4/in.liggghts" "$d/in.liggghts" && cat "$3/case-$4"/*.liggghts | cmp -s - <(cat "$d"/*.liggghts) &&
      echo "liggghts-builds: $1: the sed script '$edit' changed nothing in case $4" >&2
  fi
  (cd "$d" && /usr/bin/time -f "%U %S" -o cpu.txt "$exe" -in in.liggghts -log log.liggghts -screen screen.txt \
    >/dev/null 2>&1) || echo "liggghts-builds: $1 case $4 failed (see $d/log.liggghts)" >&2
  awk '/^Loop time of .* procs for [0-9]+ steps with [0-9]+ atoms/ {s += $9 * $12} END {printf "%.0f\n", s}' \
    "$d/log.liggghts" >"$d/atom_steps.txt"
  "$5" measure "$d" --json 2>/dev/null | python3 -c 'import json,sys; o = json.load(sys.stdin)["observables"]; print(o.get("angle", o.get("dynamic_angle")))' \
    >"$d/angle.txt" 2>/dev/null || echo nan >"$d/angle.txt"
}
export -f run_one
for k in "${ids[@]}"; do
  for b in "${builds[@]}"; do printf '%s\0%s\0%s\0%s\0%s\0' "${b%%=*}" "${b#*=}" "$work" "$k" "$demsa"; done
done | xargs -0 -P "$jobs" -n 5 bash -c 'run_one "$@"' _
echo "load after: $(cat /proc/loadavg)"
python3 - "$work" "$(IFS=,; echo "${ids[*]}")" "${builds[@]%%=*}" <<'PY'
import statistics, sys
work, ids, names = sys.argv[1], sys.argv[2].split(","), sys.argv[3:]
def read(name, k):
    d = f"{work}/{name}-{k}"
    u, s = map(float, open(f"{d}/cpu.txt").read().split()[-2:])
    return int(open(f"{d}/atom_steps.txt").read()), u + s, float(open(f"{d}/angle.txt").read())
rows = {n: [read(n, k) for k in ids] for n in names}
base = rows[names[0]]
print(f"| build | atom-steps per CPU-s (median) | ratio to {names[0]} (median of per-case ratios) | per case | "
      f"angle − {names[0]}'s [deg] per case |")
print("|---|---|---|---|---|")
for n in names:
    rate = [a / c for a, c, _ in rows[n]]
    ratio = [(a / c) / (ab / cb) for (a, c, _), (ab, cb, _) in zip(rows[n], base)]
    diff = [ang - angb for (_, _, ang), (_, _, angb) in zip(rows[n], base)]
    print(f"| {n} | {statistics.median(rate):.3g} | {statistics.median(ratio):.3f} | "
          f"{', '.join(f'{r:.3f}' for r in ratio)} | {', '.join(f'{x:+.2f}' for x in diff)} |")
print("atom-steps per case:", {n: [a for a, _, _ in rows[n]] for n in names})
PY
