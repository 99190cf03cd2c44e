#!/usr/bin/env bash
# Builds the libFuzzer target for the study-file parser (bench/fuzz_study_file.cpp + orchestrator/study and the parts
# of sobol/ it names) with clang++, AddressSanitizer and UndefinedBehaviorSanitizer, and runs it for FUZZ_SECONDS
# (default 60) on one core.
# Seeds: the examples' study files and the docs' example. Not part of CI.
# The parser and the experiments' settings tables are compiled here under the sanitizers (coverage-instrumented); the
# rest of what the registry names (case writers, measurements, sobol/, postprocess/) is linked from a CMake build's
# static libraries, uninstrumented (BUILD, default build/: `cmake -B build && make -C build demsa`).
# Usage: bench/fuzz-study-file.sh [work-dir] [build-dir]   (default: $TMPDIR/demsa-fuzz-study, build)
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="${1:-${TMPDIR:-/tmp}/demsa-fuzz-study}"
build="$(cd "${2:-$src/build}" && pwd)"
for lib in orchestrator/libdemsa_experiments.a sobol/libdemsa_sobol.a postprocess/libdemsa_postprocess.a; do
  [[ -f "$build/$lib" ]] || { echo "fuzz-study-file: $build/$lib missing: build demsa first (make -C $build demsa)" >&2; exit 2; }
done
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
# -fno-sanitize=unreachable: toml++ 3.3 (Debian's) reaches TOML_UNREACHABLE in is_non_ascii_horizontal_whitespace()
# for U+00A1–U+0499, U+2CEE–U+30E7 and U+FB36–U+FEFE after a line-ending backslash in a multi-line string
# (`"""a\ μ"""`), a fault of the library; demsa's own build reports the parse error there ("line-ending
# backslashes must be the last non-whitespace character on the line", exit 2). Left out so that the fuzzer goes on
# to faults of demsa's.
flags=(-std=c++20 -O1 -g -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize=unreachable
  -fno-sanitize-recover=undefined
  -I"$src" -isystem /usr/include/eigen3 -DFMT_SHARED "-DTOML_ASSERT(expr)=static_cast<void>(0)")
# The parser and the settings tables of every experiment (the registry's: each folder's settings.cpp, found, so that a
# new experiment needs no edit here); an object newer than its source and the headers is kept from an earlier build.
sources=(orchestrator/study/config.cpp orchestrator/study/settings.cpp orchestrator/study/parameters.cpp
  orchestrator/experiments/registry.cpp)
for f in "$src"/orchestrator/experiments/*/settings.cpp; do sources+=("${f#"$src"/}"); done
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
lib="$build/orchestrator"
"$cxx" "${flags[@]}" -fsanitize=fuzzer "$src/bench/fuzz_study_file.cpp" "${objects[@]}" "$lib/libdemsa_experiments.a" \
  "$lib/libdemsa_cases.a" "$lib/libdemsa_driver.a" "$lib/libdemsa_study.a" "$lib/libdemsa_util.a" \
  "$build/postprocess/libdemsa_postprocess.a" "$build/sobol/libdemsa_sobol.a" "$lib/libdemsa_experiments.a" \
  "$lib/libdemsa_study.a" -lSQLiteCpp -lsqlite3 -ltomlplusplus -lfmt -lnlopt -lgsl -lgslcblas -ldl \
  -o "$work/fuzz_study_file"
# Seed corpus: every study file of the examples and tests (small; libFuzzer mutates them).
for f in "$src"/examples/*.toml "$src"/examples/calibration/*.toml "$src"/tests/data/*/study.toml; do
  [[ -f "$f" ]] && cp "$f" "$work/corpus/$(echo "${f#"$src"/}" | tr / _)"
done
printf '[study]\nname = "s"\nexperiment = "oedometer"\n[design]\nsamples = 4\n[parameters]\nE = { low = 1e7, high = 1e8 }\n[oedometer]\nloads = [1, 2]\nmeasured_settlements = [1e-3]\n' \
  > "$work/corpus/small_oedometer.toml"
cd "$work"
# -max_len: a study file is a few kB; -timeout: a parse takes microseconds, 10 s is a hang.
ASAN_OPTIONS=detect_leaks=1 "$work/fuzz_study_file" -max_total_time="$seconds" -max_len=8192 -timeout=10 \
  -rss_limit_mb=2048 -artifact_prefix="$work/artifacts/" "$work/corpus" 2> >(grep -v '^demsa: warning:' >&2)
