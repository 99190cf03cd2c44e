// Calibration of a study on its metamodels (orchestrator/calibration_cmd.hpp): a synthetic study whose observables
// are known functions of the parameters, so that the parameters matching given targets are known exactly.
#include "orchestrator/analysis/calibration.hpp"
#include "orchestrator/analysis/calibration_posterior.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::analysis;

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

// angle and pile height as functions of the unit-cube point (u1 = μ_PP, u2 = μ_R,PP): quadratic, so the RSM of
// degree 2 reproduces them exactly, and with one solution in [0,1]² for any pair of reachable targets.
double angle_of(double u1, double u2) { return 22.0 + 14.0 * u2 + 5.0 * u1 * u1; }
double height_of(double u1, double u2) { return 0.02 + 0.01 * u1 + 0.004 * u2; }

// Two friction parameters, mu_pp in [0.7, 1.9] and mu_r_pp in [0.05, 0.5] (StudyToml's defaults).
const StudyToml k_study{.name = "synthetic", .seed = 7, .samples = 30};

/// DIR/study.toml and DIR/study.db with 30 done samples (random points, fixed seed) measuring angle and height.
void write_synthetic_study(const fs::path& dir) {
  SyntheticStudy study = start_synthetic_study(dir, k_study.text(), 11);
  for (const SampleRow& row : study.samples) {
    const long run = study.store.add_run(row.sample, 1);
    RunOutcome outcome;
    outcome.exit_code = 0;
    outcome.cpu_seconds = 2.0;
    outcome.wall_seconds = 2.5;
    study.store.record_done(
        run, outcome,
        {{"angle", angle_of(row.unit[0], row.unit[1])}, {"pile_height", height_of(row.unit[0], row.unit[1])}});
  }
}

/// Options of a calibration of the synthetic study, written to `dir`.
CalibrateOptions synthetic_study_options(const TempDir& dir) {
  write_synthetic_study(dir.path());
  CalibrateOptions options;
  options.dir = dir.path();
  return options;
}

TEST(Calibration, RecoversKnownOptimumWithinTwoPercentOfRange) {
  TempDir dir;
  CalibrateOptions options = synthetic_study_options(dir);
  const double u1 = 0.35;
  const double u2 = 0.62;
  options.targets = {{.name = "angle", .value = angle_of(u1, u2)}, {.name = "pile_height", .value = height_of(u1, u2)}};
  const CalibrationOutcome o = calibrate_study(options);
  ASSERT_EQ(o.unit.size(), 2u);
  EXPECT_NEAR(o.unit[0], u1, 0.02);  // 2% of each parameter's range
  EXPECT_NEAR(o.unit[1], u2, 0.02);
  EXPECT_NEAR(o.physical[0], 0.7 + 1.2 * u1, 0.02 * 1.2);
  EXPECT_NEAR(o.physical[1], 0.05 + 0.45 * u2, 0.02 * 0.45);
  ASSERT_EQ(o.targets.size(), 2u);
  EXPECT_EQ(o.targets[0].model, "rsm2");  // exact for a quadratic: Q² = 1
  EXPECT_NEAR(o.targets[0].q2, 1.0, 1e-9);
  EXPECT_NEAR(o.targets[0].predicted, angle_of(u1, u2), 1e-3);
  EXPECT_NEAR(o.targets[1].predicted, height_of(u1, u2), 1e-6);
  EXPECT_LT(o.misfit, 1e-8);
  EXPECT_EQ(o.samples, 30);
  EXPECT_EQ(o.seed, 7u);
  EXPECT_FALSE(o.verified);
}

TEST(Calibration, WritesCalibrationJsonThatReadsBack) {
  TempDir dir;
  CalibrateOptions options = synthetic_study_options(dir);
  options.targets = {{.name = "angle", .value = 30}};
  options.weights = {{"angle", 2.0}};
  const CalibrationOutcome o = calibrate_study(options);
  const CalibrationOutcome back = read_calibration(dir / "analysis/calibration.json");
  EXPECT_EQ(back.parameters, o.parameters);
  EXPECT_EQ(back.unit, o.unit);
  ASSERT_EQ(back.targets.size(), 1u);
  EXPECT_EQ(back.targets[0].weight, 2.0);
  EXPECT_EQ(back.targets[0].scale, 30.0);
  EXPECT_NEAR(back.targets[0].predicted, 30.0, 1e-3);
  EXPECT_FALSE(back.targets[0].measured.has_value());
  EXPECT_NE(calibration_text(o).find("angle"), std::string::npos);
}

