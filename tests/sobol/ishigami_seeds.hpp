#pragma once
// Accuracy of the second-order Saltelli analysis of Ishigami over scrambling seeds: shared by the test that bounds it
// (tests/sobol/test_saltelli.cpp) and the bench that measures it (bench/saltelli_seeds.cpp).
#include "sobol/saltelli.hpp"
#include "tests/sobol/analytic.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace demsa::sobol::test {

struct IshigamiSeedAccuracy {
  double rms = 0.0;                ///< RMS error of S1 and ST over every seed and input
  double worst = 0.0;              ///< the largest max |error| of S1/ST of one seed
  int within = 0;                  ///< seeds whose max |error| of S1/ST is <= 0.005
  int s13_within = 0;              ///< seeds whose S13 is within 0.01 of the analytic value
  double worst_s13 = 0.0;          ///< the largest |error| of S13
  std::vector<double> seed_worst;  ///< max |error| of S1/ST per seed, in the order of the seeds
};

/// Second-order Saltelli designs of Ishigami at `base`, one per seed, analysed without bootstrap.
inline IshigamiSeedAccuracy ishigami_over_seeds(int base, const std::vector<std::uint64_t>& seeds) {
  IshigamiSeedAccuracy a;
  double sum_squares = 0.0;
  for (const std::uint64_t seed : seeds) {
    SaltelliOptions o;
    o.base = base;
    o.dimension = 3;
    o.second_order = true;
    o.seed = seed;
    SobolOptions so;
    so.second_order = true;
    so.interval = SaltelliInterval::none;
    const SobolResult r = sobol_indices(ishigami, saltelli_design(o), so);
    double seed_worst = 0.0;
    for (std::size_t k = 0; k < 3; ++k) {
      const double e1 = r.first[k].value - k_ishigami_s1[k], et = r.total[k].value - k_ishigami_st[k];
      sum_squares += e1 * e1 + et * et;
      seed_worst = std::max({seed_worst, std::abs(e1), std::abs(et)});
    }
    a.seed_worst.push_back(seed_worst);
    a.worst = std::max(a.worst, seed_worst);
    a.within += seed_worst <= 0.005;
    const double e13 = std::abs(r.second.at(1).s.value - k_ishigami_s13);
    a.worst_s13 = std::max(a.worst_s13, e13);
    a.s13_within += e13 <= 0.01;
  }
  a.rms = std::sqrt(sum_squares / (6.0 * static_cast<double>(seeds.size())));
  return a;
}

}  // namespace demsa::sobol::test
