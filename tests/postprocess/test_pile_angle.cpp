// Angle of repose (paper §3.3) on synthetic piles of known flank angle and on a real LIGGGHTS pile.
#include "postprocess/pile_angle.hpp"

#include "postprocess/dump.hpp"
#include "support/test_support.hpp"
#include "synthetic_pile.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace demsa::postprocess {
namespace {

class SyntheticConeAngle : public ::testing::TestWithParam<double> {};

TEST_P(SyntheticConeAngle, MeasuredAngleWithinOneDegree) {
  test::SyntheticPileOptions pile;
  pile.angle_deg = GetParam();
  const Particles particles = test::make_synthetic_pile(pile);
  const PileAngleResult r = measure_pile_angle(particles, {});
  EXPECT_NEAR(r.angle, pile.angle_deg, 1.0) << "sd " << r.angle_sd << " used " << r.directions_used;
  EXPECT_EQ(r.directions_used, 180);
  EXPECT_LT(r.particles_on_pedestal, r.particles_total);  // the rolled-off ones are dropped
  // h_P: the outline's top plus at most the noise.
  const double top = test::synthetic_pile_profile(pile, 0.0);
  EXPECT_NEAR(r.pile_height, top, 0.5e-3);
  EXPECT_DOUBLE_EQ(r.angle_error, (33.5 - r.angle) * (33.5 - r.angle));
}

TEST_P(SyntheticConeAngle, OtherSeedAndFinerLevels) {
  test::SyntheticPileOptions pile;
  pile.angle_deg = GetParam();
  pile.seed = 7;
  PileAngleOptions options;
  options.levels = 20;
  const PileAngleResult r = measure_pile_angle(test::make_synthetic_pile(pile), options);
  EXPECT_NEAR(r.angle, pile.angle_deg, 1.0) << "sd " << r.angle_sd;
}

INSTANTIATE_TEST_SUITE_P(PaperRange, SyntheticConeAngle, ::testing::Values(25.0, 30.0, 33.5, 38.0));

}  // namespace
}  // namespace demsa::postprocess

