// Dump reading throughput: a ~100 MB LIGGGHTS `dump custom` file (columns id type x y z radius vx vy vz, values
// printed as LIGGGHTS does, %g) read frame by frame on one core, and the cost of getting only its last frame.
// The file is written once to $TMPDIR (or /tmp) and removed at the end. Size: DEMSA_BENCH_DUMP_MB (default 100).
#include "postprocess/dump.hpp"

#include <benchmark/benchmark.h>
#include <fmt/core.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

namespace {

namespace fs = std::filesystem;
using demsa::postprocess::DumpFrame;
using demsa::postprocess::DumpReader;

/// Writes a dump of about `megabytes` MB in frames of 100 000 atoms; returns its path.
fs::path make_dump(std::size_t megabytes) {
  const char* tmp = std::getenv("TMPDIR");
  const fs::path path = fs::path(tmp != nullptr ? tmp : "/tmp") / fmt::format("demsa_bench_{}.dump", megabytes);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) throw std::runtime_error("cannot write " + path.string());
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> pos(-0.15, 0.15), vel(-0.5, 0.5), rad(0.001, 0.0035);
  const std::size_t atoms = 100000;
  std::size_t written = 0;
  std::string buf;
  for (long step = 0; written < megabytes * 1000000; step += 20000) {
    buf = fmt::format(
        "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS ff ff ff\n-0.15 0.15\n-0.15 0.15\n"
        "-0.01 0.2\nITEM: ATOMS id type x y z radius vx vy vz \n",
        step, atoms);
    for (std::size_t i = 0; i < atoms; ++i)
      buf += fmt::format("{} 1 {:g} {:g} {:g} {:g} {:g} {:g} {:g} \n", i + 1, pos(rng), pos(rng), pos(rng) + 0.15,
                         rad(rng), vel(rng), vel(rng), vel(rng) * 1e-3);
    std::fwrite(buf.data(), 1, buf.size(), f);
    written += buf.size();
  }
  std::fclose(f);
  return path;
}

struct DumpFile {
  fs::path path;
  std::uintmax_t bytes = 0;
  DumpFile() {
    const char* mb = std::getenv("DEMSA_BENCH_DUMP_MB");
    path = make_dump(mb != nullptr ? static_cast<std::size_t>(std::atoi(mb)) : 100);
    bytes = fs::file_size(path);
  }
  ~DumpFile() { fs::remove(path); }
};

const DumpFile& dump_file() {
  static const DumpFile file;
  return file;
}

void BM_ReadAllFrames(benchmark::State& state) {
  const DumpFile& file = dump_file();
  std::size_t atoms = 0;
  for (auto _ : state) {
    DumpReader reader(file.path);
    DumpFrame frame;
    while (reader.next(frame)) atoms += frame.atom_count;
    benchmark::DoNotOptimize(atoms);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * file.bytes));
  state.counters["file_MB"] = static_cast<double>(file.bytes) / 1e6;
}
BENCHMARK(BM_ReadAllFrames)->Unit(benchmark::kMillisecond)->MinTime(3.0);

void BM_ReadLastFrame(benchmark::State& state) {
  const DumpFile& file = dump_file();
  for (auto _ : state) {
    const DumpFrame frame = demsa::postprocess::read_last_frame(file.path);
    benchmark::DoNotOptimize(frame.atom_count);
  }
  state.counters["file_MB"] = static_cast<double>(file.bytes) / 1e6;
}
BENCHMARK(BM_ReadLastFrame)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
