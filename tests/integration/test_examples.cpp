// Every study in examples/, examples/calibration/ and examples/drum-mcc/ is valid: `demsa run --dry-run` parses it and
// writes every case of its design without running one (the paper-size studies are meant for clusters, but must generate
// here). README command A runs the quickstart for real.
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace demsa {
namespace {

namespace fs = std::filesystem;

TEST(Examples, EveryExampleStudyGeneratesAllItsCases) {
  const fs::path examples = fs::path(DEMSA_SOURCE_DIR) / "examples";
  std::vector<fs::path> studies;
  // examples/, examples/calibration/ (the experiments' studies) and examples/drum-mcc/ (the drum's, beside its
  // photographs); the study folders they leave are skipped, and so are the photographs' geometry files (drum.toml,
  // IMAGE.drum.toml: `demsa measure IMAGE` reads them).
  for (const fs::path& dir : {examples, examples / "calibration", examples / "drum-mcc"})
    for (const fs::directory_entry& e : fs::directory_iterator(dir))
      if (e.is_regular_file() && e.path().extension() == ".toml" && e.path().filename() != "drum.toml" &&
          !e.path().filename().string().ends_with(".drum.toml"))
        studies.push_back(e.path());
  ASSERT_GE(studies.size(), 8u) << "quickstart, the paper's three studies and the four experiments' studies";
  for (const fs::path& study : studies) {
    SCOPED_TRACE(study.filename().string());
    test::TempDir tmp;
    const test::CommandResult r =
        test::run_demsa({"run", study.string(), "--dir", (tmp / "study").string(), "--dry-run"});
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_TRUE(fs::exists(tmp / "study" / "cases")) << r.out;
  }
}

}  // namespace
}  // namespace demsa
