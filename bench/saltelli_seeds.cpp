// Accuracy of the Saltelli estimators over scrambling seeds (docs/explanation/benchmarks.md, "Accuracy of the QMC
// estimators"): Ishigami (a = 7, b = 0.1) on second-order designs, seeds 1..S and the default 12345. Prints the RMS
// error of S1 and ST, the worst seed, how many seeds reach max |error| <= 0.005, and how many have S13 within 0.01.
//
// usage: build/bench/saltelli_seeds [BASE] [SEEDS]   (defaults 2048 100)
#include "tests/sobol/ishigami_seeds.hpp"

#include <fmt/core.h>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  const int base = argc > 1 ? std::atoi(argv[1]) : 2048;
  const int count = argc > 2 ? std::atoi(argv[2]) : 100;
  if (base < 2 || count < 1) {
    fmt::print(stderr, "usage: saltelli_seeds [BASE >= 2] [SEEDS >= 1]\n");
    return 2;
  }
  std::vector<std::uint64_t> seeds;
  for (int s = 1; s <= count; ++s) seeds.push_back(static_cast<std::uint64_t>(s));
  seeds.push_back(12345);
  const demsa::sobol::test::IshigamiSeedAccuracy a = demsa::sobol::test::ishigami_over_seeds(base, seeds);
  for (std::size_t k = 0; k < seeds.size(); ++k)
    if (seeds[k] == 7 || seeds[k] == 12345)
      fmt::print("seed {}: max |error| of S1/ST {:.4f}\n", seeds[k], a.seed_worst[k]);
  fmt::print(
      "Ishigami, base {}, {} seeds: RMS error of S1/ST {:.5f}, worst seed {:.4f}, {} seeds with max |error| <= "
      "0.005, {} with S13 within 0.01 (worst S13 error {:.4f})\n",
      base, seeds.size(), a.rms, a.worst, a.within, a.s13_within, a.worst_s13);
  return 0;
}
