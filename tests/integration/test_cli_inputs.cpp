// Bad command-line values through the real binary: every range error says "demsa: error:", names the option and
// gives a readable bound; a parameter given twice to `demsa case --set` is refused; `demsa analyze`, `report` and
// `calibrate` refuse a study that a `demsa run` holds, as a second `demsa run` does.
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/store.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>
#include <vector>

using namespace demsa::study;

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

/// A range error as a user should see it: exit 2, "demsa: error: OPTION: ...", no 309-digit DBL_MAX, no field of a
/// library's options struct.
void expect_range_error(const std::vector<std::string>& args, const std::string& option, const fs::path& cwd) {
  const CommandResult r = run_demsa(args, cwd);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("demsa: error: " + option + ": ", 0), 0u) << r.err;
  EXPECT_FALSE(std::regex_search(r.err, std::regex("[0-9]{20}"))) << r.err;
  EXPECT_EQ(r.err.find("Options."), std::string::npos) << r.err;
}

TEST(CliInputs, RangeErrorsNameTheOptionAndAReadableBound) {
  TempDir dir;
  write_file(dir / "plate_states.txt", "100 0.05 100 1\n400 0.049 400 1\n");
  const std::string states = (dir / "plate_states.txt").string();
  expect_range_error({"postprocess", "oedometer", states, "--box-side", "-1"}, "--box-side", dir.path());
  expect_range_error({"postprocess", "oedometer", states, "--box-side", "nan"}, "--box-side", dir.path());
  expect_range_error({"postprocess", "oedometer", states, "--box-side", "1e400"}, "--box-side", dir.path());
  expect_range_error({"postprocess", "oedometer", states, "--load-tolerance", "-0.1"}, "--load-tolerance", dir.path());
  expect_range_error({"postprocess", "pile", "x.dump", "--level-low", "2"}, "--level-low", dir.path());
  expect_range_error({"compare", "a.dump", "b.dump", "--tol-pos", "-1"}, "--tol-pos", dir.path());
  expect_range_error({"analyze", dir.path().string(), "--base", "1"}, "--base", dir.path());

  const CommandResult negative = run_demsa({"postprocess", "oedometer", states, "--box-side", "-1"});
  EXPECT_NE(negative.err.find("--box-side: -1: must be > 0"), std::string::npos) << negative.err;
  const CommandResult nan = run_demsa({"postprocess", "oedometer", states, "--box-side", "nan"});
  EXPECT_NE(nan.err.find("--box-side: nan: must be a finite number > 0"), std::string::npos) << nan.err;
}

TEST(CliInputs, ALibraryRuleNamesTheOptionNotTheField) {
  // --level-high below --level-low passes each option's own check; the library's rule names the option.
  TempDir dir;
  write_file(dir / "pile.dump",
             "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS ff ff ff\n-1 1\n-1 1\n0 1\nITEM: ATOMS id "
             "type x y z radius\n1 1 0 0 0.1 0.01\n");
  const CommandResult r =
      run_demsa({"postprocess", "pile", (dir / "pile.dump").string(), "--level-low", "0.6", "--level-high", "0.4"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("demsa: error: --level-high = 0.4: ", 0), 0u) << r.err;
}

TEST(CliInputs, AParameterSetTwiceIsRefused) {
  TempDir dir;
  write_file(dir / "study.toml", StudyToml{}.text());
  const CommandResult r =
      run_demsa({"case", (dir / "study.toml").string(), "--set", "mu_pp=0.5,mu_pp=0.6", "-o", (dir / "case").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err, "demsa: error: --set: mu_pp is given twice (mu_pp=0.5 and mu_pp=0.6); give each parameter once\n");
  EXPECT_FALSE(fs::exists(dir / "case"));
  // Over two --set options too.
  const CommandResult two = run_demsa({"case", (dir / "study.toml").string(), "--set", "mu_pp=0.5", "--set",
                                       "mu_pp=0.6", "-o", (dir / "case").string()});
  EXPECT_EQ(two.exit_code, 2) << two.err;
}

/// A study folder with every sample done (two parameters, smooth observables).
void write_done_study(const fs::path& dir) {
  const std::string toml =
      StudyToml{
          .name = "held", .samples = 12, .analysis = "metamodels = [\"rsm2\"]\nbootstrap = 0\nbase_samples = 64\n"}
          .text();
  SyntheticStudy study = start_synthetic_study(dir, toml, 5);
  record_every_sample_done(study, [](const SampleRow& row) -> std::map<std::string, double> {
    return {{"angle", 25.0 + 8.0 * row.unit[0] + 3.0 * row.unit[1] * row.unit[1]},
            {"pile_height", 0.02 + 0.01 * row.unit[1]}};
  });
}

TEST(CliInputs, CommandsThatWriteIntoAStudyRefuseWhileARunHoldsIt) {
  TempDir dir;
  const fs::path study = dir / "study";
  write_done_study(study);
  {
    // This process stands for the `demsa run` that holds the study (the lock is per process).
    const StudyLock held(study);
    for (const std::vector<std::string>& args : {std::vector<std::string>{"analyze", study.string()},
                                                 {"report", study.string(), "--no-html"},
                                                 {"calibrate", study.string(), "--target", "angle=30"}}) {
      const CommandResult r = run_demsa(args);
      EXPECT_EQ(r.exit_code, 2) << args[0] << ": " << r.err;
      EXPECT_NE(r.err.find("demsa: error: " + study.string() + ": another demsa (pid "), std::string::npos)
          << args[0] << ": " << r.err;
      EXPECT_NE(r.err.find("is running this study"), std::string::npos) << r.err;
    }
    EXPECT_FALSE(fs::exists(study / k_analysis_folder / "analysis.json"));
    EXPECT_FALSE(fs::exists(study / k_report_folder));
  }
  // Once the run has let go, the analysis runs.
  const CommandResult r = run_demsa({"analyze", study.string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(study / k_analysis_folder / "analysis.json"));
}

}  // namespace
}  // namespace demsa::test
