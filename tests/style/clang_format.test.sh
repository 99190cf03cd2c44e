#!/usr/bin/env bash
# The C++ sources are clang-format clean (the checked-in .clang-format).
set -euo pipefail
cd "${DEMSA_SOURCE_DIR:?}"
command -v clang-format >/dev/null || { echo "clang-format not installed (scripts/install-deps.sh installs it)"; exit 1; }
mapfile -t files < <(git ls-files -co --exclude-standard -- '*.cpp' '*.hpp' '*.h' 2>/dev/null || find sobol postprocess orchestrator tests bench -name '*.[ch]pp')
bad=()
for f in "${files[@]}"; do
  [[ -f $f ]] || continue
  clang-format --dry-run -Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if ((${#bad[@]})); then
  echo "not clang-format clean (run: clang-format -i FILE):"
  printf '  %s\n' "${bad[@]}"
  exit 1
fi
echo "${#files[@]} files clang-format clean"
