// Accuracy of the Saltelli estimators over scrambling seeds (docs/benchmarks.md, "Accuracy of the QMC estimators"):
// Ishigami (a = 7, b = 0.1) on second-order designs, seeds 1..S and the default 12345. Prints the RMS error of S1
// and ST, the worst seed, how many seeds reach max |error| <= 0.005, and how many have S13 within 0.01.
//
// usage: build/bench/saltelli_seeds [BASE] [SEEDS]   (defaults 2048 100)
#include "sobol/saltelli.hpp"
#include "tests/sobol/analytic.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  using namespace demsa::sobol;
  const int base = argc > 1 ? std::atoi(argv[1]) : 2048;
  const int count = argc > 2 ? std::atoi(argv[2]) : 100;
  if (base < 2 || count < 1) {
    fmt::print(stderr, "usage: saltelli_seeds [BASE >= 2] [SEEDS >= 1]\n");
    return 2;
  }
  std::vector<std::uint64_t> seeds;
  for (int s = 1; s <= count; ++s) seeds.push_back(static_cast<std::uint64_t>(s));
  seeds.push_back(12345);
  double sum_squares = 0.0, worst = 0.0;
  int within = 0, s13_within = 0;
  for (const std::uint64_t seed : seeds) {
    SaltelliOptions o;
    o.base = base;
    o.dimension = 3;
    o.second_order = true;
    o.seed = seed;
    SobolOptions so;
    so.second_order = true;
    so.bootstrap = 0;
    const SobolResult r = sobol_indices(test::ishigami, saltelli_design(o), so);
    double seed_worst = 0.0;
    for (std::size_t k = 0; k < 3; ++k) {
      const double e1 = r.first[k].value - test::k_ishigami_s1[k], et = r.total[k].value - test::k_ishigami_st[k];
      sum_squares += e1 * e1 + et * et;
      seed_worst = std::max({seed_worst, std::abs(e1), std::abs(et)});
    }
    worst = std::max(worst, seed_worst);
    within += seed_worst <= 0.005;
    s13_within += std::abs(r.second[1].s.value - test::k_ishigami_s13) <= 0.01;
    if (seed == 7 || seed == 12345) fmt::print("seed {}: max |error| of S1/ST {:.4f}\n", seed, seed_worst);
  }
  const double n = static_cast<double>(seeds.size());
  fmt::print(
      "Ishigami, base {}, {} seeds: RMS error of S1/ST {:.5f}, worst seed {:.4f}, {} seeds with max |error| <= "
      "0.005, {} with S13 within 0.01\n",
      base, seeds.size(), std::sqrt(sum_squares / (6.0 * n)), worst, within, s13_within);
  return 0;
}
