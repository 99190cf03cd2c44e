// The posterior (analysis/calibration_posterior.hpp): a chain that has not converged fails the check, with its
// verdict in the text and posterior.json; the printed form: what is listed and what is left to posterior.json.
#include "orchestrator/analysis/calibration_posterior.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

using namespace demsa::analysis;
using namespace demsa::study;

namespace demsa::test {
namespace {

namespace fs = std::filesystem;

/// Seven parameters whose only strong correlation is p1 ~ p2 (-0.6); p3 ~ p4 at 0.3 is on the threshold.
PosteriorOutcome seven_parameters() {
  PosteriorOutcome o;
  o.studies = {"pile"};
  for (int j = 1; j <= 7; ++j) {
    PosteriorParameter p;
    p.name = fmt::format("p{}", j);
    p.identified = "no";
    o.parameters.push_back(p);
  }
  o.correlation.assign(7, std::vector<double>(7, 0.05));
  for (int j = 0; j < 7; ++j) o.correlation[j][j] = 1.0;
  o.correlation[0][1] = o.correlation[1][0] = -0.6;
  o.correlation[2][3] = o.correlation[3][2] = 0.3;
  return o;
}

TEST(PosteriorText, ListsOnlyTheStrongCorrelationsAndCountsTheOthers) {
  const std::string text = posterior_text(seven_parameters());
  EXPECT_NE(text.find("correlations with |r| >= 0.3 (19 other pairs below, all in posterior.json):\n"
                      "  p1 ~ p2: -0.600\n  p3 ~ p4: +0.300\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("p1 ~ p3"), std::string::npos) << text;
  // The full matrix stays in the JSON.
  EXPECT_NE(posterior_to_json(seven_parameters()).find("\"correlation\""), std::string::npos);
}

/// A pile study of 30 done samples over two frictions whose angle is 22 + 14 u2 + 5 u1², fitted by rsm2, and the
/// posterior of angle = 30 ± 0.5 with `steps` kept steps per walker, written to DIR/calibration.
PosteriorOutcome posterior_with_steps(const TempDir& dir, int steps) {
  SyntheticStudy study = start_synthetic_study(
      dir.path(),
      StudyToml{.seed = 3, .samples = 30, .analysis = "metamodels = [\"rsm2\"]\nbootstrap = 0\nbase_samples = 256\n"}
          .text(),
      2);
  record_every_sample_done(study, [](const SampleRow& row) -> std::map<std::string, double> {
    return {{"angle", 22.0 + 14.0 * row.unit[1] + 5.0 * row.unit[0] * row.unit[0]}};
  });
  PosteriorOptions options;
  options.dirs = {dir.path()};
  options.targets = {MeasuredTarget{.name = "angle", .value = 30.0, .sd = 0.5}};
  options.steps = steps;
  options.burn_in = 0;
  return calibrate_posterior(options);
}

TEST(PosteriorCheck, AChainThatHasNotConvergedFailsTheCheckAndSaysWhatToRaise) {
  // 20 steps per walker from the densest prior points: far fewer than 50 τ. It used to be a passed check (exit 0)
  // with a warning on standard error only.
  TempDir dir;
  const PosteriorOutcome short_chain = posterior_with_steps(dir, 20);
  ASSERT_FALSE(short_chain.converged);
  ASSERT_EQ(short_chain.problems.size(), 1u);
  const std::string& problem = short_chain.problems.front();
  EXPECT_EQ(problem.rfind("UNCONVERGED: ", 0), 0u) << problem;
  EXPECT_NE(problem.find("20 steps per walker are fewer than 50 τ"), std::string::npos) << problem;
  EXPECT_NE(problem.find("raise the steps per walker"), std::string::npos) << problem;
  // Everything is written all the same, and posterior.json carries the verdict.
  EXPECT_TRUE(fs::exists(dir / "calibration" / "posterior_samples.csv"));
  const nlohmann::json j = nlohmann::json::parse(read_file(dir / "calibration" / "posterior.json"));
  EXPECT_FALSE(j.at("checks").at("passed").get<bool>());
  EXPECT_EQ(j.at("checks").at("problems").at(0).get<std::string>(), problem);
  EXPECT_FALSE(j.at("diagnostics").at("converged").get<bool>());
  EXPECT_EQ(read_posterior(dir / "calibration" / "posterior.json").problems, short_chain.problems);
  // The text gives the verdict with the diagnostics and under the failed check.
  const std::string text = posterior_text(short_chain);
  EXPECT_NE(text.find("diagnostics: acceptance"), std::string::npos) << text;
  EXPECT_NE(text.find("; UNCONVERGED: 20 steps per walker"), std::string::npos) << text;
  EXPECT_NE(text.find("CHECK FAILED: the chain has not converged; this posterior is not an answer:\n  UNCONVERGED: "),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("contradict"), std::string::npos) << text;

  // A chain of 3000 steps converges: the check passes.
  TempDir long_dir;
  const PosteriorOutcome long_chain = posterior_with_steps(long_dir, 3000);
  EXPECT_TRUE(long_chain.converged) << long_chain.advice;
  EXPECT_TRUE(long_chain.problems.empty()) << long_chain.problems.front();
  EXPECT_EQ(posterior_text(long_chain).find("UNCONVERGED"), std::string::npos);
}

}  // namespace
}  // namespace demsa::test
