#!/usr/bin/env bash
# Write liggghts/profile.tar.xz, the profile scripts/build-liggghts.sh compiles LIGGGHTS with (GCC's -fprofile-use):
# build the same source with -fprofile-generate (build-liggghts.sh --instrument), run it on the first case of
# demsa's examples of every experiment (pile, rough-base pile, incline, servo oedometer, draw-down, drum) and of every
# compiled rolling model (cdt, viscous, epsd, epsd2, epsd3), and pack the counts. Run it again whenever the build's
# source changes (a patch, the kernel list, a sed edit): where a function no longer matches its counts,
# build-liggghts.sh fails and says so.
# The counts are those of single-rank runs of deterministic trajectories; only what depends on the clock (timers,
# progress output) may count differently from one run of the script to the next.
#
# Usage: scripts/write-liggghts-profile.sh DEMSA [--jobs N]
#   DEMSA  the demsa executable that writes the cases (build/orchestrator/demsa)
#   --jobs N  compile jobs and cases run at once (default 2)
# Takes about 6 minutes to build and 4 to run on two cores; writes nothing but the profile (and a work folder in /tmp).
set -euo pipefail

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
say() { echo "write-liggghts-profile: $*" >&2; }
(($# >= 1)) || { sed -n '2,14p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 2; }
demsa=$(realpath "$1")
shift
jobs=2
while (($#)); do
  case $1 in
    --jobs) jobs=${2:?--jobs needs a number}; shift ;;
    *) say "error: unknown option '$1'"; exit 2 ;;
  esac
  shift
done
[[ -x $demsa ]] || { say "error: $demsa is not an executable"; exit 2; }

work=$(mktemp -d /tmp/liggghts-profile.XXXXXX)
say "work folder $work"
prefix=$("$repo/scripts/build-liggghts.sh" --instrument "$work/instrumented" --jobs "$jobs")
objects=$(cat "$prefix/objects-dir.txt")
exe=$prefix/bin/liggghts

# The training cases: STUDY SAMPLE [ROLLING_MODEL] (a model appended to a copy of the study's file).
cases=(
  "examples/quickstart.toml 0"
  "examples/quickstart-viscous.toml 0"
  "examples/calibration/pile-rough.toml 0"
  "examples/calibration/incline.toml 0"
  "examples/calibration/oedometer.toml 0"
  "examples/calibration/drawdown.toml 0"
  "bench/profile-drum.toml 0"
  "tests/data/cases/tiny_pile.toml 0 epsd"
  "tests/data/cases/tiny_pile.toml 0 epsd2"
  "tests/data/cases/tiny_pile.toml 0 epsd3"
)
mkdir -p "$work/cases"
k=0
for c in "${cases[@]}"; do
  read -r study sample model <<<"$c"
  file=$repo/$study
  if [[ -n $model ]]; then
    file=$work/cases/$k-$model.toml
    { cat "$repo/$study"; printf '\n[contact]\nrolling_model = "%s"\n' "$model"; } >"$file"
  fi
  "$demsa" case "$file" --sample "$sample" -o "$work/cases/$k" >/dev/null ||
    { say "error: demsa case $file --sample $sample failed"; exit 1; }
  k=$((k + 1))
done

# Each run writes its counts under $work/counts (GCOV_PREFIX), the objects' folder stripped to CMakeFiles/...; runs
# that end together merge their counts (gcov locks each file).
strip=$(($(tr -cd / <<<"$objects" | wc -c)))
mkdir -p "$work/counts"
run_case() {
  cd "$1" && GCOV_PREFIX=$2 GCOV_PREFIX_STRIP=$3 "$4" -in in.liggghts -log log.liggghts -screen screen.txt >/dev/null ||
    { echo "write-liggghts-profile: error: the training case $1 failed (see its log.liggghts)" >&2; return 1; }
}
export -f run_case
start=$(date +%s)
printf '%s\n' "$work"/cases/*/ | xargs -P "$jobs" -I{} bash -c 'run_case "$@"' _ {} "$work/counts" "$strip" "$exe"
say "ran ${#cases[@]} cases in $(($(date +%s) - start)) s"
counted=$(find "$work/counts/CMakeFiles/liggghts_obj.dir" -name '*.gcda' | wc -l)
((counted > 100)) || { say "error: only $counted count files under $work/counts"; exit 1; }
# A reproducible archive: sorted names, no times or owners.
tar --sort=name --mtime=@0 --owner=0 --group=0 --numeric-owner -C "$work/counts" -cf - CMakeFiles |
  xz -9e >"$repo/liggghts/profile.tar.xz"
say "wrote liggghts/profile.tar.xz ($counted files, $(stat -c %s "$repo/liggghts/profile.tar.xz") bytes)"
rm -rf "$work"
