// Oedometer observables (paper §4): plate files, settlements against the first load, stress, void ratio, E_0.
#include "postprocess/oedometer.hpp"

#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace demsa::postprocess {
namespace {

using test::TempDir;
using test::write_file;

const char* k_states =
    "# plate states written by the oedometer driver\n"
    "# load_N plate_z_m force_N converged\n"
    "100 0.0600 100.01 1\n"
    "400 0.0590 399.98 1\n"
    "1100 0.0575 1100.02 1\n"
    "2700 0.0550 2699.5 0\n";

const char* k_history =
    "# Time-averaged data for fix plate\n"
    "# TimeStep v_load v_z f_plate[3]\n"
    "# step load_N plate_z_m force_N trial delta_m accepted\n"
    "15000 100 0.0610 20 1 7.5e-6 1\n"
    "30000 100 0.0605 120 2 7.5e-6 0\n"
    "45000 100 0.0600 100.01 3 7.125e-6 1\n"
    "60000 400 0.0595 300 1 7.5e-6 1\n"
    "75000 400 0.0590 399.98 2 7.5e-6 1\n";

TEST(Oedometer, SettlementsStressAndVoidRatio) {
  TempDir dir;
  write_file(dir / "plate_states.txt", k_states);
  const std::vector<PlateState> states = read_plate_states(dir / "plate_states.txt");
  ASSERT_EQ(states.size(), 4u);
  OedometerOptions o;
  o.box_side = 0.1;
  o.solid_volume = 3.0e-4;  // m³
  o.measured_settlements = {0.0012, 0.0024, 0.0050};
  const OedometerResult r = measure_oedometer(states, o);
  ASSERT_EQ(r.steps.size(), 4u);
  EXPECT_DOUBLE_EQ(r.steps[0].settlement_m, 0.0);
  EXPECT_NEAR(r.steps[1].settlement_m, 0.0010, 1e-15);
  EXPECT_NEAR(r.steps[3].settlement_m, 0.0050, 1e-15);
  ASSERT_EQ(r.settlements.size(), 3u);
  EXPECT_NEAR(r.settlements[1], 0.0025, 1e-15);
  EXPECT_DOUBLE_EQ(r.steps[2].stress_Pa, 1100.0 / 0.01);
  // e = (A h − V_S)/V_S = (0.01·0.06 − 3e-4)/3e-4 = 1
  ASSERT_TRUE(r.steps[0].void_ratio.has_value());
  EXPECT_NEAR(*r.steps[0].void_ratio, 1.0, 1e-12);
  EXPECT_NEAR(*r.steps[3].void_ratio, (0.01 * 0.055 - 3e-4) / 3e-4, 1e-12);
  // E_0 = sqrt(0.0002² + 0.0001² + 0²)
  ASSERT_TRUE(r.settlement_error.has_value());
  EXPECT_NEAR(*r.settlement_error, std::sqrt(0.0002 * 0.0002 + 0.0001 * 0.0001), 1e-15);
  EXPECT_FALSE(r.all_converged);
  EXPECT_FALSE(r.history.has_value());
}

TEST(Oedometer, MeasuredIncludingFirstLoad) {
  std::vector<PlateState> states = {{100, 0.06, 100, true}, {400, 0.059, 400, true}};
  OedometerOptions o;
  o.measured_settlements = {0.0, 0.0013};
  const OedometerResult r = measure_oedometer(states, o);
  EXPECT_NEAR(*r.settlement_error, 0.0003, 1e-15);
  EXPECT_TRUE(r.all_converged);
  EXPECT_FALSE(r.steps[0].void_ratio.has_value());
}

TEST(Oedometer, WrongNumberOfMeasuredSettlements) {
  std::vector<PlateState> states = {{100, 0.06, 100, true}, {400, 0.059, 400, true}, {1100, 0.058, 1100, true}};
  OedometerOptions o;
  o.measured_settlements = {0.001};
  try {
    measure_oedometer(states, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "1 measured settlements for 3 load states: give 2 (one per load after the first) or 3 (starting "
                 "with the first load's 0)");
  }
  EXPECT_THROW(measure_oedometer({}, {}), InputError);
}

TEST(Oedometer, HistoryWithTrialColumns) {
  TempDir dir;
  write_file(dir / "plate_history.txt", k_history);
  const PlateHistory h = read_plate_history(dir / "plate_history.txt");
  ASSERT_EQ(h.size(), 5u);
  EXPECT_EQ(h.columns.size(), 7u);
  EXPECT_EQ(h.step[4], 75000);
  EXPECT_DOUBLE_EQ(h.delta_m[2], 7.125e-6);
  EXPECT_EQ(h.accepted[1], 0);
  const std::vector<PlateState> s = states_from_history(h, 0.03);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_DOUBLE_EQ(s[0].plate_z_m, 0.0600);
  EXPECT_TRUE(s[0].converged);
  EXPECT_DOUBLE_EQ(s[1].force_N, 399.98);
  EXPECT_TRUE(s[1].converged);
  const OedometerResult r = measure_oedometer(s, {}, h);
  EXPECT_EQ(r.trials_accepted, 4u);
  EXPECT_EQ(r.trials_rejected, 1u);
  EXPECT_NEAR(r.settlements[0], 0.001, 1e-15);
}

TEST(Oedometer, HistoryWithoutTrialColumnsTakesLastRowPerLoad) {
  TempDir dir;
  write_file(dir / "h.txt", "# step load_N plate_z_m force_N\n1 100 0.07 50\n2 100 0.069 99\n3 400 0.068 401\n");
  const std::vector<PlateState> s = states_from_history(read_plate_history(dir / "h.txt"), 0.5);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_DOUBLE_EQ(s[0].plate_z_m, 0.069);
  EXPECT_FALSE(s[0].converged);  // |99 − 100| > 0.5
  EXPECT_FALSE(s[1].converged);
}

TEST(Oedometer, SolidVolumeOfSpheres) {
  Particles p;
  p.radius = {1.0, 2.0};
  p.id = {1, 2};
  EXPECT_NEAR(solid_volume(p), 4.0 / 3.0 * std::numbers::pi * 9.0, 1e-12);
}

TEST(OedometerErrors, HistoryMissingColumn) {
  TempDir dir;
  write_file(dir / "h.txt", "# step load_N plate_z_m\n1 100 0.07\n");
  try {
    read_plate_history(dir / "h.txt");
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir / "h.txt").string() + ": no column 'force_N' (columns: step load_N plate_z_m)");
  }
}

