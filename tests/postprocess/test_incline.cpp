// The incline's onsets (postprocess/incline.hpp): synthetic probes that start from rest at a known tilt under the
// excess force of a slowly tilting plate; the measured onset, corrected for the lag of that start, is the known tilt.
#include "postprocess/error.hpp"
#include "postprocess/incline.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace demsa {
namespace {

constexpr double k_g = 9.81;

/// Down-slope position of a probe that starts at tilt `onset` [deg] on a plate tilting at `rate` [deg/s], at tilt
/// `tilt`: the exact integral of a = k g (sin θ − tan θ_c cos θ) twice in time (small steps), so that the test does
/// not assume the approximation the measurement corrects with.
double position(double tilt, double onset, double k, double rate) {
  if (tilt <= onset) return 0.0;
  const double omega = rate * std::numbers::pi / 180.0;
  const double mu = std::tan(onset * std::numbers::pi / 180.0);
  const double steps = 20000;
  const double t_end = (tilt - onset) / rate;
  const double h = t_end / steps;
  double x = 0, v = 0;
  for (int i = 0; i < steps; ++i) {
    const double theta = onset * std::numbers::pi / 180.0 + omega * (i + 0.5) * h;
    const double a = k * k_g * (std::sin(theta) - mu * std::cos(theta));
    v += a * h;
    x += v * h;
  }
  return x;
}

/// A dump of two probes (1 rolling from 20°, 2 sliding from 40°) recorded every 0.25° from step 1000 on (dt 1e-5,
/// tilt 5 deg/s: 5000 steps a record), plus a third, sliding, probe that never moves.
std::string dump(double rate) {
  std::string text;
  const double dt = 1e-5;
  const long per_record = std::lround(0.25 / rate / dt);
  for (long k = 0; k * 0.25 <= 60.0; ++k) {
    const double tilt = 0.25 * static_cast<double>(k);
    text += fmt::format(
        "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS ff ff ff\n-0.02 0.7\n-0.1 0.1\n"
        "-0.002 0.05\nITEM: ATOMS id type x y z radius vx vy vz\n",
        1000 + k * per_record);
    text += fmt::format("1 1 {:.12g} -0.01 0.002 0.002 0 0 0\n", position(tilt, 20.0, 5.0 / 7.0, rate));
    text += fmt::format("2 1 {:.12g} 0 0.002 0.002 0 0 0\n", position(tilt, 40.0, 1.0, rate));
    text += "3 1 0 0.01 0.002 0.002 0 0 0\n";
  }
  return text;
}

TEST(Incline, CorrectedOnsetsAreTheTiltsAtWhichTheProbesStarted) {
  for (const double rate : {2.5, 5.0, 10.0}) {
    test::TempDir tmp;
    test::write_file(tmp / "probes.dump", dump(rate));
    postprocess::InclineOptions o;
    o.tilt_rate = rate;
    o.tilt_start_step = 1000;
    o.dt = 1e-5;
    o.onset_distance = 2e-3;
    o.rolling_probes = 1;
    const postprocess::InclineResult r = postprocess::measure_incline(tmp / "probes.dump", o);
    ASSERT_EQ(r.probes.size(), 3u);
    ASSERT_TRUE(r.probes[0].onset && r.probes[1].onset);
    // The raw onsets lag by about a degree; corrected, within a few hundredths (linear interpolation between
    // records of a cubic start).
    EXPECT_GT(*r.probes[0].onset_raw - 20.0, 0.3) << rate;
    EXPECT_NEAR(*r.probes[0].onset, 20.0, 0.05) << rate;
    EXPECT_NEAR(*r.probes[1].onset, 40.0, 0.05) << rate;
    EXPECT_FALSE(r.probes[2].onset);
    EXPECT_EQ(r.rolled, 1);
    EXPECT_EQ(r.slid, 1);
    ASSERT_TRUE(r.roll_angle);
    EXPECT_DOUBLE_EQ(*r.roll_angle, *r.probes[0].onset);
    // One of two sliding probes slid: not more than half, no median.
    EXPECT_FALSE(r.slide_angle) << rate;
  }
}

TEST(Incline, OnsetCorrectionInvertsTheStartFromRest) {
  // The lag grows with the distance and falls with the steepness; 0 distance is no lag.
  EXPECT_NEAR(postprocess::incline_onset(30.0, 0.0, 1.0, 5.0, k_g), 30.0, 1e-12);
  const double small = 30.0 - postprocess::incline_onset(30.0, 0.5e-3, 1.0, 5.0, k_g);
  const double large = 30.0 - postprocess::incline_onset(30.0, 2e-3, 1.0, 5.0, k_g);
  EXPECT_NEAR(large / small, std::cbrt(4.0), 0.02);
  EXPECT_GT(postprocess::incline_onset(30.0, 2e-3, 1.0, 5.0, k_g),
            postprocess::incline_onset(30.0, 2e-3, 5.0 / 7.0, 5.0, k_g));
}

TEST(Incline, SpeedAtTheAngleIsInterpolatedBetweenRecords) {
  test::TempDir tmp;
  std::string text;
  for (int k = 0; k <= 40; ++k)  // tilt 0.25 k, vx = 0.01 * tilt
    text += fmt::format(
        "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\n"
        "ITEM: ATOMS id type x y z radius vx vy vz\n1 1 {} 0 0 0.001 {} 0 0\n",
        k * 5000, 1e-3 * k, 0.01 * 0.25 * k);
  test::write_file(tmp / "d.dump", text);
  postprocess::InclineOptions o;
  o.dt = 1e-5;
  o.speed_angle = 5.1;
  o.rolling_probes = 1;
  const postprocess::InclineResult r = postprocess::measure_incline(tmp / "d.dump", o);
  ASSERT_TRUE(r.roll_speed);
  EXPECT_NEAR(*r.roll_speed, 0.051, 1e-12);
}

TEST(Incline, InvalidOptionsAndFilesAreRefused) {
  postprocess::InclineOptions o;
  EXPECT_THROW(o.validate(), std::invalid_argument);  // dt = 0
  o.dt = 1e-5;
  o.tilt_rate = 0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o.tilt_rate = 5;
  test::TempDir tmp;
  test::write_file(tmp / "bad.dump", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\n");
  EXPECT_THROW(postprocess::measure_incline(tmp / "bad.dump", o), postprocess::ParseError);
}

postprocess::InclineOptions options_of_dump(double rate) {
  postprocess::InclineOptions o;
  o.tilt_rate = rate;
  o.tilt_start_step = 1000;
  o.dt = 1e-5;
  o.onset_distance = 2e-3;
  o.rolling_probes = 1;
  return o;
}

TEST(Incline, AnOnsetBeyondTheScheduleMaximumIsNone) {
  // issue 45: the dump records up to one record past max_tilt; a probe that started there moved after the tilt the
  // case applied, and its onset was stored above the recorded maximum.
  test::TempDir tmp;
  test::write_file(tmp / "probes.dump", dump(5.0));
  postprocess::InclineOptions o = options_of_dump(5.0);
  o.max_tilt = 30.0;
  const postprocess::InclineResult r = postprocess::measure_incline(tmp / "probes.dump", o);
  ASSERT_TRUE(r.probes[0].onset);
  EXPECT_NEAR(*r.probes[0].onset, 20.0, 0.05);
  EXPECT_FALSE(r.probes[1].onset) << *r.probes[1].onset;  // it slides from 40°, after the schedule's 30°
  EXPECT_FALSE(r.slide_angle);
  o.max_tilt = 95;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

TEST(Incline, AFrameBeyondNinetyDegreesOrAnIdTwiceIsRefused) {
  test::TempDir tmp;
  test::write_file(tmp / "probes.dump", dump(5.0));
  // Read with twice the rate it was written at, the frames reach 120°: not this schedule's dump.
  try {
    postprocess::measure_incline(tmp / "probes.dump", options_of_dump(10.0));
    ADD_FAILURE() << "a tilt of 120° was measured";
  } catch (const postprocess::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("beyond 90°: the dump does not follow its case's schedule"), std::string::npos)
        << e.what();
  }
  // Probe 3 written as a second probe 2: one id on two rows.
  std::string text = dump(5.0);
  for (std::size_t at = text.find("\n3 1 0 0.01"); at != std::string::npos; at = text.find("\n3 1 0 0.01", at))
    text.replace(at, 3, "\n2 ");
  test::write_file(tmp / "twice.dump", text);
  try {
    postprocess::measure_incline(tmp / "twice.dump", options_of_dump(5.0));
    ADD_FAILURE() << "a dump with an id twice was measured";
  } catch (const postprocess::ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("twice.dump:12: atom id 2 appears twice in the frame of time step 1000"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace demsa
