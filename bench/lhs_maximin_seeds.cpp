// 160 x 7 maximin LHS over seeds: minimum distance on the unit cube and CPU time per seed, with the default
// iteration budget (docs/explanation/benchmarks.md, section "Reproducible designs"). A plain executable: the numbers
// are the designs' quality, the times a side note (CPU time of this process, so a loaded machine inflates them little).
//   build-*/bench/lhs_maximin_seeds [FIRST_SEED] [LAST_SEED] [ITERATIONS]
// The OpenTURNS side: bench/lhs-maximin-openturns.py.
#include "sobol/design.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <vector>

int main(int argc, char** argv) {
  using namespace demsa::sobol;
  const int first = argc > 1 ? std::atoi(argv[1]) : 1;
  const int last = argc > 2 ? std::atoi(argv[2]) : 20;
  DesignOptions o;
  o.kind = DesignKind::lhs_maximin;
  o.samples = 160;
  o.dimension = 7;
  if (argc > 3) o.iterations = std::atoi(argv[3]);
  std::vector<double> distances, seconds;
  for (int seed = first; seed <= last; ++seed) {
    o.seed = static_cast<std::uint64_t>(seed);
    const std::clock_t start = std::clock();
    const DesignResult r = make_design(o, false);
    const double cpu = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    const double d = min_distance(r.points);
    fmt::print("seed {:2d}  min distance {:.4f}  iterations {:3d} ({})  cpu {:.2f} s\n", seed, d, r.iterations,
               to_string(r.stop), cpu);
    distances.push_back(d);
    seconds.push_back(cpu);
  }
  std::vector<double> sorted = seconds;
  std::sort(sorted.begin(), sorted.end());
  double mean = 0.0;
  for (const double d : distances) mean += d / static_cast<double>(distances.size());
  fmt::print("worst {:.4f}  mean {:.4f}  median cpu {:.2f} s  max cpu {:.2f} s\n",
             *std::min_element(distances.begin(), distances.end()), mean, sorted[sorted.size() / 2], sorted.back());
}
