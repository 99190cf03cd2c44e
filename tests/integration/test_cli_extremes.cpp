// Extreme settings through the real binary: every number of the study file has a physical range, and a value outside
// it, or settings whose derived sizes (lattice sites, step counts, rejection draws) exceed what a case can hold, is
// refused with exit 2 at the key's line by `demsa case` and `demsa run --dry-run` alike, instead of an abort, a hang or
// a case whose step counts are written as 1.
#include "support/process.hpp"
#include "support/test_support.hpp"

#include <signal.h>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

/// Writes a study of `experiment` with `tables` and expects both commands to refuse it with exit 2 and a message that
/// holds every one of `expected`; no case folder is left behind.
void expect_refused(const std::string& experiment, const std::string& tables,
                    const std::vector<std::string>& expected) {
  TempDir dir;
  StudyToml study;
  study.experiment = experiment;
  study.samples = 2;
  study.tables = tables;
  write_file(dir / "study.toml", study.text());
  const std::vector<std::vector<std::string>> commands{
      {"case", (dir / "study.toml").string(), "--sample", "0", "-o", (dir / "case").string()},
      {"run", (dir / "study.toml").string(), "--dir", (dir / "study").string(), "--dry-run"}};
  for (const std::vector<std::string>& args : commands) {
    const CommandResult r = run_demsa(args);
    EXPECT_EQ(r.exit_code, 2) << args[0] << ": " << tables << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("demsa: error: ", 0), 0u) << r.err;
    for (const std::string& text : expected) EXPECT_NE(r.err.find(text), std::string::npos) << text << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "case" / "params.liggghts"));
  EXPECT_FALSE(fs::exists(dir / "study" / "cases" / "0" / "params.liggghts"));
}

TEST(CliExtremes, OedometerBoxSideHasARange) {
  // 1e8 m overflowed the lattice's int site count and ended on an assert (exit 134).
  expect_refused("oedometer", "[oedometer]\nbox_side = 1e8\n",
                 {"study.toml:", "[oedometer] box_side: must lie in (0, 10], got 100000000"});
  // Above 2 r_max but below one lattice cell (2.2 r_max) the lattice had no site: an assert too.
  expect_refused("oedometer", "[oedometer]\nbox_side = 0.0063\n",
                 {"[oedometer] box_side: 0.0063 m is too small", "at least 2.2 r_max"});
}

TEST(CliExtremes, PedestalSizesHaveRanges) {
  // 1e-300 aborted in the STL writer (degenerate triangles); 1e4 ran out of memory; 1e12 tessellated for ever.
  expect_refused("pile", "[pile]\npedestal_height = 1e-300\n", {"[pile] pedestal_height: must lie in [0.0001, 1]"});
  expect_refused("pile", "[pile]\npedestal_radius = 1e12\ndomain_half_width = 10\n",
                 {"[pile] pedestal_radius: must lie in [0.001, 1]"});
  // A base layer of particles sized by the pedestal over the mean radius: more sites than a case holds.
  expect_refused(
      "pile",
      "[pile]\nbase = \"particles\"\npedestal_radius = 1\ndomain_half_width = 2\nr_min = 1e-6\nr_max = 2e-6\n"
      "r_mean = 1.5e-6\nr_sd = 1e-6\ndisc_radius = 0.01\n",
      {"[pile] pedestal_radius: a base layer of particles", "more than 1e+07"});
}

TEST(CliExtremes, MaterialNumbersHaveRanges) {
  // density = 1e-300 gave a time step of 8.7e-158 s and every step count written as 1, exit 0.
  expect_refused("pile", "[material]\ndensity = 1e-300\n", {"[material] density: must lie in [1, 1e+05], got 1e-300"});
  expect_refused("pile", "[material]\ngravity = 1e300\n", {"[material] gravity: must lie in [0.001, 10000]"});
}

TEST(CliExtremes, ARadiusSpreadThatRejectionCannotDrawIsRefused) {
  // r_sd = 1e8 m never finished: rejection sampling kept 1 draw in 1e11.
  for (const std::string experiment : {"pile", "oedometer"})
    expect_refused(experiment, "[" + experiment + "]\nr_sd = 0.9\n",
                   {"[" + experiment + "] r_sd: r_sd = 0.9 m leaves", "r_sd must be at most"});
}

