// Accuracy of the two angle-of-repose estimators (postprocess/pile_angle.hpp, AngleEstimator) on synthetic cones of
// known flank angle (tests/postprocess/synthetic_cone.hpp), smooth and with surface jitter (docs/benchmarks.md,
// "Angle estimators on synthetic cones"). For each angle and jitter: the mean error (bias), the standard deviation
// over the seeds (spread) and the largest |error| of each estimator, default options otherwise (180 directions,
// 10 levels between 0.2 h_P and 0.75 h_P for paper (centre points), 0.25 and 0.8 h_P for robust).
//
// usage: build/bench/angle_estimators [SEEDS]   (default 20)
#include "postprocess/pile_angle.hpp"
#include "tests/postprocess/synthetic_cone.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace {

struct Stats {
  double bias = 0, sd = 0, worst = 0;
};

Stats stats_of(const std::vector<double>& errors) {
  Stats s;
  for (double e : errors) s.bias += e;
  s.bias /= static_cast<double>(errors.size());
  for (double e : errors) {
    s.sd += (e - s.bias) * (e - s.bias);
    s.worst = std::max(s.worst, std::fabs(e));
  }
  s.sd = errors.size() > 1 ? std::sqrt(s.sd / static_cast<double>(errors.size() - 1)) : 0.0;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  namespace pp = demsa::postprocess;
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 20;
  if (seeds < 2) {
    fmt::print(stderr, "usage: angle_estimators [SEEDS >= 2]\n");
    return 2;
  }
  pp::PileAngleOptions paper;
  pp::PileAngleOptions robust;
  robust.estimator = pp::AngleEstimator::robust;
  fmt::print(
      "| angle [deg] | jitter [mm] | paper bias | paper sd | paper max abs | robust bias | robust sd | robust max abs "
      "|\n");
  fmt::print("|---|---|---|---|---|---|---|---|\n");
  double worst_paper_bias[3] = {0, 0, 0}, worst_robust_bias[3] = {0, 0, 0};
  for (double angle : {22.0, 25.0, 28.0, 31.0, 34.0, 37.0, 41.0}) {
    for (int jitter_mm = 0; jitter_mm <= 2; ++jitter_mm) {
      std::vector<double> e_paper, e_robust;
      for (int seed = 1; seed <= seeds; ++seed) {
        demsa::test::SyntheticConeOptions cone;
        cone.angle_deg = angle;
        cone.jitter = 1e-3 * jitter_mm;
        cone.seed = static_cast<unsigned>(seed);
        const pp::Particles particles = demsa::test::make_synthetic_cone(cone);
        e_paper.push_back(pp::measure_pile_angle(particles, paper).angle_mean - angle);
        e_robust.push_back(pp::measure_pile_angle(particles, robust).angle_mean - angle);
      }
      const Stats p = stats_of(e_paper), r = stats_of(e_robust);
      const auto j = static_cast<std::size_t>(jitter_mm);
      if (std::fabs(p.bias) > std::fabs(worst_paper_bias[j])) worst_paper_bias[j] = p.bias;
      if (std::fabs(r.bias) > std::fabs(worst_robust_bias[j])) worst_robust_bias[j] = r.bias;
      fmt::print("| {:.0f} | {} | {:+.2f} | {:.2f} | {:.2f} | {:+.2f} | {:.2f} | {:.2f} |\n", angle, jitter_mm, p.bias,
                 p.sd, p.worst, r.bias, r.sd, r.worst);
    }
  }
  for (std::size_t j = 0; j < 3; ++j)
    fmt::print("jitter {} mm: largest |bias| paper {:+.2f} deg, robust {:+.2f} deg ({} seeds per angle)\n", j,
               worst_paper_bias[j], worst_robust_bias[j], seeds);
  return 0;
}
