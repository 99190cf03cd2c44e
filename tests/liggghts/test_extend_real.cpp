// A real LIGGGHTS study extended: 4 tiny piles through `demsa run`, then `demsa extend` to 6 and `demsa run` again,
// which runs the 2 new cases only (the first 4 keep their runs and angles).
#include "orchestrator/study/store.hpp"

#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

namespace demsa {

using namespace demsa::study;
namespace {

namespace fs = std::filesystem;

TEST(ExtendReal, TinyPileStudyGrowsAndRunsOnlyItsNewCases) {
  test::TempDir tmp;
  test::write_file(
      tmp / "tiny.toml",
      test::StudyToml{.name = "tiny-real-extend",
                      .seed = 5,
                      .method = "lhs-maximin",
                      .samples = 4,
                      .parameters = "mu_pp = { low = 0.2, high = 0.9 }\nmu_r_pp = { low = 0.02, high = 0.3 }\n",
                      .tables = "[material]\nE = 1e8\n\n[pile]\nparticles = 120\nsettle_time = 0.1\n",
                      .run = "ranks = 1\ntimeout = 600\nretries = 0\n",
                      .analysis = "metamodels = [\"rsm1\"]\nbootstrap = 0\nbase_samples = 256\n"
                                  "second_order = false\n"}
          .text());
  const fs::path dir = tmp / "tiny";
  const test::CommandResult first =
      test::run_demsa({"run", (tmp / "tiny.toml").string(), "--dir", dir.string(), "--no-analyze", "--quiet"});
  ASSERT_EQ(first.exit_code, 0) << first.out << first.err;
  std::map<int, double> angles;
  for (const auto& [sample, values] : Store::open_read_only((dir / "study.db").string()).observables())
    angles[sample] = values.at("angle");
  ASSERT_EQ(angles.size(), 4u);

  const test::CommandResult extend = test::run_demsa({"extend", dir.string(), "--samples", "6"});
  ASSERT_EQ(extend.exit_code, 0) << extend.out << extend.err;
  const test::CommandResult second =
      test::run_demsa({"run", (dir / "study.toml").string(), "--dir", dir.string(), "--progress-interval", "5"});
  ASSERT_EQ(second.exit_code, 0) << second.out << second.err;
  EXPECT_NE(second.out.find("6 of 6 samples done (2 now"), std::string::npos) << second.out;

  const Store store = Store::open_read_only((dir / "study.db").string());
  EXPECT_EQ(store.design_samples(), 6);
  EXPECT_EQ(store.runs().size(), 6u);  // one run per sample: the first four were not run again
  for (const auto& [sample, values] : store.observables()) {
    SCOPED_TRACE(fmt::format("sample {}", sample));
    if (sample < 4) {
      EXPECT_EQ(values.at("angle"), angles.at(sample));
    }
    EXPECT_GT(values.at("angle"), 2.0);
    EXPECT_LT(values.at("angle"), 80.0);
  }
}

}  // namespace
}  // namespace demsa