TEST(OedometerErrors, HistoryRowBeforeHeader) {
  TempDir dir;
  write_file(dir / "h.txt", "# comment\n1 100 0.07 5\n");
  try {
    read_plate_history(dir / "h.txt");
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 2);
  }
}

TEST(OedometerErrors, NonNumericAndShortRows) {
  TempDir dir;
  write_file(dir / "s.txt", "100 0.06 100 1\n400 0.0x 400 1\n");
  EXPECT_EQ(test::message_of<ParseError>([&] { read_plate_states(dir / "s.txt"); }),
            (dir / "s.txt").string() + ":2: column 'plate_z_m': '0.0x' is not a number");
  write_file(dir / "s.txt", "100 0.06 100\n");
  EXPECT_EQ(test::message_of<ParseError>([&] { read_plate_states(dir / "s.txt"); }),
            (dir / "s.txt").string() + ":1: row has 3 values, the header names 4 columns");
  write_file(dir / "s.txt", "100 0.06 100 2\n");
  EXPECT_THROW(read_plate_states(dir / "s.txt"), ParseError);
  EXPECT_THROW(read_plate_states(dir / "missing.txt"), ParseError);
}

TEST(OedometerErrors, DecreasingLoadNamesFileLineAndValue) {
  TempDir dir;
  write_file(dir / "s.txt", "# load_N plate_z_m force_N converged\n100 0.06 100 1\n400 0.059 400 1\n300 0.058 300 1\n");
  EXPECT_EQ(test::message_of<ParseError>([&] { read_plate_states(dir / "s.txt"); }),
            (dir / "s.txt").string() +
                ":4: column 'load_N': 300 is below the 400 of line 3: the loads of the load states must not decrease");
  write_file(dir / "h.txt", "# step load_N plate_z_m force_N\n1000 400 0.06 390\n2000 100 0.059 99\n");
  EXPECT_EQ(test::message_of<ParseError>([&] { read_plate_history(dir / "h.txt"); }),
            (dir / "h.txt").string() +
                ":3: column 'load_N': 100 is below the 400 of line 2: the loads of a plate history must not decrease");
  // Equal loads (the rows of one load step) are the normal case.
  write_file(dir / "h.txt", "# step load_N plate_z_m force_N\n1000 100 0.06 90\n2000 100 0.059 99\n");
  EXPECT_EQ(read_plate_history(dir / "h.txt").size(), 2u);
}

TEST(OedometerErrors, ImplausiblePositionsAndLoads) {
  TempDir dir;
  write_file(dir / "s.txt", "100 0.06 100 1\n400 1e308 400 1\n");
  EXPECT_EQ(test::message_of<ParseError>([&] { read_plate_states(dir / "s.txt"); }),
            (dir / "s.txt").string() + ":2: column 'plate_z_m': 1e+308 m is not a plate position (|z| > 1000 m)");
  write_file(dir / "s.txt", "-100 0.06 100 1\n");
  EXPECT_EQ(test::message_of<ParseError>([&] { read_plate_states(dir / "s.txt"); }),
            (dir / "s.txt").string() + ":1: column 'load_N': -100 is negative");
  write_file(dir / "h.txt", "# step load_N plate_z_m force_N trial delta_m accepted\n1 100 0.06 99 1 -2e3 1\n");
  EXPECT_EQ(test::message_of<ParseError>([&] { read_plate_history(dir / "h.txt"); }),
            (dir / "h.txt").string() + ":2: column 'delta_m': -2000 m is not a trial step (|delta| > 1000 m)");
  write_file(dir / "s.txt", "100 inf 100 1\n");
  EXPECT_EQ(test::message_of<ParseError>([&] { read_plate_states(dir / "s.txt"); }),
            (dir / "s.txt").string() + ":1: column 'plate_z_m': 'inf' is not a number");
}

