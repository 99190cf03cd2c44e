#!/usr/bin/env bash
# ARCHITECTURE.md "Adding an experiment": an experiment is its folder orchestrator/experiments/NAME/ and one line of
# registry.cpp. check_tree checks, for every experiment folder of a source tree, that the rest of demsa needs no edit
# for it:
#   - registry.cpp lists it once (`&NAME::experiment(),`), and it has its settings.cpp and its fake LIGGGHTS
#     (fake_liggghts.py with `def run(case, unit, mode, particles, sample)`);
#   - the build (orchestrator/CMakeLists.txt), the fake LIGGGHTS's main and bench/fuzz-study-file.sh name no experiment
#     folder, and no C++ file outside the folder compares a name with it (`== "NAME"`);
#   - outside the folder only registry.cpp includes its headers (an experiment's own tool, `demsa postprocess NAME`,
#     comes through its descriptor: experiments/case_tool.hpp).
# It checks demsa's tree, then proves the recipe on a throw-away copy: a new experiment `toy` (a copy of an existing
# folder under the new name) with its registry line passes, and without that line fails.
set -euo pipefail
cd "${DEMSA_SOURCE_DIR:?}"

# check_tree ROOT: prints what breaks the recipe; succeeds when nothing does.
check_tree() {
  local root=$1 bad="" count=0 dir name lines file hits hit
  for dir in "$root"/orchestrator/experiments/*/; do
    name=$(basename "$dir")
    count=$((count + 1))
    lines=$(grep -cE "^[[:space:]]*&${name}::experiment\(\),?[[:space:]]*$" "$root/orchestrator/experiments/registry.cpp" || true)
    [[ $lines == 1 ]] || bad+=$'\n'"registry.cpp: $name listed $lines times (once expected)"
    [[ -f $dir/settings.cpp ]] || bad+=$'\n'"$name: no settings.cpp"
    grep -q '^def run(case, unit, mode, particles, sample):' "$dir/fake_liggghts.py" 2>/dev/null ||
      bad+=$'\n'"$name: no fake_liggghts.py with run(case, unit, mode, particles, sample)"
    for file in orchestrator/CMakeLists.txt tests/integration/fake_liggghts/liggghts bench/fuzz-study-file.sh; do
      hits=$(grep -nE "experiments/$name\b|== \"$name\"" "$root/$file" || true)
      [[ -z $hits ]] || bad+=$'\n'"$file: $hits (names $name)"
    done
    while IFS= read -r hit; do
      [[ -n $hit ]] || continue
      file=${hit#"$root"/}
      file=${file%%:*}
      [[ $file == orchestrator/experiments/$name/* ]] && continue
      bad+=$'\n'"${hit#"$root"/} (compares with the name of $name)"
    done < <(grep -rnE "(==|!=) \"$name\"|\"$name\" (==|!=)" "$root/orchestrator" --include='*.cpp' --include='*.hpp' || true)
    while IFS= read -r hit; do
      [[ -n $hit ]] || continue
      file=${hit#"$root"/}
      file=${file%%:*}
      [[ $file == orchestrator/experiments/$name/* || $file == orchestrator/experiments/registry.cpp ]] && continue
      bad+=$'\n'"${hit#"$root"/} (includes $name's headers)"
    done < <(grep -rnE "#include[[:space:]]*\"orchestrator/experiments/$name/" "$root/orchestrator" --include='*.cpp' \
      --include='*.hpp' || true)
  done
  ((count >= 1)) || bad+=$'\n'"orchestrator/experiments/: no experiment folder"
  [[ -z ${bad//$'\n'/} ]] || { echo "$bad"; return 1; }
  echo "$count experiments, each its folder and one line of registry.cpp"
}

if ! out=$(check_tree "$PWD"); then
  echo "an experiment is not in one place (ARCHITECTURE.md \"Adding an experiment\"):$out"
  exit 1
fi
echo "$out"

# The recipe on a throw-away copy: the files check_tree reads, and a new experiment `toy` made of the draw-down's.
tree=$(mktemp -d)
trap 'rm -rf "$tree"' EXIT
mkdir -p "$tree/tests/integration" "$tree/bench"
cp -r orchestrator "$tree/orchestrator"
cp -r tests/integration/fake_liggghts "$tree/tests/integration/"
cp bench/fuzz-study-file.sh "$tree/bench/"
cp -r "$tree/orchestrator/experiments/drawdown" "$tree/orchestrator/experiments/toy"
for f in "$tree"/orchestrator/experiments/toy/*; do
  sed -i 's/drawdown/toy/g' "$f"
  [[ $f == */drawdown* ]] && mv "$f" "${f/drawdown/toy}"
done
if out=$(check_tree "$tree"); then
  echo "a new experiment without its registry line passed the check:"
  echo "$out"
  exit 1
fi
[[ $out == *"registry.cpp: toy listed 0 times"* ]] || { echo "unexpected complaint about toy:$out"; exit 1; }
sed -i 's/^\([[:space:]]*\)&drawdown::experiment(),$/&\n\1\&toy::experiment(),/' "$tree/orchestrator/experiments/registry.cpp"
if ! out=$(check_tree "$tree"); then
  echo "a new experiment in its folder with its registry line failed the check:$out"
  exit 1
fi
echo "throw-away experiment toy: $out"
