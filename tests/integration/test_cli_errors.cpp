// Exit statuses of failures through the real binary (docs/reference/command-line.md, "Exit status"): a mistake in the
// user's input exits 2 with "demsa: error: ...", a failure of the machine (a folder that cannot be written, a study
// store that cannot be opened) exits 3 with "demsa: internal error: ..." naming what failed.
#include "orchestrator/study/store.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>

using namespace demsa::study;

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

/// A study folder with every sample done: angle and pile height are smooth functions of the two parameters.
void write_done_study(const fs::path& dir) {
  const std::string toml = StudyToml{.name = "cli-errors",
                                     .samples = 12,
                                     .analysis = "metamodels = [\"rsm2\"]\nbootstrap = 0\nbase_samples = 64\n"}
                               .text();
  SyntheticStudy study = start_synthetic_study(dir, toml, 5);
  record_every_sample_done(study, [](const SampleRow& row) -> std::map<std::string, double> {
    return {{"angle", 25.0 + 8.0 * row.unit[0] + 3.0 * row.unit[1] * row.unit[1]},
            {"pile_height", 0.02 + 0.01 * row.unit[1]}};
  });
}

TEST(CliErrors, AnalysisFolderThatCannotBeCreatedExits3NamingIt) {
  TempDir dir;
  write_done_study(dir / "study");
  write_file(dir / "study" / "analysis", "a file where the analysis folder goes\n");
  const CommandResult r = run_demsa({"analyze", (dir / "study").string()});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_EQ(r.err.rfind("demsa: internal error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find((dir / "study" / "analysis").string()), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("demsa: error:"), std::string::npos) << r.err;
}

TEST(CliErrors, StudyStoreThatCannotBeOpenedExits3) {
  TempDir dir;
  write_done_study(dir / "study");
  fs::remove(dir / "study" / "study.db");
  fs::create_directory(dir / "study" / "study.db");
  const CommandResult r = run_demsa({"status", (dir / "study").string()});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("demsa: internal error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("SQLite"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find((dir / "study" / "study.db").string()), std::string::npos) << r.err;
}

TEST(CliErrors, StudyAnalyzesOnceTheFolderCanBeWritten) {
  // The same study as above, unobstructed: the exit 3 above is the folder's doing, not the study's.
  TempDir dir;
  write_done_study(dir / "study");
  const CommandResult r = run_demsa({"analyze", (dir / "study").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(CliErrors, UnknownMetamodelFromTheLibraryExits2) {
  // sobol::InputError thrown by the library itself, caught only by run_cli().
  TempDir dir;
  write_done_study(dir / "study");
  const CommandResult r = run_demsa({"analyze", (dir / "study").string(), "--models", "quartic"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("demsa: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("quartic"), std::string::npos) << r.err;
}

TEST(CliErrors, CommandLineErrorsExit2AsDemsaErrors) {
  const CommandResult unknown = run_demsa({"frobnicate"});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_EQ(unknown.err.rfind("demsa: error: ", 0), 0u) << unknown.err;
  EXPECT_NE(unknown.err.find("frobnicate"), std::string::npos) << unknown.err;
  const CommandResult missing = run_demsa({"status"});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(missing.err.rfind("demsa: error: ", 0), 0u) << missing.err;
}

TEST(CliErrors, BadPostprocessOptionIsAUsageError) {
  // The library reports it as std::invalid_argument (a programming error for its other callers); from the command
  // line it is the user's: exit 2, not 3.
  TempDir dir;
  write_file(dir / "plate_states.txt", "# load_N plate_z_m force_N converged\n100 0.06 100 1\n");
  const CommandResult r =
      run_demsa({"postprocess", "oedometer", (dir / "plate_states.txt").string(), "--floor-z", "inf"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("demsa: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("--floor-z = inf"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace demsa::test