TEST(Calibration, DefaultTargetIsTheStudysTargetAngle) {
  TempDir dir;
  CalibrateOptions options = synthetic_study_options(dir);
  const CalibrationOutcome o = calibrate_study(options);
  ASSERT_EQ(o.targets.size(), 1u);
  EXPECT_EQ(o.targets[0].name, "angle");
  EXPECT_EQ(o.targets[0].target, 33.5);  // [pile] target_angle default, paper §3.3
  EXPECT_NEAR(o.targets[0].predicted, 33.5, 1e-3);
  // Any point on the curve angle = 33.5 is an optimum: check that this one lies on it.
  EXPECT_NEAR(angle_of(o.unit[0], o.unit[1]), 33.5, 1e-3);
}

TEST(Calibration, ForcedModelIsUsed) {
  TempDir dir;
  CalibrateOptions options = synthetic_study_options(dir);
  options.model = "rbf-cubic";
  options.targets = {{.name = "angle", .value = 28}};
  const CalibrationOutcome o = calibrate_study(options);
  EXPECT_EQ(o.targets[0].model, "rbf-cubic");
  EXPECT_LT(o.targets[0].q2, 1.0);
  EXPECT_NEAR(o.targets[0].predicted, 28.0, 1e-3);
}

std::string error_of(const CalibrateOptions& options) {
  try {
    calibrate_study(options);
  } catch (const UserError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Calibration, UnknownObservableListsTheValidOnes) {
  TempDir dir;
  CalibrateOptions options = synthetic_study_options(dir);
  options.targets = {{.name = "angel", .value = 33}};
  const std::string e = error_of(options);
  EXPECT_NE(e.find("unknown observable 'angel'"), std::string::npos) << e;
  EXPECT_NE(e.find("angle, pile_height"), std::string::npos) << e;
}

TEST(Calibration, BadTargetsAndWeightsNameTheField) {
  TempDir dir;
  CalibrateOptions options = synthetic_study_options(dir);
  options.targets = {{.name = "angle", .value = std::nan("")}};
  EXPECT_EQ(error_of(options), "CalibrateOptions.targets 'angle=nan': the value must be a finite number");
  options.targets = {{.name = "angle", .value = 30}, {.name = "angle", .value = 31}};
  EXPECT_EQ(error_of(options), "CalibrateOptions.targets: angle is given twice");
  options.targets = {{.study = "other", .name = "angle", .value = 30}};
  EXPECT_EQ(error_of(options),
            "CalibrateOptions.targets 'other:angle=30': the study is named 'synthetic', not 'other'");
  options.targets = {{.name = "angle", .value = 30}};
  options.weights = {{"pile_height", 2.0}};
  EXPECT_EQ(error_of(options), "CalibrateOptions.weights: pile_height is not a target");
  options.weights = {{"angle", -1.0}};
  EXPECT_EQ(error_of(options), "CalibrateOptions.weights 'angle=-1': one value >= 0 expected");
  options.weights = {};
  options.model = "rsm9";
  EXPECT_NE(error_of(options).find("CalibrateOptions.model: "), std::string::npos) << error_of(options);
  EXPECT_NE(error_of(options).find("rsm9"), std::string::npos) << error_of(options);
}

TEST(CalibrationPosterior, OptionsNameTheFieldAndTheValue) {
  const auto error_of = [](const PosteriorOptions& options) -> std::string {
    try {
      options.validate();
    } catch (const UserError& e) {
      return e.what();
    }
    return "no error";
  };
  PosteriorOptions options;
  options.dirs = {"study"};
  EXPECT_EQ(error_of(options), "PosteriorOptions.targets: no measured value given");
  options.targets = {{.name = "angle", .value = 30, .sd = 0.5}};
  EXPECT_EQ(error_of(options), "no error");
  options.walkers = 7;
  EXPECT_EQ(error_of(options), "PosteriorOptions.walkers 7: must be even and >= 2 × parameters + 2");
  options.walkers = 0;
  options.targets.push_back({.study = "pile", .name = "angle", .value = 31, .sd = -1});
  EXPECT_EQ(error_of(options), "PosteriorOptions.targets 'pile:angle': uncertainty -1 must be a finite number >= 0");
  options.targets.back().sd = 0;  // none given: the metamodel's error alone
  options.weights = {{"angel", 2.0}};
  EXPECT_EQ(error_of(options), "PosteriorOptions.weights: angel is not a target");
  options.weights = {{"pile:angle", 2.0}};
  EXPECT_EQ(error_of(options), "no error");
  options.targets.push_back({.name = "angle", .value = 32, .sd = 1});
  EXPECT_EQ(error_of(options), "PosteriorOptions.targets: angle is given twice");
}

TEST(Calibration, NotAStudyFolder) {
  TempDir dir;
  CalibrateOptions options;
  options.dir = dir.path();
  EXPECT_NE(error_of(options).find("not a study folder"), std::string::npos) << error_of(options);
}

TEST(Calibration, UnreadableCalibrationFileNamesIt) {
  TempDir dir;
  write_file(dir / "calibration.json", "{\"study\": 3}");
  try {
    read_calibration(dir / "calibration.json");
    FAIL() << "accepted";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("calibration.json"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace demsa::test
