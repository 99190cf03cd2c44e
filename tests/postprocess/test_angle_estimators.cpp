// The two angle estimators (AngleEstimator::paper, ::robust) on synthetic cones of known flank angle, smooth and
// with 1–2 mm of surface jitter (tests/postprocess/synthetic_cone.hpp); the Theil–Sen line on its own.
// The tolerances are on the mean over a few seeds (one cone's own random surface moves both estimators by a few
// tenths of a degree); docs/explanation/benchmarks.md "Angle estimators on synthetic cones" has the full table over 20
// seeds.
#include "postprocess/pile_angle.hpp"

#include "tests/postprocess/synthetic_cone.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace demsa::postprocess {
namespace {

constexpr int k_seeds = 8;

/// Mean error [deg] of an estimator over seeds 1..k_seeds on cones of angle θ and jitter J.
double mean_error(AngleEstimator estimator, double angle, double jitter_mm) {
  PileAngleOptions options;
  options.estimator = estimator;
  double sum = 0.0;
  for (int seed = 1; seed <= k_seeds; ++seed) {
    test::SyntheticConeOptions cone;
    cone.angle_deg = angle;
    cone.jitter = 1e-3 * jitter_mm;
    cone.seed = static_cast<unsigned>(seed);
    const PileAngleResult r = measure_pile_angle(test::make_synthetic_cone(cone), options);
    EXPECT_EQ(r.options.estimator, estimator);
    EXPECT_GT(r.directions_used, 170);
    sum += r.angle - angle;
  }
  return sum / k_seeds;
}

class SmoothCone : public ::testing::TestWithParam<double> {};

TEST_P(SmoothCone, BothEstimatorsWithinHalfADegree) {
  const double angle = GetParam();
  EXPECT_NEAR(mean_error(AngleEstimator::paper, angle, 0.0), 0.0, 0.5) << angle << " deg";
  EXPECT_NEAR(mean_error(AngleEstimator::robust, angle, 0.0), 0.0, 0.5) << angle << " deg";
}

INSTANTIATE_TEST_SUITE_P(From22To41, SmoothCone, ::testing::Values(22.0, 28.0, 34.0, 41.0));

struct RoughCase {
  double angle;
  double jitter_mm;
};

class RoughCone : public ::testing::TestWithParam<RoughCase> {};

TEST_P(RoughCone, RobustWithinHalfADegree) {
  const RoughCase c = GetParam();
  EXPECT_NEAR(mean_error(AngleEstimator::robust, c.angle, c.jitter_mm), 0.0, 0.5)
      << c.angle << " deg, jitter " << c.jitter_mm << " mm";
}

INSTANTIATE_TEST_SUITE_P(OneAndTwoMillimetres, RoughCone,
                         ::testing::Values(RoughCase{25.0, 1.0}, RoughCase{34.0, 1.0}, RoughCase{41.0, 1.0},
                                           RoughCase{25.0, 2.0}, RoughCase{34.0, 2.0}, RoughCase{41.0, 2.0}));

TEST(RoughConePaper, ReadsLowOnTwoMillimetresOfJitter) {
  // The paper's estimator (outermost particle per level, orthogonal line) reads low on a rough flank; the robust
  // one on the same cones does not.
  for (double angle : {25.0, 34.0, 41.0}) {
    const double paper = mean_error(AngleEstimator::paper, angle, 2.0);
    const double robust = mean_error(AngleEstimator::robust, angle, 2.0);
    EXPECT_LT(paper, -0.5) << angle << " deg";
    EXPECT_LT(std::fabs(robust), std::fabs(paper)) << angle << " deg";
  }
}

// Held out: Gaussian normal jitter (sd 1.5 mm), a kind of roughness the robust estimator was not designed on, from
// 22° to 45°. Its cones vary more than the bench's (one reads up to 2° off), hence 40 seeds. Before the sector
// sections (the paper's half-plane cross-section) the mean read +0.52° at 27° and +0.45° at 37°, and the steep flanks'
// upper levels read 0.3–0.4 mm further out than their lower ones.
double held_out_error(double angle, int seeds) {
  PileAngleOptions options;
  options.estimator = AngleEstimator::robust;
  double sum = 0.0;
  for (int seed = 1; seed <= seeds; ++seed) {
    test::SyntheticConeOptions cone;
    cone.angle_deg = angle;
    cone.jitter_sd = 1.5e-3;
    cone.seed = static_cast<unsigned>(seed);
    sum += measure_pile_angle(test::make_synthetic_cone(cone), options).angle - angle;
  }
  return sum / seeds;
}

class HeldOutGaussianJitter : public ::testing::TestWithParam<double> {};

TEST_P(HeldOutGaussianJitter, RobustWithinHalfADegree) {
  const double angle = GetParam();
  EXPECT_NEAR(held_out_error(angle, 40), 0.0, 0.5) << angle << " deg";
}

INSTANTIATE_TEST_SUITE_P(From22To45, HeldOutGaussianJitter, ::testing::Values(22.0, 27.0, 33.5, 37.0, 41.0, 45.0));

TEST(HeldOutGaussianJitter, SteepFlankReadsAsFarOutAtTheTopAsAtTheFoot) {
  // The surface points' mean distance beyond the cone's flank (base radius − height / tan θ) at the three highest
  // levels against the three lowest, over the directions and 20 seeds: the same within 0.15 mm on 41° and 45° cones
  // (the half-plane sections: +0.32 mm and +0.35 mm, which tilt the line by about +0.3°).
  PileAngleOptions options;
  options.estimator = AngleEstimator::robust;
  for (double angle : {41.0, 45.0}) {
    const double tan_theta = std::tan(angle * std::numbers::pi / 180.0);
    double low = 0.0, high = 0.0;
    int n_low = 0, n_high = 0;
    for (int seed = 1; seed <= 20; ++seed) {
      test::SyntheticConeOptions cone;
      cone.angle_deg = angle;
      cone.jitter_sd = 1.5e-3;
      cone.seed = static_cast<unsigned>(seed);
      const PileAngleResult r = measure_pile_angle(test::make_synthetic_cone(cone), options);
      ASSERT_EQ(r.level_heights.size(), 10U);
      for (const BoundaryParticle& b : r.boundary) {
        const double beyond = b.radial - (cone.base_radius - b.height / tan_theta);
        if (b.level <= 2) {
          low += beyond;
          ++n_low;
        } else if (b.level >= 7) {
          high += beyond;
          ++n_high;
        }
      }
    }
    ASSERT_GT(n_low, 0);
    ASSERT_GT(n_high, 0);
    EXPECT_NEAR(high / n_high - low / n_low, 0.0, 0.15e-3) << angle << " deg";
  }
}

TEST(RobustEstimator, LowestLevelClearsTheParticlesOnThePedestalEdge) {
  // A 22° cone of particle set 1 is about 18 mm high: 0.25 h_P lies below 1.5 r_max = 5.25 mm, so the band starts
  // there; a band given explicitly is kept.
  test::SyntheticConeOptions cone;
  cone.angle_deg = 22.0;
  const Particles particles = test::make_synthetic_cone(cone);
  PileAngleOptions options;
  options.estimator = AngleEstimator::robust;
  const PileAngleResult r = measure_pile_angle(particles, options);
  double r_max = 0.0;
  for (std::size_t j : pedestal_particles(particles, options)) r_max = std::max(r_max, particles.radius[j]);
  EXPECT_NEAR(r.level_heights.front(), k_robust_floor_radii * r_max, 1e-12);
  EXPECT_NEAR(*r.options.level_low, k_robust_floor_radii * r_max / r.pile_height, 1e-12);
  EXPECT_GT(*r.options.level_low, k_robust_level_low);
  options.level_low = 0.25;
  EXPECT_NEAR(measure_pile_angle(particles, options).level_heights.front(), 0.25 * r.pile_height, 1e-12);
  // A steep cone's 0.25 h_P is above the floor: the band is the estimator's own.
  cone.angle_deg = 41.0;
  options.level_low.reset();
  EXPECT_EQ(*measure_pile_angle(test::make_synthetic_cone(cone), options).options.level_low, k_robust_level_low);
}

TEST(TheilSen, OneOutlierDoesNotTiltTheLine) {
  // u = 0.04 − 1.5 v at ten heights, one point pushed 2 mm out: Theil–Sen keeps slope and intercept, the orthogonal
  // fit does not.
  std::vector<double> u, v;
  for (int k = 0; k < 10; ++k) {
    v.push_back(0.002 * k);
    u.push_back(0.04 - 1.5 * v.back());
  }
  u[0] += 0.002;
  const TheilSenLine ts = fit_theil_sen_line(u, v);
  EXPECT_NEAR(ts.slope, -1.5, 1e-12);
  EXPECT_NEAR(ts.intercept, 0.04, 1e-12);
  const TlsLine tls = fit_tls_line(u, v);
  EXPECT_GT(std::fabs(tls.dv / tls.du + 1.0 / 1.5), 0.01);
}

TEST(TheilSen, MedianOfPairwiseSlopes) {
  // v = 0, 1, 3 with u = 0, 1, 2: pairwise slopes du/dv 1, 2/3, 1/2 -> 2/3. With a fourth point (u, v) = (5, 4) the
  // six slopes 1, 2/3, 5/4, 1/2, 4/3, 3 have the median (1 + 5/4)/2; the intercept is the median of u − slope·v.
  EXPECT_DOUBLE_EQ(fit_theil_sen_line({0, 1, 2}, {0, 1, 3}).slope, 2.0 / 3.0);
  const TheilSenLine even = fit_theil_sen_line({0, 1, 2, 5}, {0, 1, 3, 4});
  EXPECT_DOUBLE_EQ(even.slope, 1.125);
  // u − 1.125 v: 0, −0.125, −1.375, 0.5 -> median (−0.125 + 0)/2
  EXPECT_DOUBLE_EQ(even.intercept, -0.0625);
}

TEST(AngleEstimatorNames, RoundTripAndListValidNames) {
  for (const std::string& name : angle_estimator_names()) EXPECT_EQ(to_string(angle_estimator_from_string(name)), name);
  try {
    angle_estimator_from_string("best");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "unknown angle estimator 'best' (valid: paper, robust)");
  }
}