namespace demsa::postprocess {
namespace {

TEST(PileAngle, RealLiggghtsPile) {
  const Particles p = read_particles(test::data_path("postprocess/liggghts_pile/pile_final.dump"));
  ASSERT_EQ(p.size(), 600u);
  const PileAngleResult r = measure_pile_angle(p, {});
  EXPECT_EQ(r.particles_on_pedestal, 591u);
  // h_P independently: the highest z + r above 5 mm (pileinfo of the run: 21.65 mm).
  EXPECT_NEAR(r.pile_height, 0.02165, 0.00001);
  EXPECT_GT(r.angle, 20.0);
  EXPECT_LT(r.angle, 45.0);
  EXPECT_GT(r.directions_used, 150);
}

TEST(PileAngle, TlsLineIsOrthogonalNotOrdinary) {
  // Points on z = 2 − u with symmetric perpendicular offsets: TLS recovers slope −1 exactly, while ordinary least
  // squares on v would be biased by the offsets in u.
  std::vector<double> u, v;
  for (int k = 0; k < 5; ++k) {
    const double t = k;
    for (double off : {-0.1, 0.1}) {
      u.push_back(t + off / std::sqrt(2.0));
      v.push_back(2.0 - t + off / std::sqrt(2.0));
    }
  }
  const TlsLine l = fit_tls_line(u, v);
  EXPECT_NEAR(l.dv / l.du, -1.0, 1e-12);
  EXPECT_NEAR(l.rms_distance, 0.1, 1e-12);
  EXPECT_NEAR(l.u0, 2.0, 1e-12);
  EXPECT_NEAR(l.v0, 0.0, 1e-12);
}

class ExactCone : public ::testing::TestWithParam<BoundaryPointKind> {};

TEST_P(ExactCone, EveryDirectionMeasuresTheFlank) {
  // Spheres of one radius whose outermost point lies exactly on a 30° flank at every level height, one per
  // direction and level: centres and surface points both lie on lines parallel to the flank, so every direction
  // measures 30° up to rounding.
  PileAngleOptions o;
  o.point = GetParam();
  o.directions = 36;
  o.levels = 5;
  Particles p;
  const double theta = 30.0 * std::numbers::pi / 180.0;
  const double base = 0.04, r = 0.001;
  const double h = base * std::tan(theta);
  // the apex particle defines h_P: top at h above the pedestal top
  auto add = [&p](std::int64_t id, double x, double y, double z, double rad) {
    p.id.push_back(id);
    p.type.push_back(1);
    p.x.push_back(x);
    p.y.push_back(y);
    p.z.push_back(z);
    p.radius.push_back(rad);
  };
  add(1, 0, 0, o.pedestal_top + h - r, r);
  std::int64_t id = 2;
  for (int i = 0; i < o.directions; ++i) {
    const double phi = 2.0 * std::numbers::pi * i / o.directions;
    for (int k = 0; k < o.levels; ++k) {
      const double zk = h * (0.2 + 0.55 * k / (o.levels - 1));
      const double rho = (h - zk) / std::tan(theta) - r;  // centre at the level height, touching the flank
      add(id++, rho * std::cos(phi), -rho * std::sin(phi), o.pedestal_top + zk, r);
    }
  }
  const PileAngleResult res = measure_pile_angle(p, o);
  EXPECT_NEAR(res.pile_height, h, 1e-15);
  EXPECT_EQ(res.directions_used, 36);
  EXPECT_NEAR(res.angle, 30.0, 1e-9);
  EXPECT_NEAR(res.angle_sd, 0.0, 1e-9);
  ASSERT_EQ(res.boundary.size(), 36u * 5u);
  EXPECT_EQ(res.boundary[0].direction, 0);
  EXPECT_EQ(res.boundary[0].id, 2);
  EXPECT_NEAR(res.lines[9].phi, 90.0, 1e-12);
  EXPECT_NEAR(res.lines[9].ey, -1.0, 1e-12);
  EXPECT_NEAR(res.lines[0].height_low, 0.2 * h, 1e-12);
  EXPECT_NEAR(res.lines[0].height_high, 0.75 * h, 1e-12);
  EXPECT_NEAR(res.angle_error, 3.5 * 3.5, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(BothPoints, ExactCone,
                         ::testing::Values(BoundaryPointKind::centre, BoundaryPointKind::surface));

TEST(PileAngleErrors, ABowlIsNoPile) {
  // issue 45: particles whose outermost edge rises outward (a bowl, a ring left by a pile that slid off) measured a
  // negative angle of repose, stored as the case's angle.
  PileAngleOptions o;
  o.directions = 36;
  o.levels = 5;
  o.pedestal_radius = 0.06;
  Particles p;
  const double r = 0.001, h = 0.02, slope = std::tan(30.0 * std::numbers::pi / 180.0);
  std::int64_t id = 1;
  const auto add = [&](double rho, double phi, double z) {
    p.id.push_back(id++);
    p.type.push_back(1);
    p.x.push_back(rho * std::cos(phi));
    p.y.push_back(-rho * std::sin(phi));
    p.z.push_back(o.pedestal_top + z);
    p.radius.push_back(r);
  };
  add(0.005 + h / slope, 0.0, h - r);  // the rim's top defines h_P
  for (int i = 0; i < o.directions; ++i)
    for (int k = 0; k < o.levels; ++k) {
      const double zk = h * (0.2 + 0.55 * k / (o.levels - 1));
      add(0.005 + zk / slope, 2.0 * std::numbers::pi * i / o.directions, zk);
    }
  try {
    const PileAngleResult res = measure_pile_angle(p, o);
    ADD_FAILURE() << "a bowl measured an angle of repose of " << res.angle << "°";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no pile to measure"), std::string::npos) << e.what();
  }
}

TEST(PileAngleErrors, NothingOnThePedestal) {
  Particles p;
  p.id = {1};
  p.type = {1};
  p.x = {0.2};
  p.y = {0.0};
  p.z = {0.01};
  p.radius = {0.001};
  EXPECT_THROW(measure_pile_angle(p, {}), InputError);
}

TEST(PileAngleErrors, FlatLayerHasNoLines) {
  Particles p;
  for (int k = 0; k < 3; ++k) {
    p.id.push_back(k + 1);
    p.type.push_back(1);
    p.x.push_back(0.01 * k);
    p.y.push_back(0.0);
    p.z.push_back(0.006);
    p.radius.push_back(0.001);
  }
  try {
    measure_pile_angle(p, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a pile"), std::string::npos) << e.what();
  }
}

TEST(PileAngleOptionsLevels, UnsetLevelsTakeTheEstimatorsBand) {
  PileAngleOptions o;
  EXPECT_FALSE(o.level_low.has_value());
  EXPECT_DOUBLE_EQ(o.low_level(), 0.20);  // paper §3.3
  EXPECT_DOUBLE_EQ(o.high_level(), 0.75);
  o.estimator = AngleEstimator::robust;
  EXPECT_DOUBLE_EQ(o.low_level(), k_robust_level_low);
  EXPECT_DOUBLE_EQ(o.high_level(), k_robust_level_high);
  o.level_high = 0.7;  // a level given wins; the other end stays the estimator's
  EXPECT_DOUBLE_EQ(o.low_level(), k_robust_level_low);
  EXPECT_DOUBLE_EQ(o.high_level(), 0.7);
  // The result echoes the band it measured on, and its level heights follow it.
  const Particles particles = test::make_synthetic_pile({});
  PileAngleOptions robust;
  robust.estimator = AngleEstimator::robust;
  const PileAngleResult r = measure_pile_angle(particles, robust);
  ASSERT_TRUE(r.options.level_low && r.options.level_high);
  EXPECT_DOUBLE_EQ(*r.options.level_low, k_robust_level_low);
  EXPECT_DOUBLE_EQ(*r.options.level_high, k_robust_level_high);
  EXPECT_DOUBLE_EQ(r.level_heights.front(), k_robust_level_low * r.pile_height);
  EXPECT_DOUBLE_EQ(r.level_heights.back(), k_robust_level_high * r.pile_height);
  const PileAngleResult paper = measure_pile_angle(particles, {});
  EXPECT_DOUBLE_EQ(*paper.options.level_low, 0.20);
  EXPECT_DOUBLE_EQ(paper.level_heights.back(), 0.75 * paper.pile_height);
}

TEST(PileAngleErrors, OptionsValidateNamesField) {
  PileAngleOptions o;
  o.levels = 1;
  EXPECT_EQ(test::message_of<std::invalid_argument>([&] { o.validate(); }),
            "PileAngleOptions.levels = 1: must be at least 2");
  o = {};
  o.level_high = 0.1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  EXPECT_THROW(boundary_point_kind_from_string("middle"), std::invalid_argument);
  EXPECT_EQ(boundary_point_kind_from_string("centre"), BoundaryPointKind::centre);
}

}  // namespace
}  // namespace demsa::postprocess
