// [pile] angle_estimator: parsed and checked by the settings table, in the design hash only when not "paper", and
// the estimator measure_case() measures a finished pile with (as its case.json records it).
#include "orchestrator/exec/measure.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/parameters.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/pile_angle.hpp"
#include "support/test_support.hpp"
#include "tests/postprocess/synthetic_cone.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <string>

namespace demsa {
namespace {

namespace pile = experiments::pile;

const std::string k_base =
    "[study]\nname = \"s\"\nexperiment = \"pile\"\n[parameters]\nE = { low = 1e8, high = 1e9, scale = \"log\" }\n";

TEST(AngleEstimatorSetting, ParsedCheckedAndHashedWhenNotTheDefault) {
  const study::StudyConfig defaults = experiments::parse_study(k_base, "study.toml");
  EXPECT_EQ(pile::settings(defaults).angle_estimator, "paper");
  const study::StudyConfig robust =
      experiments::parse_study(k_base + "[pile]\nangle_estimator = \"robust\"\n", "study.toml");
  EXPECT_EQ(pile::settings(robust).angle_estimator, "robust");
  EXPECT_NE(study::design_hash(robust), study::design_hash(defaults));
  EXPECT_EQ(
      study::design_hash(experiments::parse_study(k_base + "[pile]\nangle_estimator = \"paper\"\n", "study.toml")),
      study::design_hash(defaults));
  const std::string message = test::message_of<util::UserError>(
      [] { experiments::parse_study(k_base + "[pile]\nangle_estimator = \"best\"\n", "study.toml"); });
  EXPECT_NE(message.find("study.toml:7"), std::string::npos) << message;
  EXPECT_NE(message.find("unknown value 'best' (valid: paper, robust)"), std::string::npos) << message;
  // The study accepts exactly the estimators postprocess/ has.
  EXPECT_EQ(experiments::settings_table().find("pile", "angle_estimator")->choices,
            postprocess::angle_estimator_names());
}

TEST(AngleEstimatorSetting, StudyPileSettingsBecomeTheOptions) {
  study::StudyConfig config = experiments::parse_study(
      k_base +
          "[pile]\npedestal_radius = 0.04\npedestal_height = 0.004\ndirections = 90\nlevels = 7\n"
          "target_angle = 30.5\nangle_estimator = \"robust\"\n",
      "study.toml");
  const postprocess::PileAngleOptions o = pile::angle_options(pile::settings(config));
  EXPECT_DOUBLE_EQ(o.pedestal_radius, 0.04);
  EXPECT_DOUBLE_EQ(o.pedestal_top, 0.004);
  EXPECT_EQ(o.directions, 90);
  EXPECT_EQ(o.levels, 7);
  EXPECT_DOUBLE_EQ(o.target_angle, 30.5);
  EXPECT_EQ(o.estimator, postprocess::AngleEstimator::robust);
  // The band is the estimator's own: left unset, 0.25-0.80 for robust, the paper's 0.20-0.75 otherwise.
  EXPECT_FALSE(o.level_low || o.level_high);
  EXPECT_DOUBLE_EQ(o.low_level(), postprocess::k_robust_level_low);
  EXPECT_DOUBLE_EQ(o.high_level(), postprocess::k_robust_level_high);
  pile::settings(config).angle_estimator = "paper";
  EXPECT_DOUBLE_EQ(pile::angle_options(pile::settings(config)).low_level(), 0.20);
  EXPECT_DOUBLE_EQ(pile::angle_options(pile::settings(config)).high_level(), 0.75);
}

TEST(AngleEstimatorSetting, MeasureCaseUsesIt) {
  test::TempDir tmp;
  test::SyntheticConeOptions cone;
  cone.jitter = 2e-3;
  const postprocess::Particles particles = test::make_synthetic_cone(cone);
  test::write_file(tmp / pile::k_final_dump, test::synthetic_dump_text(particles));
  // The case.json of a pile case records the pedestal and the study's angle estimator.
  const auto write_case_json = [&](const char* estimator) {
    test::write_file(tmp / study::k_case_json,
                     fmt::format("{{\"experiment\": \"pile\", \"pile\": {{\"pedestal_radius_m\": 0.05, "
                                 "\"pedestal_height_m\": 0.005, \"angle_measurement\": {{\"directions\": 180, "
                                 "\"levels\": 10, \"estimator\": \"{}\"}}}}}}\n",
                                 estimator));
  };
  write_case_json("paper");
  const double paper = exec::measure_case(tmp.path()).at(std::string(pile::k_angle));
  write_case_json("robust");
  const double robust = exec::measure_case(tmp.path()).at(std::string(pile::k_angle));
  postprocess::PileAngleOptions options;
  options.estimator = postprocess::AngleEstimator::robust;
  options.level_low = postprocess::k_robust_level_low;  // the robust estimator's own band of levels
  options.level_high = postprocess::k_robust_level_high;
  // The dump holds 9 significant digits: the same angle to well below a thousandth of a degree.
  EXPECT_NEAR(robust, postprocess::measure_pile_angle(particles, options).angle, 1e-3);
  EXPECT_NEAR(paper, postprocess::measure_pile_angle(particles, {}).angle, 1e-3);
  EXPECT_GT(robust - paper, 0.3);  // 2 mm of jitter: the paper's estimator reads lower
}

}  // namespace
}  // namespace demsa
