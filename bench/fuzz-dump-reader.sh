#!/usr/bin/env bash
# Builds the libFuzzer target for the dump reader (bench/fuzz_dump_reader.cpp + postprocess/dump.cpp and text.cpp) with clang++,
# AddressSanitizer and UndefinedBehaviorSanitizer, and runs it for FUZZ_SECONDS (default 60) on one core.
# Seeds: the real LIGGGHTS pile dump of the tests and a few small frames. Not part of CI.
# Usage: bench/fuzz-dump-reader.sh [work-dir]   (default: $TMPDIR/demsa-fuzz-dump)
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="${1:-${TMPDIR:-/tmp}/demsa-fuzz-dump}"
seconds="${FUZZ_SECONDS:-60}"
cxx="$(command -v clang++ || true)"
if [[ -z "$cxx" ]]; then
  echo "fuzz-dump-reader: clang++ not found; the libFuzzer target needs clang (apt-get install clang)" >&2
  exit 2
fi
mkdir -p "$work/corpus" "$work/artifacts"
"$cxx" -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
  -I"$src" "$src/bench/fuzz_dump_reader.cpp" "$src/postprocess/dump.cpp" "$src/postprocess/text.cpp" -lfmt \
  -o "$work/fuzz_dump_reader"
# Seed corpus (small inputs; libFuzzer mutates them).
head -c 4000 "$src/tests/data/postprocess/liggghts_pile/pile_final.dump" > "$work/corpus/pile_head.dump"
printf 'ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp ff\n0 1\n0 1\n0 1\nITEM: ATOMS id type x y z radius\n1 1 0.5 0.5 0.5 0.1\n2 1 0.25 0.5 0.75 0.05\n' \
  > "$work/corpus/two_atoms.dump"
printf 'ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS xy xz yz ff ff ff\n0 2 0.1\n0 4 0\n0 8 0\nITEM: ATOMS id type xs ys zs radius\n1 1 0.5 0.25 0.5 0.1\n' \
  > "$work/corpus/triclinic_scaled.dump"
cd "$work"
ASAN_OPTIONS=detect_leaks=1 "$work/fuzz_dump_reader" -max_total_time="$seconds" -max_len=16384 -rss_limit_mb=2048 \
  -artifact_prefix="$work/artifacts/" "$work/corpus"
