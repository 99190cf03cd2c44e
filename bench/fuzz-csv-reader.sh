#!/usr/bin/env bash
# Builds the libFuzzer target for the CSV reader (bench/fuzz_csv_reader.cpp + orchestrator/util/csv.cpp and the two
# util files it needs) with clang++, AddressSanitizer and UndefinedBehaviorSanitizer, and runs it for FUZZ_SECONDS
# (default 60) on one core. Seeds: a design, a data table with a label column, a BOM and CRLF file. Not part of CI.
# Usage: bench/fuzz-csv-reader.sh [work-dir]   (default: $TMPDIR/demsa-fuzz-csv)
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="${1:-${TMPDIR:-/tmp}/demsa-fuzz-csv}"
seconds="${FUZZ_SECONDS:-60}"
cxx="$(command -v clang++ || true)"
if [[ -z "$cxx" ]]; then
  echo "fuzz-csv-reader: clang++ not found; the libFuzzer target needs clang (apt-get install clang)" >&2
  exit 2
fi
mkdir -p "$work/corpus" "$work/artifacts"
"$cxx" -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined -I"$src" \
  -isystem /usr/include/eigen3 "$src/bench/fuzz_csv_reader.cpp" "$src/orchestrator/util/csv.cpp" \
  "$src/orchestrator/util/atomic_file.cpp" "$src/orchestrator/util/text.cpp" -lfmt -o "$work/fuzz_csv_reader"
# Seed corpus (small inputs; libFuzzer mutates them). The first byte picks the reader's options.
printf '\x00block,a,b\n0,0.25,0.5\n1,0.75,0.125\n2,0.75,0.5\n3,0.25,0.125\n' > "$work/corpus/design.csv"
printf '\x08# data\na,b,label,y\n1.5,2,"x",3e-4\n2.5,-1,y,nan\n\n3.5,0,z,inf\n' > "$work/corpus/labels.csv"
printf '\x01\xef\xbb\xbf"a","y"\r\n1,2\r\n3,4\r\n' > "$work/corpus/bom_crlf.csv"
printf '\x04x,y\n0.5,1\n0.5,2\n' > "$work/corpus/constant.csv"
{ printf '\x00'; printf '1.5,2.5\n3,4\n'; } > "$work/corpus/no_header.csv"
cd "$work"
ASAN_OPTIONS=detect_leaks=1 "$work/fuzz_csv_reader" -max_total_time="$seconds" -max_len=16384 -rss_limit_mb=2048 \
  -artifact_prefix="$work/artifacts/" "$work/corpus"
