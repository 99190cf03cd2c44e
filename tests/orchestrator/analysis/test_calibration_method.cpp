// The choice of a calibration's method (analysis/calibration_method.hpp): auto picks bayes for an uncertainty or
// several studies, optimize otherwise; each combination a method refuses names the field and the value.
#include "orchestrator/analysis/calibration_method.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

using namespace demsa::analysis;
using demsa::util::UserError;

namespace demsa::test {
namespace {

const MeasuredTarget k_point{"", "angle", 33.5, 0.0};
const MeasuredTarget k_uncertain{"", "angle", 33.5, 1.5};

TEST(CalibrationMethod, AutoIsBayesForAnUncertaintyOrSeveralStudies) {
  EXPECT_EQ((CalibrationMethodOptions{"auto", 1, {k_point}, {}, -1, {}}.choose()), CalibrationMethod::optimize);
  EXPECT_EQ((CalibrationMethodOptions{"auto", 1, {}, {}, -1, {}}.choose()), CalibrationMethod::optimize);
  EXPECT_EQ((CalibrationMethodOptions{"auto", 1, {k_uncertain}, {}, -1, {}}.choose()), CalibrationMethod::bayes);
  EXPECT_EQ((CalibrationMethodOptions{"auto", 1, {}, {k_uncertain}, -1, {}}.choose()), CalibrationMethod::bayes);
  EXPECT_EQ((CalibrationMethodOptions{"auto", 2, {k_point}, {}, -1, {}}.choose()), CalibrationMethod::bayes);
  EXPECT_EQ((CalibrationMethodOptions{"bayes", 1, {k_point}, {}, 3, {}}.choose()), CalibrationMethod::bayes);
  EXPECT_EQ((CalibrationMethodOptions{"optimize", 1, {k_point}, {}, 0, {}}.choose()), CalibrationMethod::optimize);
}

TEST(CalibrationMethod, RefusedCombinationsNameTheField) {
  EXPECT_EQ(message_of<UserError>([] { CalibrationMethodOptions{"optimize", 2, {k_point}, {}, -1, {}}.choose(); }),
            "CalibrationMethodOptions.method optimize: one study folder, not 2 (several studies: "
            "CalibrationMethodOptions.method bayes)");
  EXPECT_EQ(message_of<UserError>([] { CalibrationMethodOptions{"optimize", 1, {k_point}, {}, 2, {}}.choose(); }),
            "CalibrationMethodOptions.verify 2: CalibrationMethodOptions.method optimize verifies its one optimum "
            "(give CalibrationMethodOptions.verify alone)");
  EXPECT_EQ(message_of<UserError>([] { CalibrationMethodOptions{"optimize", 1, {k_uncertain}, {}, -1, {}}.choose(); }),
            "CalibrationMethodOptions.targets 'angle=33.5±1.5': CalibrationMethodOptions.method optimize matches a "
            "value; an uncertainty is for CalibrationMethodOptions.method bayes");
  EXPECT_EQ(message_of<UserError>([] { CalibrationMethodOptions{"bayes", 1, {}, {}, -1, {}}.choose(); }),
            "calibrate CalibrationMethodOptions.method bayes: give the measured values with "
            "CalibrationMethodOptions.targets NAME=V±E or CalibrationMethodOptions.target_files");
  EXPECT_EQ(message_of<UserError>([] { CalibrationMethodOptions{"mcmc", 1, {k_point}, {}, -1, {}}.choose(); }),
            "CalibrationMethodOptions.method 'mcmc': expected auto, bayes or optimize");
}

TEST(CalibrationMethod, TargetsAndWeightsReadFromTextNameTheField) {
  const CalibrationMethodOptions read = read_calibration_targets({"angle=33.5±1.5", "mass=2"}, {}, {"angle=2"});
  ASSERT_EQ(read.targets.size(), 2u);
  EXPECT_DOUBLE_EQ(read.targets[0].sd, 1.5);
  EXPECT_DOUBLE_EQ(read.weights.at("angle"), 2.0);
  EXPECT_TRUE(read.target_files.empty());
  EXPECT_EQ(message_of<UserError>([] { read_calibration_targets({"angle"}, {}, {}); }),
            "CalibrationMethodOptions.targets 'angle': expected NAME=VALUE±ERROR");
  EXPECT_EQ(message_of<UserError>([] { read_calibration_targets({}, {}, {"angle=-1"}); }),
            "CalibrationMethodOptions.weights 'angle=-1': one value >= 0 expected");
  EXPECT_EQ(message_of<UserError>([] { read_calibration_targets({}, {"curve"}, {}); }),
            "CalibrationMethodOptions.target_files 'curve': expected NAME=FILE.csv");
}

TEST(CalibrationMethod, FailedChecks) {
  CalibrationOutcome optimum;
  EXPECT_FALSE(calibration_failed(optimum, false));
  EXPECT_TRUE(calibration_failed(optimum, true));  // asked to verify, not verified
  optimum.verified = true;
  EXPECT_FALSE(calibration_failed(optimum, true));
  optimum.problems.push_back("angle: the study cannot produce 80");
  EXPECT_TRUE(calibration_failed(optimum, true));

  PosteriorOutcome posterior;
  EXPECT_FALSE(posterior_failed(posterior));
  posterior.verification.push_back(VerifyPoint{});
  EXPECT_FALSE(posterior_failed(posterior));
  posterior.verification.back().errors.push_back("the run failed");
  EXPECT_TRUE(posterior_failed(posterior));
  posterior.verification.clear();
  posterior.problems.push_back("the chain has not converged");
  EXPECT_TRUE(posterior_failed(posterior));
}

}  // namespace
}  // namespace demsa::test
