// A real LIGGGHTS study end to end: 6 tiny piles through `demsa run` (local executor, 1 rank each), then the
// analysis. Checks that every case ran cleanly, that the measured angles are physical, and that the store and the
// analysis files agree.
#include "orchestrator/study/store.hpp"

#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>

namespace demsa {

using namespace demsa::study;
namespace {

namespace fs = std::filesystem;

const std::string k_tiny_study =
    test::StudyToml{.name = "tiny-real-pile",
                    .seed = 3,
                    .method = "lhs-maximin",
                    .samples = 6,
                    .parameters = "mu_pp = { low = 0.2, high = 0.9 }\nmu_r_pp = { low = 0.02, high = 0.3 }\n",
                    .tables = "[material]\nE = 1e8\n\n[pile]\nparticles = 120\nsettle_time = 0.1\n",
                    .run = "ranks = 1\ntimeout = 600\nretries = 0\n",
                    .analysis =
                        "metamodels = [\"rsm2\", \"rbf-cubic\"]\nbootstrap = 0\nbase_samples = 1024\n"
                        "second_order = false\n"}
        .text();

TEST(StudyReal, TinyPileStudyRunsEndToEndWithAnalysis) {
  test::TempDir tmp;
  test::write_file(tmp / "tiny.toml", k_tiny_study);
  const fs::path dir = tmp / "tiny";
  const test::CommandResult run =
      test::run_demsa({"run", (tmp / "tiny.toml").string(), "--dir", dir.string(), "--progress-interval", "5"});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("6 of 6 samples done"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("Sobol' S1 of angle"), std::string::npos) << run.out;

  const Store store = Store::open_read_only((dir / "study.db").string());
  EXPECT_EQ(store.integrity_check(), "ok");
  const auto observables = store.observables();
  ASSERT_EQ(observables.size(), 6u);
  for (const auto& [sample, values] : observables) {
    SCOPED_TRACE(fmt::format("sample {}", sample));
    // A pile of real spheres on the pedestal: an angle between flat and vertical, a height of a few particles.
    EXPECT_GT(values.at("angle"), 2.0);
    EXPECT_LT(values.at("angle"), 80.0);
    EXPECT_GT(values.at("pile_height"), 0.002);
    EXPECT_LT(values.at("pile_height"), 0.1);
  }
  for (const RunRow& r : store.runs()) {
    EXPECT_EQ(r.state, RunState::done);
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_GT(r.cpu_seconds, 0.1);  // LIGGGHTS's CPU time reached demsa through run.sh and mpirun
    EXPECT_FALSE(r.host.empty());
  }
  const nlohmann::json analysis = nlohmann::json::parse(test::read_file(dir / "analysis" / "analysis.json"));
  EXPECT_EQ(analysis.at("samples_used").size(), 6u);
  // rsm2 in 2 inputs has 6 terms: fitted exactly through 6 points, its Q² is not computable and it gives no index;
  // the table lists rbf-cubic alone.
  const std::string table = test::read_file(dir / "analysis" / "table_angle.csv");
  EXPECT_NE(table.find("rbf-cubic,"), std::string::npos) << table;
  EXPECT_EQ(table.find("rsm2,"), std::string::npos) << table;
}

}  // namespace
}  // namespace demsa
