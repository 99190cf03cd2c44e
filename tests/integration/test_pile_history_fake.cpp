// The pile in time against the fake LIGGGHTS (tests/integration/fake_liggghts, FAKE_LIGGGHTS_DRIFT): its snapshots
// of a cone whose angle changes at a known rate give the series, angle@T and angle_drift; a pile whose angle still
// moves is stored unsettled and flagged with its drift; measure_times beyond the cap and a changed measure_times on a
// finished study are refused.
#include "orchestrator/study/store.hpp"

#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

namespace demsa {
namespace {

namespace fs = std::filesystem;

/// A pile study over μ_PW and μ_R,PW (the fake's angle: 24 + 12 u0 + 6 u1²) with settling of 1 s, checked every 0.05 s,
/// a snapshot every 0.1 s, and `pile` lines more.
std::string history_study(int samples, const std::string& pile) {
  return test::StudyToml{
      .name = "history",
      .experiment = "pile",
      .samples = samples,
      .parameters = "mu_pw = { low = 0.4, high = 1.9 }\nmu_r_pw = { low = 0.05, high = 0.5 }\n",
      .tables = "[pile]\nsettle_time = 1.0\nsettle_check_time = 0.05\nhistory_interval = 0.1\n" + pile,
      .run = test::fake_liggghts_run_lines() + "parallel = 2\noversubscribe = true\n",
      .analysis = "metamodels = [\"rsm1\"]\nbootstrap = 0\nbase_samples = 64\nsecond_order = false\n"}
      .text();
}

/// Lines of a text file.
int line_count(const fs::path& file) {
  std::ifstream in(file);
  int n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

}  // namespace

TEST(PileHistoryFake, SnapshotsGiveTheSeriesTheAngleAtEachTimeAndTheDrift) {
  test::TempDir tmp;
  // 4 samples: rsm1 in two parameters has 3 terms, and on 3 samples its Q² is not computable.
  test::write_file(tmp / "study.toml", history_study(4, "measure_times = [0.3, 1.0]\n"));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::ScopedEnv drift("FAKE_LIGGGHTS_DRIFT",
                              "-2");  // the angle falls by 2° per second: 2° in the second of settling
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet", "--no-analyze"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const study::Store store = study::Store::open_read_only((tmp / "study" / "study.db").string());
  ASSERT_EQ(store.observables().size(), 4u);
  for (const auto& [sample, values] : store.observables()) {
    SCOPED_TRACE(fmt::format("sample {}", sample));
    const double final_angle = values.at("angle");
    // The cone 0.7 s before the end stood 1.4° higher; the drift is the rate the fake was given.
    EXPECT_NEAR(values.at("angle@1"), final_angle, 1e-9);
    EXPECT_NEAR(values.at("angle@0.3"), final_angle + 1.4, 0.05);
    EXPECT_NEAR(values.at("angle_drift"), -2.0, 0.05);
    // Every snapshot is stored, by its nominal time: 0, 0.1, ..., 1.0 s.
    for (int k = 0; k <= 10; ++k) {
      const std::string name = fmt::format("angle_series@{}", std::stod(fmt::format("{:.9g}", 0.1 * k)));
      ASSERT_TRUE(values.count(name)) << name;
      EXPECT_NEAR(values.at(name), final_angle + 2.0 * (1.0 - 0.1 * k), 0.05) << name;
    }
    // Still moving at 2°/s, more than drift_limit (1°/s): unsettled.
    EXPECT_EQ(values.at("settled"), 0.0);
  }
  // The case folder holds the series; the snapshots are gone once measured.
  const fs::path case_dir = tmp / "study" / "cases" / "000000";
  ASSERT_TRUE(fs::exists(case_dir / "pile_history.csv"));
  EXPECT_EQ(line_count(case_dir / "pile_history.csv"), 2 + 11);  // comment, header, 11 snapshots
  EXPECT_FALSE(fs::exists(case_dir / "pile_snapshot_0.dump"));
  EXPECT_FALSE(fs::exists(case_dir / "pile_snapshot_20.dump"));

  // status flags the unsettled samples with their drift.
  const test::CommandResult status = test::run_demsa({"status", (tmp / "study").string()});
  ASSERT_EQ(status.exit_code, 0) << status.err;
  EXPECT_NE(status.out.find("unsettled 4 of 4 done"), std::string::npos) << status.out;
  EXPECT_NE(status.out.find("angle_drift -2"), std::string::npos) << status.out;

  // Measured again without the snapshots, from pile_history.csv: the same values.
  const test::CommandResult measure = test::run_demsa({"measure", case_dir.string(), "--json"});
  ASSERT_EQ(measure.exit_code, 0) << measure.out << measure.err;
  const auto again = nlohmann::json::parse(measure.out);
  EXPECT_NEAR(again["observables"]["angle@0.3"].get<double>(), store.observables().at(0).at("angle@0.3"), 1e-12)
      << measure.out;
  EXPECT_NEAR(again["observables"]["angle_drift"].get<double>(), store.observables().at(0).at("angle_drift"), 1e-12);

  // The analysis analyses angle@T like angle and says which samples were still moving.
  const test::CommandResult analyze = test::run_demsa({"analyze", (tmp / "study").string()});
  ASSERT_EQ(analyze.exit_code, 0) << analyze.out << analyze.err;
  EXPECT_NE(analyze.out.find("angle@0.3"), std::string::npos) << analyze.out;
  EXPECT_NE(analyze.out.find("unsettled, still moving at the end of settling"), std::string::npos) << analyze.out;
}

TEST(PileHistoryFake, AStaticPileIsSettledAndKeptSnapshotsStay) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", history_study(2, "keep_snapshots = true\n"));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::ScopedEnv drift("FAKE_LIGGGHTS_DRIFT", "0");
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet", "--no-analyze"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const study::Store store = study::Store::open_read_only((tmp / "study" / "study.db").string());
  for (const auto& [sample, values] : store.observables()) {
    EXPECT_NEAR(values.at("angle_drift"), 0.0, 1e-9);
    EXPECT_EQ(values.at("settled"), 1.0);
    EXPECT_FALSE(values.count("angle@0.3"));  // no measure_times
  }
  EXPECT_TRUE(fs::exists(tmp / "study" / "cases" / "000001" / "pile_snapshot_20.dump"));
  const test::CommandResult status = test::run_demsa({"status", (tmp / "study").string()});
  EXPECT_EQ(status.out.find("unsettled"), std::string::npos) << status.out;
}

TEST(PileHistoryFake, MeasureTimesBeyondTheCapAreRefused) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", history_study(2, "measure_times = [0.5, 1.5]\n"));
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--dry-run"}));
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("measure_times"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("1.5 s lies beyond settle_time = 1 s"), std::string::npos) << run.err;
  test::write_file(tmp / "study.toml", history_study(2, "measure_times = [0.5, 0.3]\n"));
  const test::CommandResult decreasing = test::run_demsa(test::run_args(tmp, {"--dry-run"}));
  EXPECT_NE(decreasing.exit_code, 0);
  EXPECT_NE(decreasing.err.find("times must increase"), std::string::npos) << decreasing.err;
}

TEST(PileHistoryFake, ChangingMeasureTimesOnAFinishedStudyIsRefused) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", history_study(2, "measure_times = [0.5]\n"));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::ScopedEnv drift("FAKE_LIGGGHTS_DRIFT", "0");
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet", "--no-analyze"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  test::write_file(tmp / "study.toml", history_study(2, "measure_times = [0.5, 0.8]\n"));
  const test::CommandResult again = test::run_demsa(test::run_args(tmp, {"--quiet", "--no-analyze"}));
  EXPECT_NE(again.exit_code, 0);
  EXPECT_NE(again.err.find("measure_times"), std::string::npos) << again.err;
}

}  // namespace demsa
