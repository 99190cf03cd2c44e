// Rayleigh time, time step choice and the LIGGGHTS limits that demsa refuses before a run.
#include "orchestrator/experiments/oedometer/oedometer.hpp"
#include "orchestrator/experiments/physics.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace demsa {

using namespace demsa::study;
using namespace demsa::experiments;
namespace {

TEST(Physics, RayleighTimeMatchesHandValue) {
  // r = 1 mm, E = 1e8 Pa, nu = 0.3, rho = 2500: G = E/2.6, T_R = pi r sqrt(rho/G) / (0.1631 nu + 0.8766)
  // = 2.736629791946464e-05 s (evaluated independently).
  EXPECT_NEAR(rayleigh_time(1e-3, 1e8, 0.3, 2500), 2.736629791946464e-05, 1e-15);
  EXPECT_DOUBLE_EQ(shear_modulus(2.6e8, 0.3), 1e8);
  // T_R scales with r and 1/sqrt(E).
  EXPECT_NEAR(rayleigh_time(2e-3, 4e8, 0.3, 2500), rayleigh_time(1e-3, 1e8, 0.3, 2500), 1e-18);
}

TEST(Physics, TimestepIsFractionOfRayleighOrFixed) {
  Material m;
  TimestepSettings s;
  const TimestepChoice r = choose_timestep(s, m, 1e-3);
  EXPECT_DOUBLE_EQ(r.dt, 0.15 * r.rayleigh_time);
  EXPECT_DOUBLE_EQ(r.fraction_of_rayleigh(), 0.15);
  s.mode = TimestepMode::fixed;
  s.value = 1e-6;
  const TimestepChoice f = choose_timestep(s, m, 1e-3);
  EXPECT_DOUBLE_EQ(f.dt, 1e-6);
  EXPECT_DOUBLE_EQ(f.rayleigh_time, r.rayleigh_time);
}

TEST(Physics, AppendIntervalIsFallTimeOfTwoUpperRadii) {
  const double t = pile::disc_append_interval(3.5e-3, 9.81);
  EXPECT_NEAR(t, 0.037777178144788405, 1e-15);
  EXPECT_NEAR(0.5 * 9.81 * t * t, 2 * 3.5e-3, 1e-15);  // a disc released at rest falls 2 r_U
  EXPECT_EQ(steps_for(t, 1e-5, "t"), 3778);
  EXPECT_EQ(steps_for(0.0, 1e-5, "t"), 1);
}

TEST(Physics, ValidSettingsHaveNoViolations) {
  StudyConfig c;
  const TimestepChoice ts = choose_timestep(c.timestep, c.material, 1e-3);
  EXPECT_TRUE(liggghts_limit_violations(c.material, ts).empty());
}

TEST(Physics, TooLargeTimestepIsRefusedWithReason) {
  StudyConfig c;
  c.timestep.mode = TimestepMode::fixed;
  c.timestep.value = 1e-5;  // 0.365 T_R at r = 1 mm
  const TimestepChoice ts = choose_timestep(c.timestep, c.material, 1e-3);
  const auto v = liggghts_limit_violations(c.material, ts);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_NE(v[0].find("0.365 Rayleigh times"), std::string::npos) << v[0];
  EXPECT_NE(v[0].find("above 0.3 T_R"), std::string::npos) << v[0];
}

TEST(Physics, YoungsModulusOutsideLiggghtsRangeNeedsFlag) {
  StudyConfig c;
  Material m = c.material;
  m.E = 2e6;
  auto v = liggghts_limit_violations(m, choose_timestep(c.timestep, m, 1e-3));
  ASSERT_EQ(v.size(), 1u);
  EXPECT_NE(v[0].find("soft_particles = true"), std::string::npos) << v[0];
  m.soft_particles = true;
  EXPECT_TRUE(liggghts_limit_violations(m, choose_timestep(c.timestep, m, 1e-3)).empty());
  m.E = 2e9;
  v = liggghts_limit_violations(m, choose_timestep(c.timestep, m, 1e-3));
  ASSERT_EQ(v.size(), 1u);
  EXPECT_NE(v[0].find("hard_particles = true"), std::string::npos) << v[0];
  m.E = 1e9;  // the bound itself is accepted by LIGGGHTS
  EXPECT_TRUE(liggghts_limit_violations(m, choose_timestep(c.timestep, m, 1e-3)).empty());
}

TEST(Physics, ServoSpeedAboveHalfSkinPerStepIsRefused) {
  StudyConfig c;
  c.experiment = "oedometer";
  c.timestep.mode = TimestepMode::fixed;
  c.timestep.value = 1e-5;
  c.timestep.skin = 1e-3;  // skin / (2 dt) = 50 m/s
  Material m = c.material;
  const TimestepChoice ts = choose_timestep(c.timestep, m, 3e-3);
  oedometer::settings(c).servo_vel_max = 49.0;
  EXPECT_TRUE(oedometer::experiment().limit_violations(c, m, ts).empty());
  oedometer::settings(c).servo_vel_max = 50.0;
  const auto v = oedometer::experiment().limit_violations(c, m, ts);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_NE(v[0].find("skin/(2 dt) = 50 m/s"), std::string::npos) << v[0];
  oedometer::settings(c).plate_mode = oedometer::PlateMode::trial_step;  // no servo, no servo limit
  EXPECT_TRUE(oedometer::experiment().limit_violations(c, m, ts).empty());
}

}  // namespace
}  // namespace demsa
