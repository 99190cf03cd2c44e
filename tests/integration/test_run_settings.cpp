// `demsa run` and the design hash of the settings table (orchestrator/study/settings.hpp), against the fake
// LIGGGHTS (tests/integration/fake_liggghts): a finished study whose measurement settings changed is refused and
// the message names the changed keys; a store holding the previous version's hash resumes.
#include "orchestrator/study/store.hpp"

#include "support/test_support.hpp"

#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace demsa {

using namespace demsa::study;
namespace {

namespace fs = std::filesystem;

/// A small pile study run by the fake; `pile` is the body of [pile].
std::string study_text(const std::string& pile) {
  return test::StudyToml{.name = "resume",
                         .experiment = "pile",
                         .seed = 7,
                         .method = "lhs",
                         .samples = 4,
                         .tables = "[pile]\n" + pile,
                         .run = test::fake_liggghts_run_lines() + "parallel = 2\noversubscribe = true\n",
                         .analysis = "metamodels = [\"rsm2\", \"rbf-cubic\"]\n"}
      .text();
}

TEST(RunSettings, FinishedStudyWithChangedLevelsIsMeasuredAgainAndChangedCasesRefusedNamingTheKey) {
  test::TempDir tmp;
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0);
  test::write_file(tmp / "study.toml", study_text("particles = 300\n"));
  const test::CommandResult first = test::run_demsa(test::run_args(tmp, {"--no-analyze", "--quiet"}));
  ASSERT_EQ(first.exit_code, 0) << first.out << first.err;
  const std::size_t runs = Store::open_read_only((tmp / "study" / "study.db").string()).runs().size();
  // The angle of every finished case was measured on 10 levels; with 12 every case is measured again from its files
  // (one table never mixes two measurements), and nothing runs again.
  test::write_file(tmp / "study.toml", study_text("particles = 300\nlevels = 12\n"));
  const test::CommandResult again = test::run_demsa(test::run_args(tmp, {"--no-analyze", "--quiet"}));
  EXPECT_EQ(again.exit_code, 0) << again.out << again.err;
  EXPECT_NE(again.out.find("only how cases are measured changed ([pile] levels: 10 -> 12): 4 finished case(s) "
                           "measured again"),
            std::string::npos)
      << again.out;
  EXPECT_EQ(Store::open_read_only((tmp / "study" / "study.db").string()).runs().size(), runs);
  // A key that changes the cases is refused, naming it.
  test::write_file(tmp / "study.toml", study_text("particles = 400\nlevels = 12\n"));
  const test::CommandResult refused = test::run_demsa(test::run_args(tmp, {"--no-analyze", "--quiet"}));
  EXPECT_EQ(refused.exit_code, 2) << refused.out << refused.err;
  EXPECT_NE(refused.err.find("design-relevant settings differ"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("changed: [pile] particles: 300 -> 400"), std::string::npos) << refused.err;
  // [run] may change; the study as it was resumes.
  test::write_file(tmp / "study.toml", study_text("particles = 300\nlevels = 12\n") + "\n");
  const test::CommandResult resumed = test::run_demsa(test::run_args(tmp, {"--no-analyze", "--quiet"}));
  EXPECT_EQ(resumed.exit_code, 0) << resumed.out << resumed.err;
}

TEST(RunSettings, StoreOfThePreviousVersionResumes) {
  // 08d437ffe546bf8f: the design hash the previous version (commit 6807f91) stored for this study (its demsa run
  // --dry-run, read from study.db). A store that holds it must resume.
  test::TempDir tmp;
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0);
  test::write_file(tmp / "study.toml", study_text("particles = 300\n"));
  ASSERT_EQ(test::run_demsa(test::run_args(tmp, {"--dry-run"})).exit_code, 0);
  const fs::path db = tmp / "study" / "study.db";
  {
    SQLite::Database store(db.string(), SQLite::OPEN_READWRITE);
    SQLite::Statement q(store, "SELECT value FROM meta WHERE key = 'design_hash'");
    ASSERT_TRUE(q.executeStep());
    EXPECT_EQ(q.getColumn(0).getString(), "08d437ffe546bf8f");
    store.exec("UPDATE meta SET value = '08d437ffe546bf8f' WHERE key = 'design_hash'");
  }
  const test::CommandResult resumed = test::run_demsa(test::run_args(tmp, {"--no-analyze", "--quiet"}));
  EXPECT_EQ(resumed.exit_code, 0) << resumed.out << resumed.err;
  const Store store = Store::open_read_only(db.string());
  EXPECT_EQ(store.design_hash().value_or(""), "08d437ffe546bf8f");
}

}  // namespace
}  // namespace demsa
