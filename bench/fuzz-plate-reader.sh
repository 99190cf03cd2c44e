#!/usr/bin/env bash
# Builds the libFuzzer target for the plate-file readers (bench/fuzz_plate_reader.cpp + postprocess/oedometer.cpp,
# text.cpp, measures.cpp) with clang++, AddressSanitizer and UndefinedBehaviorSanitizer, and runs it for
# FUZZ_SECONDS (default 60) on one core. Seeds: a few small plate tables in both formats. Not part of CI.
# Usage: bench/fuzz-plate-reader.sh [work-dir]   (default: $TMPDIR/demsa-fuzz-plate)
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="${1:-${TMPDIR:-/tmp}/demsa-fuzz-plate}"
seconds="${FUZZ_SECONDS:-60}"
cxx="$(command -v clang++ || true)"
if [[ -z "$cxx" ]]; then
  echo "fuzz-plate-reader: clang++ not found; the libFuzzer target needs clang (apt-get install clang)" >&2
  exit 2
fi
mkdir -p "$work/corpus" "$work/artifacts"
"$cxx" -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined -I"$src" \
  "$src/bench/fuzz_plate_reader.cpp" "$src/postprocess/oedometer.cpp" "$src/postprocess/text.cpp" \
  "$src/postprocess/measures.cpp" -lfmt -o "$work/fuzz_plate_reader"
# Seed corpus (small inputs; libFuzzer mutates them).
printf '# plate states\n# load_N plate_z_m force_N converged\n100 0.0600 100.01 1\n400 0.0590 399.98 1\n1100 0.0575 1100.02 1\n2700 0.0550 2699.5 0\n' \
  > "$work/corpus/states.txt"
printf '# Time-averaged data for fix plate\n# step load_N plate_z_m force_N trial delta_m accepted\n15000 100 0.0610 20 1 7.5e-6 1\n30000 100 0.0605 120 2 7.5e-6 0\n45000 100 0.0600 100.01 3 7.125e-6 1\n60000 400 0.0595 300 1 7.5e-6 1\n' \
  > "$work/corpus/history_trial.txt"
printf '\xef\xbb\xbf# step load_N plate_z_m force_N\r\n1000 100 0.06 99.5\r\n2000 100 0.0599 100.2\r\n3000 400 0.059 399\r\n' \
  > "$work/corpus/history_bom_crlf.txt"
cd "$work"
ASAN_OPTIONS=detect_leaks=1 "$work/fuzz_plate_reader" -max_total_time="$seconds" -max_len=16384 -rss_limit_mb=2048 \
  -artifact_prefix="$work/artifacts/" "$work/corpus"
