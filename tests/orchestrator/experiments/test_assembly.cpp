// Particle assemblies: radii, disc filling without overlaps, the pile schedule, the oedometer lattice, and the
// paper-size presets (generated, not run).
#include "orchestrator/experiments/assembly.hpp"
#include "orchestrator/experiments/oedometer/oedometer.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace demsa {

using namespace demsa::study;
using namespace demsa::experiments;
using namespace demsa::experiments::pile;
using oedometer::OedometerAssembly;
using oedometer::OedometerSettings;
namespace {

TEST(Assembly, TruncatedNormalRadiiAreSeededAndInRange) {
  const RadiusDistribution d{1e-3, 3.5e-3, 2e-3, 0.5e-3};
  const auto a = truncated_normal_radii(d, 20000, 5);
  EXPECT_EQ(a, truncated_normal_radii(d, 20000, 5));
  EXPECT_NE(a, truncated_normal_radii(d, 20000, 6));
  for (double r : a) {
    ASSERT_GE(r, d.r_min);
    ASSERT_LE(r, d.r_max);
  }
  // Mean of N(2, 0.5) truncated to [1, 3.5] mm: mu + sd (phi(a) - phi(b)) / (Phi(b) - Phi(a)) with a = -2, b = 3:
  // phi(-2) = 0.0539910, phi(3) = 0.0044318, Phi(3) - Phi(-2) = 0.9986501 - 0.0227501 = 0.9759 -> 2.025391 mm.
  const double mean = std::accumulate(a.begin(), a.end(), 0.0) / a.size();
  EXPECT_NEAR(mean, 2.025391e-3, 3 * 0.5e-3 / std::sqrt(20000.0));
}

TEST(Assembly, DiscRingsFollowTheAnnulusRule) {
  // Equal radii r = 0.9 with r_U = 1: rings at 0, 2, 4 for a disc radius of 5 (ring 3 at 6 would stick out).
  std::vector<double> radii(1000, 0.9);
  std::size_t next = 0;
  const Disc disc = fill_disc(radii, next, 1.0, 5.0, 0.0);
  ASSERT_FALSE(disc.empty());
  // Ring k of radius 2k holds floor(pi / asin(0.9/(2k))) spheres: pi/asin(0.45) = 6.73, pi/asin(0.225) = 13.84.
  EXPECT_EQ(disc.size(), 1u + 6u + 13u);
  EXPECT_EQ(next, disc.size());
  EXPECT_GE(min_pair_gap(disc), -1e-12);
  for (const Particle& p : disc) EXPECT_LE(std::hypot(p.x, p.y) + p.radius, 5.0 + 1e-12);
}

TEST(Assembly, MinPairGapFindsOverlap) {
  std::vector<Particle> ps{{0, 0, 0, 1.0}, {1.5, 0, 0, 1.0}, {10, 0, 0, 1.0}};
  EXPECT_DOUBLE_EQ(min_pair_gap(ps), -0.5);
  ps[1].x = 2.25;
  EXPECT_DOUBLE_EQ(min_pair_gap(ps), 0.25);
  EXPECT_TRUE(std::isinf(min_pair_gap({{0, 0, 0, 1.0}})));
}

/// Checks a pile: counts, radii, inside the disc radius, no overlaps within the column or within any disc, and
/// the heights of the schedule.
void check_pile(const PileSettings& s, std::uint64_t seed) {
  const PileAssembly a = pile::build_assembly(s, seed);
  EXPECT_EQ(a.particles(), s.particles);
  std::vector<Particle> column;
  for (std::size_t k = 0; k < a.discs.size(); ++k) {
    const Disc& d = a.discs[k];
    EXPECT_GE(min_pair_gap(d), 0.0) << "disc " << k;
    for (const Particle& p : d) {
      ASSERT_LE(std::hypot(p.x, p.y) + p.radius, s.disc_radius + 1e-12);
      ASSERT_GE(p.radius, s.radii.r_min);
      ASSERT_LE(p.radius, s.radii.r_max);
      if (static_cast<int>(k) < a.column_discs) {
        EXPECT_DOUBLE_EQ(p.z, s.pedestal_height + s.radii.r_max + 2 * s.radii.r_max * static_cast<double>(k));
        column.push_back(p);
      } else {
        EXPECT_DOUBLE_EQ(p.z, s.pedestal_height + s.fill_height);
      }
      // Above the pedestal top.
      ASSERT_GE(p.z - p.radius, s.pedestal_height);
    }
  }
  EXPECT_GE(min_pair_gap(column), 0.0);
  EXPECT_EQ(static_cast<int>(column.size()), a.column_particles());
  // Column: discs up to the fill height h_fu, no more.
  const double top = s.pedestal_height + s.radii.r_max + 2 * s.radii.r_max * (a.column_discs - 1);
  EXPECT_LE(top, s.pedestal_height + s.fill_height + 1e-12);
  if (static_cast<int>(a.discs.size()) > a.column_discs) {
    EXPECT_GT(top + 2 * s.radii.r_max, s.pedestal_height + s.fill_height);
  }
}

TEST(Assembly, PaperPileSet1HasSixThousandValidParticles) {
  PileSettings s;  // defaults = set 1
  s.particles = 6000;
  s.radii = {1e-3, 3.5e-3, 2e-3, 0.5e-3};
  check_pile(s, 12345);
  const PileAssembly a = pile::build_assembly(s, 12345);
  EXPECT_EQ(a.column_discs, 14);  // z = 5 + 3.5 + 7k mm <= 105 mm -> k = 0..13
}

TEST(Assembly, PaperPileSet2HasEightThousandValidParticles) {
  PileSettings s;
  s.particles = 8000;
  s.radii = {0.8e-3, 2.5e-3, 1.5e-3, 0.35e-3};
  check_pile(s, 12345);
  const PileAssembly a = pile::build_assembly(s, 12345);
  EXPECT_EQ(a.column_discs, 20);  // z = 5 + 2.5 + 5k mm <= 105 mm -> k = 0..19
}

TEST(Assembly, PileIsIdenticalForTheSameSeed) {
  PileSettings s;
  s.particles = 500;
  const PileAssembly a = pile::build_assembly(s, 3), b = pile::build_assembly(s, 3);
  ASSERT_EQ(a.discs.size(), b.discs.size());
  for (std::size_t k = 0; k < a.discs.size(); ++k)
    for (std::size_t i = 0; i < a.discs[k].size(); ++i) {
      EXPECT_EQ(a.discs[k][i].x, b.discs[k][i].x);
      EXPECT_EQ(a.discs[k][i].radius, b.discs[k][i].radius);
    }
}

TEST(Assembly, PaperOedometerHas4642ValidParticles) {
  const OedometerSettings s =
      oedometer::settings(parse_study("[study]\nname = \"p\"\nexperiment = \"oedometer\"\n[parameters]\n"
                                      "E = { low = 1e8, high = 1e9 }\n[oedometer]\npreset = \"paper\"\n",
                                      "study.toml"));
  ASSERT_EQ(s.particles, 4642);
  // Paper §4, assembly one: e = V_P / V_S = 0.66 with V_P = 10 x 10 x 5 cm^3 - V_S, so V_S = 301.2 cm^3 and
  // E[r^3] = 15.49 mm^3. The preset's truncated normal has E[r^3] = 15.496 mm^3 (study_config.cpp): the sampler
  // must reproduce it (sd of r^3 < 5 mm^3, so 4 standard errors over 200000 radii are < 0.045 mm^3)...
  const std::vector<double> many = truncated_normal_radii(s.radii, 200000, 1);
  double cube_mean = 0;
  for (const double r : many) cube_mean += r * r * r / static_cast<double>(many.size());
  EXPECT_NEAR(cube_mean, 15.496e-9, 0.045e-9);
  const OedometerAssembly a = oedometer::build_assembly(s, 12345);
  // ... and the 4642 particles of a study fit in the 500 cm^3 with the paper's void ratio (4 standard errors:
  // 4 x 1.66 x 4.6 / (15.5 sqrt(4642)) = 0.03).
  const double void_ratio = (0.1 * 0.1 * 0.05 - a.solid_volume) / a.solid_volume;
  EXPECT_NEAR(void_ratio, 0.66, 0.03);
  ASSERT_EQ(a.particles.size(), 4642u);
  EXPECT_GE(min_pair_gap(a.particles), 0.1 * s.radii.r_max - 1e-12);  // the lattice's cell gap at least
  double volume = 0;
  for (const Particle& p : a.particles) {
    ASSERT_GE(p.x - p.radius, -s.box_side / 2);
    ASSERT_LE(p.x + p.radius, s.box_side / 2);
    ASSERT_GE(p.y - p.radius, -s.box_side / 2);
    ASSERT_LE(p.y + p.radius, s.box_side / 2);
    ASSERT_GT(p.z - p.radius, 0.0);
    volume += 4.0 / 3.0 * M_PI * p.radius * p.radius * p.radius;
  }
  EXPECT_NEAR(a.solid_volume, volume, 1e-15);
  // cell = 2 * 3.0 + 0.3 = 6.3 mm; floor((100 - 0.3) / 6.3) = 15 per row.
  EXPECT_EQ(a.per_layer, 225);
  EXPECT_EQ(a.layers, (4642 + 224) / 225);
  for (const Particle& p : a.particles) {
    ASSERT_GE(p.radius, 2.0e-3);
    ASSERT_LE(p.radius, 3.0e-3);
  }
}

}  // namespace
}  // namespace demsa