TEST(OedometerErrors, LongLineAndHugeFileAreRefusedQuickly) {
  // A line without end (binary data, /dev/zero) stops the reader at 64 KiB instead of growing without bound.
  TempDir dir;
  write_file(dir / "s.txt", "100 0.06 100 1\n" + std::string(1 << 20, '7'));
  const std::string message = test::message_of<ParseError>([&] { read_plate_states(dir / "s.txt"); });
  EXPECT_EQ(message, (dir / "s.txt").string() +
                         ":2: line longer than 65536 bytes (it starts '7777777777777777777777777777777777777777...'): "
                         "not a text file of this kind");
  // /dev/zero is not a regular file: refused before it is opened (issue 45: a FIFO would block the open).
  EXPECT_EQ(test::message_of<ParseError>([] {
              read_plate_history("/dev/zero");
            }).rfind("/dev/zero: a character device, not a regular file", 0),
            0u);
}

TEST(OedometerErrors, ByteOrderMarkAndCrLfAreText) {
  const std::vector<PlateState> states =
      parse_plate_states("\xEF\xBB\xBF# load_N plate_z_m force_N converged\r\n100 0.06 100 1\r\n", "s.txt");
  ASSERT_EQ(states.size(), 1u);
  EXPECT_DOUBLE_EQ(states[0].plate_z_m, 0.06);
}

TEST(SettledPacking, TheFillsCommentGivesTheFillsVoidRatioAndThePlatesGap) {
  const std::string line =
      "# settled packing: particles 1000, top_z_m 0.0306807689495588, void_ratio 1.65171513157407, "
      "plate_start_z_m 0.0311807689495588\n";
  const std::optional<SettledPacking> p =
      parse_settled_packing(line + "# load_N plate_z_m force_N converged\n100 0.0246 99.998 1\n", "s.txt");
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->particles, 1000);
  EXPECT_DOUBLE_EQ(p->top_z_m, 0.0306807689495588);
  EXPECT_DOUBLE_EQ(p->void_ratio, 1.65171513157407);
  EXPECT_NEAR(p->plate_start_z_m - p->top_z_m, 0.5e-3, 1e-15);
  // A file without it (the fill did not end, or a file of an older demsa) has none.
  EXPECT_FALSE(parse_settled_packing("# load_N plate_z_m force_N converged\n", "s.txt").has_value());
  EXPECT_FALSE(parse_settled_packing("", "s.txt").has_value());
}

TEST(SettledPacking, AMalformedCommentNamesTheFileTheLineAndTheValue) {
  const auto message = [](const std::string& text) {
    return test::message_of<ParseError>([&] { parse_settled_packing(text, "s.txt"); });
  };
  EXPECT_EQ(message("\n# settled packing: particles 1000, top_z_m 0.03, void_ratio nan, plate_start_z_m 0.031\n"),
            "s.txt:2: settled packing: void_ratio = 'nan' is not a finite number");
  EXPECT_EQ(message("# settled packing: particles 1000, top_z_m 0.03, plate_start_z_m 0.031\n"),
            "s.txt:1: settled packing: no void_ratio in '# settled packing: particles 1000, top_z...'");
  EXPECT_EQ(message("# settled packing: particles 0.5, top_z_m 0.03, void_ratio 1, plate_start_z_m 0.031\n"),
            "s.txt:1: settled packing: particles = 0.5 is not a count");
  EXPECT_EQ(message("# settled packing: particles 10, top_z_m 0.03, void_ratio -1, plate_start_z_m 0.031\n"),
            "s.txt:1: settled packing: void_ratio = -1 is negative");
  EXPECT_EQ(message("# settled packing: particles 10, top_z_m 0.03, void_ratio 1, plate_start_z_m 0.02\n"),
            "s.txt:1: settled packing: plate_start_z_m = 0.02 lies below top_z_m = 0.03");
}

TEST(OedometerErrors, OptionsValidate) {
  OedometerOptions o;
  o.box_side = -1;
  EXPECT_EQ(test::message_of<std::invalid_argument>([&] { o.validate(); }),
            "OedometerOptions.box_side = -1: must be a positive length [m]");
}

}  // namespace
}  // namespace demsa::postprocess
