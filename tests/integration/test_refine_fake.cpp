// `demsa extend` and `demsa refine` end to end against the fake LIGGGHTS (tests/integration/fake_liggghts): a raised
// [design] samples and `demsa extend` add points and run only those, shrinking is refused, refine adds batches
// until its budget or target, and both survive SIGKILL at random moments.
#include "orchestrator/study/store.hpp"

#include "support/process.hpp"
#include "support/test_support.hpp"

#include <signal.h>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace demsa {

using namespace demsa::study;
namespace {

namespace fs = std::filesystem;
using test::starts_per_sample;

std::string study_text(int samples, const std::string& method = "lhs-maximin") {
  return test::StudyToml{.name = "fake-refine",
                         .experiment = "pile",
                         .seed = 7,
                         .method = method,
                         .samples = samples,
                         .parameters =
                             "mu_pp = { low = 0.2, high = 0.8 }\nmu_r_pp = { low = 0.05, high = 0.3 }\n"
                             "e_r = { low = 0.3, high = 0.7 }\n",
                         .tables = "[pile]\nparticles = 300\n",
                         .run = test::fake_liggghts_run_lines() + "parallel = 2\noversubscribe = true\nretries = 1\n",
                         .analysis =
                             "metamodels = [\"rsm2\", \"gp\"]\nbootstrap = 20\nbase_samples = 256\n"
                             "second_order = false\n"}
      .text();
}

/// Every sample of the store has exactly one done run and the last run of each is the done one; every unit value is
/// in [0,1] and no two samples coincide.
void expect_done_once(const fs::path& dir) {
  const Store store = Store::open_read_only((dir / "study.db").string());
  EXPECT_EQ(store.integrity_check(), "ok");
  std::map<int, std::vector<RunRow>> runs;
  for (const RunRow& r : store.runs()) runs[r.sample].push_back(r);
  const std::vector<SampleRow> samples = store.samples();
  for (const SampleRow& s : samples) {
    SCOPED_TRACE(fmt::format("sample {}", s.sample));
    int done = 0;
    for (const RunRow& r : runs[s.sample]) done += r.state == RunState::done;
    EXPECT_EQ(done, 1);
    ASSERT_FALSE(runs[s.sample].empty());
    EXPECT_EQ(runs[s.sample].back().state, RunState::done);
    for (double u : s.unit) {
      EXPECT_GE(u, 0.0);
      EXPECT_LE(u, 1.0);
    }
    for (const SampleRow& t : samples)
      if (t.sample < s.sample) {
        EXPECT_NE(t.unit, s.unit) << "sample " << t.sample;
      }
  }
}

TEST(ExtendFake, RaisedSamplesRunOnlyTheNewPointsAndShrinkingIsRefused) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study_text(8));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const std::vector<std::string> args = test::run_args(tmp, {"--no-analyze", "--quiet"});
  ASSERT_EQ(test::run_demsa(args).exit_code, 0);
  const std::vector<SampleRow> before = Store::open_read_only((tmp / "study" / "study.db").string()).samples();

  test::write_file(tmp / "study.toml", study_text(13));
  const test::CommandResult grown = test::run_demsa(args);
  ASSERT_EQ(grown.exit_code, 0) << grown.out << grown.err;
  {
    const Store store = Store::open_read_only((tmp / "study" / "study.db").string());
    const std::vector<SampleRow> after = store.samples();
    ASSERT_EQ(after.size(), 13u);
    EXPECT_EQ(store.design_samples(), 13);
    for (std::size_t i = 0; i < before.size(); ++i) EXPECT_EQ(after[i].unit, before[i].unit) << "sample " << i;
    bool extended = false;
    for (const EventRow& e : store.events()) extended |= e.kind == "extended";
    EXPECT_TRUE(extended);
  }
  const std::map<int, int> starts = starts_per_sample(tmp.path());
  for (int k = 0; k < 13; ++k) EXPECT_EQ(starts.count(k) ? starts.at(k) : 0, 1) << "sample " << k;
  expect_done_once(tmp / "study");
  const std::string design = test::read_file(tmp / "study" / "design.csv");
  EXPECT_EQ(std::count(design.begin(), design.end(), '\n'), 14);

  // Shrinking: refused, naming the count the study has.
  test::write_file(tmp / "study.toml", study_text(10));
  const test::CommandResult shrunk = test::run_demsa(args);
  EXPECT_EQ(shrunk.exit_code, 2);
  EXPECT_NE(shrunk.err.find("has 13 design samples already"), std::string::npos) << shrunk.err;
  // Another change with the growth is still a changed study.
  test::write_file(tmp / "study.toml", study_text(16, "lhs"));
  const test::CommandResult changed = test::run_demsa(args);
  EXPECT_EQ(changed.exit_code, 2);
  EXPECT_NE(changed.err.find("design-relevant settings differ"), std::string::npos) << changed.err;
}