TEST(CliExtremes, StepCountsBeyondWhatLiggghtsRunsAreRefused) {
  // A time step of 1e-300 Rayleigh times: each step count was rounded from beyond a long's range and written as 1.
  // A denormal fraction (found by bench/fuzz_extreme_settings) gave dt = 0 and an assert.
  for (const char* fraction : {"1e-300", "4.9406564584124654e-324"})
    expect_refused("pile", std::string("[timestep]\nfraction = ") + fraction + "\n",
                   {"[timestep] fraction: must lie in [1e-06, 0.3]"});
  expect_refused("pile", "[timestep]\nmode = \"fixed\"\nvalue = 1e-300\n",
                 {"study.toml: ", "more than 1e+12", "[timestep] value = 1e-300 s"});
}

TEST(CliExtremes, ADumpCutInItsLastNumberIsRefused) {
  // The last atom row cut mid-number, no final end of line: it was read as complete (a wrong last value).
  TempDir dir;
  std::string dump = read_file(data_path("postprocess/liggghts_pile/pile_final.dump"));
  while (!dump.empty() && dump.back() == '\n') dump.pop_back();
  dump.pop_back();  // inside the last number
  write_file(dir / "cut.dump", dump);
  write_file(dir / "whole.dump", read_file(data_path("postprocess/liggghts_pile/pile_final.dump")));
  const std::vector<std::vector<std::string>> commands{
      {"postprocess", "pile", (dir / "cut.dump").string()},
      {"compare", (dir / "cut.dump").string(), (dir / "whole.dump").string()},
      {"export-vtk", (dir / "cut.dump").string()}};
  for (const std::vector<std::string>& args : commands) {
    const CommandResult r = run_demsa(args);
    EXPECT_EQ(r.exit_code, 2) << args[0] << ": " << r.err;
    EXPECT_NE(r.err.find((dir / "cut.dump").string() + ":"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("no end of line): cut short?"), std::string::npos) << r.err;
  }
}

TEST(CliExtremes, ASignalStopsCaseWritingWithinASecondAndLeavesNothing) {
  // A case of 1e7 particles takes about half a minute to draw and write: SIGINT (`case`) or SIGTERM (`run`) ended
  // it only at its end, or killed it with the folder half written.
  TempDir dir;
  StudyToml study;
  study.samples = 2;
  study.tables = "[pile]\nparticles = 10000000\n";
  write_file(dir / "study.toml", study.text());
  const std::vector<std::pair<std::vector<std::string>, int>> commands{
      {{"case", (dir / "study.toml").string(), "--sample", "0", "-o", (dir / "case").string()}, SIGINT},
      {{"run", (dir / "study.toml").string(), "--dir", (dir / "study").string(), "--dry-run"}, SIGTERM}};
  for (const auto& [args, sig] : commands) {
    const pid_t pid = spawn_demsa(args, dir / "log.txt");
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    const auto sent = std::chrono::steady_clock::now();
    ASSERT_EQ(::kill(pid, sig), 0);
    const int status = wait_exit(pid);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    EXPECT_EQ(status, 128 + sig) << args[0] << "\n" << read_file(dir / "log.txt");
    EXPECT_LT(seconds, 1.0) << args[0];
  }
  EXPECT_FALSE(fs::exists(dir / "case"));
  EXPECT_FALSE(fs::exists(dir / "study" / "cases" / "000000"));
  EXPECT_NE(read_file(dir / "log.txt").find("demsa: stopped by signal 2; nothing partial was left"), std::string::npos)
      << read_file(dir / "log.txt");
}

TEST(CliExtremes, OutOfMemoryNamesTheCommandThatRan) {
  // The message named the first registered subcommand (`demsa run`) whatever ran. 30e6 x 2 values (480 MB) are
  // within the design's cap and beyond an address space of 300 MB.
  TempDir dir;
  const CommandResult r = run_command({"/bin/sh", "-c",
                                       std::string("ulimit -v 300000; exec '") + DEMSA_BINARY +
                                           "' design lhs -n 30000000 --dim 2 -o " + (dir / "x.csv").string()});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("out of memory while running `demsa design lhs`"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.csv"));
}

}  // namespace
}  // namespace demsa::test
