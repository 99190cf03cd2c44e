// LIGGGHTS log reader on the log of the real test pile and on hand-written logs (errors, lost atoms).
#include "postprocess/liggghts_log.hpp"

#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

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

TEST(LiggghtsLog, ScanThermoStreamsTheRowsOfTheReader) {
  const std::filesystem::path path = test::data_path("postprocess/liggghts_pile/log.liggghts");
  const LiggghtsLog log = read_liggghts_log(path);
  std::size_t rows = 0;
  std::size_t block = 0;
  long last_header = -1;
  bool same = true;
  scan_thermo(path, [&](const ThermoRow& row) {
    if (row.block.header_line != last_header) {
      if (last_header >= 0) ++block;
      last_header = row.block.header_line;
      rows = 0;
    }
    same = same && block < log.thermo.size() && log.thermo[block].header_line == row.block.header_line &&
           log.thermo[block].columns == row.block.columns && rows < log.thermo[block].rows.size() &&
           log.thermo[block].rows[rows] == row.values && row.words.size() == row.values.size() && row.line > 0 &&
           row.block.rows.empty();
    ++rows;
    return true;
  });
  EXPECT_TRUE(same);
  EXPECT_EQ(block + 1, log.thermo.size());
  EXPECT_EQ(rows, log.thermo.back().rows.size());
  // `visit` returning false stops the scan.
  int seen = 0;
  scan_thermo(path, [&](const ThermoRow&) { return ++seen < 3; });
  EXPECT_EQ(seen, 3);
  EXPECT_THROW(scan_thermo("/nonexistent/log.liggghts", [](const ThermoRow&) { return true; }), ParseError);
}

TEST(LiggghtsLog, NanAndInfAreThermoValues) {
  test::TempDir dir;
  test::write_file(dir / "log.liggghts",
                   "    Step    Atoms         KinEng           c_ke \n"
                   "       0       10              0              0 \n"
                   "     100       10            inf           -nan \n"
                   "     200       10            nan            1e3 7\n"  // one value too many: not a row
                   "     300       10              0              0 \n");
  std::vector<long> lines;
  std::vector<std::string> words;
  scan_thermo(dir / "log.liggghts", [&](const ThermoRow& row) {
    lines.push_back(row.line);
    words.push_back(row.words[3]);
    if (row.line == 3) {
      EXPECT_TRUE(std::isinf(row.values[2]));
      EXPECT_TRUE(std::isnan(row.values[3]));
    }
    return true;
  });
  EXPECT_EQ(lines, (std::vector<long>{2, 3}));
  EXPECT_EQ(words, (std::vector<std::string>{"0", "-nan"}));
  const LiggghtsLog log = read_liggghts_log(dir / "log.liggghts");
  ASSERT_EQ(log.thermo.size(), 1u);
  EXPECT_EQ(log.thermo[0].rows.size(), 2u);
  EXPECT_EQ(log.thermo[0].kinetic_energy_column(), 3);
}

TEST(LiggghtsLog, KineticEnergyColumn) {
  auto column = [](std::vector<std::string> names) {
    return ThermoBlock{1, std::move(names), {}}.kinetic_energy_column();
  };
  EXPECT_EQ(column({"Step", "Atoms", "KinEng"}), 2);
  EXPECT_EQ(column({"Step", "KinEng", "c_KE", "Volume"}), 2);  // the last one
  EXPECT_EQ(column({"Step", "v_kinetic_energy"}), 1);
  EXPECT_EQ(column({"Step", "f_vke"}), 1);
  EXPECT_EQ(column({"Step", "Atoms", "c_rke", "Volume", "v_"}), -1);
}

TEST(LiggghtsLog, FirstErrorLine) {
  test::TempDir dir;
  test::write_file(dir / "screen.txt",
                   "echo: ERROR: not at the start\n"
                   "   ERROR on proc 2: Cannot open file a.stl (../input.cpp:3)\r\n"
                   "ERROR: second (x.cpp:1)\n");
  EXPECT_EQ(first_error_line(dir / "screen.txt"), "ERROR on proc 2: Cannot open file a.stl (../input.cpp:3)");
  test::write_file(dir / "clean.txt", "ERRORS are not errors\nWARNING: fine\n");
  EXPECT_EQ(first_error_line(dir / "clean.txt"), "");
  EXPECT_EQ(first_error_line(dir / "missing.txt"), "");
  // The whole-log reader applies the same rule.
  const LiggghtsLog log = read_liggghts_log(dir / "screen.txt");
  ASSERT_EQ(log.errors.size(), 2u);
  EXPECT_EQ(log.errors[0].line, 2);
  EXPECT_EQ(log.errors[0].text, "Cannot open file a.stl (../input.cpp:3)");
}

TEST(LiggghtsLog, LineLimit) {
  // Binary data in a log (a node that died mid-write, /dev/zero) is refused at 1 MiB, naming the file and line,
  // instead of growing a line without bound; first_error_line still reports the ERROR lines before it.
  test::TempDir dir;
  test::write_file(dir / "log.liggghts", "LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, compiled)\nERROR: boom (a.cpp:1)\n" +
                                             std::string((1 << 20) + 10, '\0'));
  const std::string message = test::message_of<ParseError>([&] { read_liggghts_log(dir / "log.liggghts"); });
  EXPECT_EQ(message.rfind((dir / "log.liggghts").string() + ":3: line longer than 1 MiB", 0), 0u) << message;
  EXPECT_EQ(first_error_line(dir / "log.liggghts"), "ERROR: boom (a.cpp:1)");
  EXPECT_THROW(scan_thermo(dir / "log.liggghts", [](const ThermoRow&) { return true; }), ParseError);
  EXPECT_EQ(first_error_line("/dev/zero"), "");
}

TEST(LiggghtsLog, MissingFile) { EXPECT_THROW(read_liggghts_log("/nonexistent/log.liggghts"), ParseError); }

}  // namespace
}  // namespace demsa::postprocess