TEST(ExtendFake, ExtendCommandGrowsASobolDesignWithItsNextPoints) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study_text(8, "sobol"));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  ASSERT_EQ(test::run_demsa(test::run_args(tmp, {"--no-analyze", "--quiet"})).exit_code, 0);
  const std::string dir = (tmp / "study").string();
  const test::CommandResult extend = test::run_demsa({"extend", dir, "--samples", "16"});
  ASSERT_EQ(extend.exit_code, 0) << extend.out << extend.err;
  EXPECT_NE(extend.out.find("8 design samples added"), std::string::npos) << extend.out;
  // The frozen study file says 16 now; a fresh Sobol' study of 16 has the same points.
  const test::CommandResult fresh_design =
      test::run_demsa({"run", (tmp / "study" / "study.toml").string(), "--dir", (tmp / "fresh").string(), "--dry-run"});
  ASSERT_EQ(fresh_design.exit_code, 0) << fresh_design.err;
  EXPECT_EQ(test::read_file(tmp / "fresh" / "design.csv"), test::read_file(tmp / "study" / "design.csv"));
  // Only the new cases run.
  ASSERT_EQ(test::run_demsa({"run", (tmp / "study" / "study.toml").string(), "--dir", dir, "--no-analyze", "--quiet"})
                .exit_code,
            0);
  const std::map<int, int> starts = starts_per_sample(tmp.path());
  for (int k = 0; k < 16; ++k) EXPECT_EQ(starts.count(k) ? starts.at(k) : 0, 1) << "sample " << k;
  // `demsa case --sample` takes an added sample's id (the study file still says 8; the folder's store has 16) and
  // writes the case `demsa run` ran; an id the study does not have is refused, naming the valid ones.
  const test::CommandResult added = test::run_demsa(
      {"case", (tmp / "study.toml").string(), "--sample", "13", "--dir", dir, "-o", (tmp / "case13").string()});
  ASSERT_EQ(added.exit_code, 0) << added.out << added.err;
  const auto case_json = [](const fs::path& folder) {
    return nlohmann::json::parse(test::read_file(folder / "case.json"));
  };
  EXPECT_EQ(case_json(tmp / "case13").at("sample"), 13);
  EXPECT_EQ(case_json(tmp / "case13").at("unit_point"), case_json(tmp / "study" / "cases" / "000013").at("unit_point"));
  const test::CommandResult missing = test::run_demsa(
      {"case", (tmp / "study.toml").string(), "--sample", "16", "--dir", dir, "-o", (tmp / "case16").string()});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("--sample 16: no such case in study folder " + dir + ": design samples 0-15"),
            std::string::npos)
      << missing.err;
  // Same count: nothing to add; fewer: refused; not a number: refused by the option check.
  EXPECT_EQ(test::run_demsa({"extend", dir, "--samples", "16"}).exit_code, 0);
  const test::CommandResult shrink = test::run_demsa({"extend", dir, "--samples", "12"});
  EXPECT_EQ(shrink.exit_code, 2);
  EXPECT_NE(shrink.err.find("can grow, not shrink"), std::string::npos) << shrink.err;
  EXPECT_EQ(test::run_demsa({"extend", dir, "--samples", "2.5"}).exit_code, 2);
}

TEST(ExtendFake, GrowthSurvivesSigkillAtRandomMoments) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study_text(6));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.3);
  const std::vector<std::string> args = test::run_args(tmp, {"--no-analyze", "--quiet"});
  ASSERT_EQ(test::run_demsa(args).exit_code, 0);
  test::write_file(tmp / "study.toml", study_text(14));
  test::kill_at_random_moments(args, tmp / "demsa.log", 31, 6, 50, 1500);
  const test::CommandResult final_run = test::run_demsa(args);
  ASSERT_EQ(final_run.exit_code, 0) << final_run.out << final_run.err << test::read_file(tmp / "demsa.log");
  const Store store = Store::open_read_only((tmp / "study" / "study.db").string());
  EXPECT_EQ(store.samples().size(), 14u);
  EXPECT_EQ(store.design_samples(), 14);
  int extended = 0;
  for (const EventRow& e : store.events()) extended += e.kind == "extended";
  EXPECT_EQ(extended, 1);  // one extension, whichever run made it
  expect_done_once(tmp / "study");
  const std::map<int, int> starts = starts_per_sample(tmp.path());
  for (int k = 0; k < 6; ++k) EXPECT_EQ(starts.at(k), 1) << "sample " << k << " ran again";
}