TEST(RobustEstimator, ExactConeAndSurfacePointsEcho) {
  // One sphere per direction and level touching a 30° flank at the level height, as in test_pile_angle.cpp's exact
  // cone: the robust estimator measures 30° exactly and echoes the surface points it fitted.
  PileAngleOptions o;
  o.estimator = AngleEstimator::robust;
  o.directions = 36;
  o.levels = 5;
  o.level_low = 0.2;  // the spheres sit at the paper's levels, not at the robust estimator's own band
  o.level_high = 0.75;
  Particles p;
  const double theta = 30.0 * std::numbers::pi / 180.0;
  const double base = 0.04, r = 0.001;
  const double h = base * std::tan(theta);
  auto add = [&p](std::int64_t id, double x, double y, double z) {
    p.id.push_back(id);
    p.type.push_back(1);
    p.x.push_back(x);
    p.y.push_back(y);
    p.z.push_back(z);
    p.radius.push_back(0.001);
  };
  add(1, 0, 0, o.pedestal_top + h - r);
  std::int64_t id = 2;
  for (int i = 0; i < o.directions; ++i) {
    const double phi = 2.0 * std::numbers::pi * i / o.directions;
    for (int k = 0; k < o.levels; ++k) {
      const double zk = h * (0.2 + 0.55 * k / (o.levels - 1));
      const double rho = (h - zk) / std::tan(theta) - r;
      add(id++, rho * std::cos(phi), -rho * std::sin(phi), o.pedestal_top + zk);
    }
  }
  const PileAngleResult res = measure_pile_angle(p, o);
  EXPECT_EQ(res.options.point, BoundaryPointKind::surface);
  EXPECT_EQ(res.directions_used, 36);
  EXPECT_NEAR(res.angle, 30.0, 1e-9);
  EXPECT_NEAR(res.lines[0].height_low, 0.2 * h, 1e-12);
  EXPECT_NEAR(res.lines[0].radial_low, (h - 0.2 * h) / std::tan(theta), 1e-12);
  EXPECT_NEAR(res.lines[0].rms_distance, 0.0, 1e-12);
}

}  // namespace
}  // namespace demsa::postprocess
