// The draw-down's measurement (postprocess/drawdown.hpp): the slope of a synthetic box of known angles, and the
// discharge rate of a known record.
#include "postprocess/drawdown.hpp"
#include "postprocess/error.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace demsa {
namespace {

constexpr double k_deg = std::numbers::pi / 180.0;

/// Spheres of radius 2 mm filling the box (width 102 mm, slot 30 mm, depth 20 mm) under a surface that rises from
/// each slot edge at `left` and `right` degrees, with ids from 101 on; ids 1..100 are a floor layer at z = 2 mm
/// that reaches over the whole box (the measurement must leave it out).
postprocess::Particles box(double left, double right, unsigned seed) {
  postprocess::Particles p;
  const double r = 2e-3;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.4e-3, 0.4e-3);
  long id = 0;
  for (int i = 0; i < 100; ++i) {
    p.id.push_back(++id), p.type.push_back(1), p.x.push_back(-0.05 + 0.001 * i), p.y.push_back(0.01);
    p.z.push_back(0.002), p.radius.push_back(r);
  }
  id = 100;
  for (double x = -0.049; x <= 0.049; x += 2 * r)
    for (double y = 0.002; y < 0.02; y += 2 * r) {
      const double edge = std::abs(x) - 0.015;
      if (edge < 0) continue;  // the slot is empty
      const double surface = 0.004 + edge * std::tan((x < 0 ? left : right) * k_deg);
      for (double z = 0.006; z + r <= surface; z += 2 * r) {
        p.id.push_back(++id), p.type.push_back(1), p.x.push_back(x + jitter(rng)), p.y.push_back(y);
        p.z.push_back(z), p.radius.push_back(r);
      }
      // The top particle sits on the surface.
      p.id.push_back(++id), p.type.push_back(1), p.x.push_back(x), p.y.push_back(y), p.z.push_back(surface - r);
      p.radius.push_back(r);
    }
  return p;
}

TEST(Drawdown, SlopeAnglesOfASyntheticBox) {
  postprocess::DrawdownSlopeOptions o;
  o.skip_ids = 100;
  for (const auto& [left, right] : {std::pair{30.0, 40.0}, std::pair{25.0, 25.0}}) {
    const postprocess::DrawdownSlope s = postprocess::measure_drawdown_slope(box(left, right, 3), o, 2500);
    EXPECT_NEAR(s.angle_left, left, 1.0);
    EXPECT_NEAR(s.angle_right, right, 1.0);
    EXPECT_NEAR(s.angle, 0.5 * (left + right), 1.0);
    EXPECT_EQ(s.slices_left.size(), 5u);
  }
  // The floor layer's ids are left out of the material in the box.
  const long skipped = postprocess::measure_drawdown_slope(box(30, 40, 3), o, 2500).particles_left;
  o.skip_ids = 0;
  EXPECT_EQ(postprocess::measure_drawdown_slope(box(30, 40, 3), o, 2500).particles_left, skipped + 100);
}

TEST(Drawdown, AnEmptyBoxHasNoSlope) {
  postprocess::Particles none;
  EXPECT_THROW(postprocess::measure_drawdown_slope(none, {}, 2500), postprocess::InputError);
}

TEST(Drawdown, DischargeRateIsTheSteadyFlowsSlope) {
  test::TempDir tmp;
  // 0.3 kg/s from t = 0.1 s to 0.6 s, then nothing: 0.15 kg in all; the start and end are left out.
  std::string text = "# t_open_s discharged_kg atoms\n";
  for (int k = 0; k <= 100; ++k) {
    const double t = 0.01 * k;
    const double m = t < 0.1 ? 0.0 : t < 0.6 ? 0.3 * (t - 0.1) : 0.15;
    text += fmt::format("{} {} {}\n", t, m, 1000);
  }
  test::write_file(tmp / "d.txt", text);
  const postprocess::DischargeRecord r = postprocess::read_discharge(tmp / "d.txt");
  EXPECT_NEAR(postprocess::discharge_rate(r), 0.3, 1e-9);
  test::write_file(tmp / "bad.txt", "0 0 10\n0.1 0.01 9\n0.05 0.02 8\n");
  EXPECT_THROW(postprocess::read_discharge(tmp / "bad.txt"), postprocess::ParseError);
  test::write_file(tmp / "none.txt", "0 0 10\n0.1 0 10\n");
  EXPECT_THROW(postprocess::discharge_rate(postprocess::read_discharge(tmp / "none.txt")), postprocess::InputError);
}

}  // namespace
}  // namespace demsa
