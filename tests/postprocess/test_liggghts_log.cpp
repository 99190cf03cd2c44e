// LIGGGHTS log reader on the log of the real test pile and on hand-written logs (errors, lost atoms).
#include "postprocess/liggghts_log.hpp"

#include "support/test_support.hpp"

#include <gtest/gtest.h>

namespace demsa::postprocess {
namespace {

TEST(LiggghtsLog, RealPileLog) {
  const LiggghtsLog log = read_liggghts_log(test::data_path("postprocess/liggghts_pile/log.liggghts"));
  EXPECT_EQ(log.version, "LIGGGHTS-PUBLIC 3.8.0");
  // 13 appended discs + the settling run + the initial fall (`grep -c '^Loop time'`: 14).
  ASSERT_EQ(log.loops.size(), 14u);
  ASSERT_EQ(log.thermo.size(), 14u);
  EXPECT_EQ(log.steps, 545557);  // sum of the steps of the Loop time lines
  EXPECT_NEAR(log.loop_seconds, 94.665151, 1e-5);
  EXPECT_EQ(log.loops.back().steps, 300000);
  EXPECT_EQ(log.loops.back().atoms, 600);
  EXPECT_EQ(log.loops.back().procs, 1);
  EXPECT_NEAR(log.loops.back().seconds, 53.2401, 1e-9);
  const ThermoBlock& first = log.thermo.front();
  EXPECT_EQ(first.header_line, 83);
  EXPECT_EQ(first.columns.at(1), "Atoms");
  ASSERT_EQ(first.rows.size(), 2u);
  EXPECT_DOUBLE_EQ(first.rows[1][0], 18889.0);
  EXPECT_DOUBLE_EQ(first.rows[1][2], 0.00075767815);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_EQ(log.warnings[0].line, 73);
  EXPECT_EQ(log.warnings[0].text.rfind("Changing thermo_temp compute object.", 0), 0u);
  EXPECT_TRUE(log.errors.empty());
  EXPECT_EQ(log.lost_atoms, 0);  // all 600 atoms are still in the final thermo row
}

TEST(LiggghtsLog, LostAtomsFromThermoAndErrors) {
  const std::string text =
      "LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, compiled 2022)\n"
      "  Step Atoms KinEng\n"
      "  0 1000 0\n"
      "  100 998 1.5\n"
      "  200 994 1.25\n"
      "Loop time of 2.5 on 2 procs for 200 steps with 994 atoms\n"
      "WARNING: something odd (./src/x.cpp:1)\n"
      "  Step Atoms KinEng\n"
      "  200 1010 1.25\n"
      "  300 10";  // a cut row of a killed run
  const LiggghtsLog log = parse_liggghts_log(text);
  EXPECT_EQ(log.lost_atoms, 6);
  ASSERT_EQ(log.thermo.size(), 2u);
  EXPECT_EQ(log.thermo[1].rows.size(), 1u);
  ASSERT_EQ(log.loops.size(), 1u);
  EXPECT_EQ(log.loops[0].procs, 2);
  EXPECT_EQ(log.warnings.at(0).line, 7);
  EXPECT_EQ(log.warnings.at(0).text, "something odd (./src/x.cpp:1)");

  const LiggghtsLog err = parse_liggghts_log(
      "ERROR: Lost atoms: original 1000 current 990 (../thermo.cpp:389)\nERROR on proc 1: Bad thing (x.cpp:2)\n"
      "Total wall time: 1:02:03\n");
  EXPECT_EQ(err.lost_atoms, 10);
  ASSERT_EQ(err.errors.size(), 2u);
  EXPECT_EQ(err.errors[1].text, "Bad thing (x.cpp:2)");
  ASSERT_TRUE(err.total_wall_seconds.has_value());
  EXPECT_DOUBLE_EQ(*err.total_wall_seconds, 3723.0);
}

TEST(LiggghtsLog, MissingFile) { EXPECT_THROW(read_liggghts_log("/nonexistent/log.liggghts"), ParseError); }

}  // namespace
}  // namespace demsa::postprocess