TEST(RefineFake, AddsBatchesUntilTheBudgetAndRecordsTheHistory) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study_text(8));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const std::string dir = (tmp / "study").string();
  ASSERT_EQ(test::run_demsa(test::run_args(tmp, {"--no-analyze", "--quiet"})).exit_code, 0);
  // A width no 17 samples reach: the budget ends it (exit 1), after 8 -> 11 -> 14 -> 17.
  const test::CommandResult refine =
      test::run_demsa({"refine", dir, "--target-ci", "0.00001", "--batch", "3", "--max-samples", "17", "--quiet"});
  EXPECT_EQ(refine.exit_code, 1) << refine.out << refine.err;
  EXPECT_NE(refine.out.find("budget of 17 samples is spent"), std::string::npos) << refine.out;
  const Store store = Store::open_read_only((tmp / "study" / "study.db").string());
  EXPECT_EQ(store.samples().size(), 17u);
  EXPECT_EQ(store.design_samples(), 8);
  const std::vector<RefineStep> history = store.refine_history();
  ASSERT_EQ(history.size(), 4u);
  const std::vector<int> expected{8, 11, 14, 17};
  for (std::size_t i = 0; i < history.size(); ++i) {
    EXPECT_EQ(history[i].samples, expected[i]);
    EXPECT_EQ(history[i].iteration, static_cast<int>(i) + 1);
    ASSERT_TRUE(history[i].max_half_width.count("angle"));
    EXPECT_FALSE(history[i].max_half_width.at("angle") <= 0.0);  // positive, or NaN without intervals
    EXPECT_EQ(history[i].decision, i + 1 < history.size() ? "added 3" : "budget");
  }
  expect_done_once(tmp / "study");
  const std::string csv = test::read_file(tmp / "study" / "analysis" / "refine.csv");
  EXPECT_EQ(csv.rfind("iteration,samples,decision,target,max_half_width_angle,max_half_width_pile_height\n", 0), 0u)
      << csv;
  const nlohmann::json json = nlohmann::json::parse(test::read_file(tmp / "study" / "analysis" / "refine.json"));
  ASSERT_EQ(json.size(), 4u);
  EXPECT_TRUE(json[0].at("indices").at("angle").at("S1").contains("mu_pp"));

  // A reachable width ends at once (exit 0) without adding a sample; the report plots the history.
  const test::CommandResult reached = test::run_demsa({"refine", dir, "--target-ci", "1", "--quiet"});
  EXPECT_EQ(reached.exit_code, 0) << reached.out << reached.err;
  EXPECT_EQ(Store::open_read_only((tmp / "study" / "study.db").string()).samples().size(), 17u);
  const test::CommandResult report = test::run_demsa({"report", dir});
  ASSERT_EQ(report.exit_code, 0) << report.out << report.err;
  EXPECT_TRUE(fs::exists(tmp / "study" / "report" / "refine_history.png"));
  EXPECT_NE(test::read_file(tmp / "study" / "report" / "report.md").find("## Refinement"), std::string::npos);
}

TEST(RefineFake, ResumeAfterSigkillAtRandomMomentsRunsEachSampleOnce) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study_text(6));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.3);
  const std::string dir = (tmp / "study").string();
  ASSERT_EQ(test::run_demsa(test::run_args(tmp, {"--no-analyze", "--quiet"})).exit_code, 0);
  const std::vector<std::string> args{"refine",        dir,  "--target-ci", "0.00001", "--batch", "2",
                                      "--max-samples", "14", "--quiet"};
  test::kill_at_random_moments(args, tmp / "demsa.log", 77, 6, 200, 2500);
  const test::CommandResult final_run = test::run_demsa(args);
  EXPECT_EQ(final_run.exit_code, 1) << final_run.out << final_run.err << test::read_file(tmp / "demsa.log");
  const Store store = Store::open_read_only((tmp / "study" / "study.db").string());
  EXPECT_EQ(store.samples().size(), 14u);
  expect_done_once(tmp / "study");
  const std::map<int, int> starts = starts_per_sample(tmp.path());
  std::map<int, int> rows;
  for (const RunRow& r : store.runs()) ++rows[r.sample];
  for (const auto& [sample, n] : starts) EXPECT_LE(n, rows[sample]) << "sample " << sample;
  // The history: one row per number of done samples, increasing, the last the budget.
  const std::vector<RefineStep> history = store.refine_history();
  ASSERT_FALSE(history.empty());
  EXPECT_EQ(history.back().samples, 14);
  EXPECT_EQ(history.back().decision, "budget");
  for (std::size_t i = 1; i < history.size(); ++i) EXPECT_GT(history[i].samples, history[i - 1].samples);
}

}  // namespace
}  // namespace demsa
