#!/usr/bin/env bash
# Builds the libFuzzer target for the study-file parser (bench/fuzz_study_file.cpp + orchestrator/study and the parts
# of sobol/ it names) with clang++, AddressSanitizer and UndefinedBehaviorSanitizer, and runs it for FUZZ_SECONDS
# (default 60) on one core.
# Seeds: the examples' study files and the docs' example. Not part of CI.
# Usage: bench/fuzz-study-file.sh [work-dir]   (default: $TMPDIR/demsa-fuzz-study)
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="${1:-${TMPDIR:-/tmp}/demsa-fuzz-study}"
seconds="${FUZZ_SECONDS:-60}"
cxx="$(command -v clang++ || true)"
if [[ -z "$cxx" ]]; then
  echo "fuzz-study-file: clang++ not found; the libFuzzer target needs clang (apt-get install clang)" >&2
  exit 2
fi
mkdir -p "$work/corpus" "$work/artifacts" "$work/obj"
# toml++ is compiled into the target (instrumented) with its internal assertions off, as in the shared library demsa
# links: toml++ 3.3's parse_key() asserts on "[ =" before its own error path reports it ("expected bare key starting
# character"), which is what demsa prints.
flags=(-std=c++20 -O1 -g -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
  -I"$src" -isystem /usr/include/eigen3 -DFMT_SHARED "-DTOML_ASSERT(expr)=static_cast<void>(0)")
# The parser and what it names of sobol/ (design kinds, metamodel names, scales); an object newer than its source and
# the headers is kept from an earlier build (the sobol/ sources take minutes under the sanitizers).
sources=(orchestrator/study/config.cpp orchestrator/study/settings.cpp orchestrator/study/parameters.cpp
  orchestrator/util/text.cpp orchestrator/util/log.cpp sobol/design.cpp sobol/scaling.cpp sobol/metamodel.cpp
  sobol/gp.cpp sobol/rbf.cpp sobol/rsm.cpp)
newest_header="$(find "$src/orchestrator" "$src/sobol" -name '*.hpp' -newer "$work/obj" -print -quit 2>/dev/null || true)"
objects=()
for f in "${sources[@]}"; do
  o="$work/obj/$(echo "$f" | tr / _).o"
  if [[ ! -f "$o" || "$src/$f" -nt "$o" || -n "$newest_header" ]]; then
    "$cxx" "${flags[@]}" -c "$src/$f" -o "$o"
  fi
  objects+=("$o")
done
touch "$work/obj"
"$cxx" "${flags[@]}" -fsanitize=fuzzer "$src/bench/fuzz_study_file.cpp" "${objects[@]}" -lfmt -lnlopt -lgsl -lgslcblas \
  -o "$work/fuzz_study_file"
# Seed corpus: every study file of the examples and tests (small; libFuzzer mutates them).
for f in "$src"/examples/*.toml "$src"/tests/data/*/study.toml; do
  [[ -f "$f" ]] && cp "$f" "$work/corpus/$(echo "${f#"$src"/}" | tr / _)"
done
printf '[study]\nname = "s"\nexperiment = "oedometer"\n[design]\nsamples = 4\n[parameters]\nE = { low = 1e7, high = 1e8 }\n[oedometer]\nloads = [1, 2]\nmeasured_settlements = [1e-3]\n' \
  > "$work/corpus/small_oedometer.toml"
cd "$work"
# -max_len: a study file is a few kB; -timeout: a parse takes microseconds, 10 s is a hang.
ASAN_OPTIONS=detect_leaks=1 "$work/fuzz_study_file" -max_total_time="$seconds" -max_len=8192 -timeout=10 \
  -rss_limit_mb=2048 -artifact_prefix="$work/artifacts/" "$work/corpus" 2> >(grep -v '^demsa: warning:' >&2)
