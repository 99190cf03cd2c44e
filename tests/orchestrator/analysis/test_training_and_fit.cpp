// The analysis building blocks shared by `demsa analyze`, `demsa calibrate` and the report: the training data of an
// observable (training_data.hpp), the candidate fits and their ranking by Q² (fit.hpp), and analysis.json read
// back as typed data (analysis_json.hpp).
#include "orchestrator/analysis/analysis_json.hpp"
#include "orchestrator/analysis/fit.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/analysis/training_data.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/errors.hpp"
#include "sobol/error.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::analysis;

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();

// Three parameters, listed e_r, mu_pp, mu_r_pp in the study file: the study keeps them in the paper's order
// (mu_pp, e_r, mu_r_pp), and so do the training data.
const StudyToml k_study{.name = "training",
                        .seed = 3,
                        .samples = 16,
                        .parameters =
                            "e_r = { low = 0.2, high = 0.6 }\nmu_pp = { low = 0.7, high = 1.9 }\n"
                            "mu_r_pp = { low = 0.05, high = 0.5 }\n",
                        .analysis = "metamodels = [\"rsm3\", \"rsm1\", \"rsm2\"]\nbootstrap = 0\nbase_samples = 256\n"};

double angle_of(const std::vector<double>& u) { return 25.0 + 10.0 * u[2] + 3.0 * u[0] * u[0] + u[1]; }

/// Samples 0 and 1 never run; sample 2 measured only the angle; the others angle and pile height.
SyntheticStudy write_study(const fs::path& dir) {
  SyntheticStudy study = start_synthetic_study(dir, k_study.text(), 5);
  for (const SampleRow& row : study.samples) {
    if (row.sample < 2) continue;
    RunOutcome done;
    done.exit_code = 0;
    std::map<std::string, double> values{{"angle", angle_of(row.unit)}};
    if (row.sample != 2) values["pile_height"] = 0.02 + 0.01 * row.unit[1];
    study.store.record_done(study.store.add_run(row.sample, 1), done, values);
  }
  return study;
}

TEST(TrainingData, RowsOfTheSamplesThatMeasuredTheObservableInParameterOrder) {
  TempDir dir;
  const SyntheticStudy study = write_study(dir.path());
  const TrainingData angle = training_data(study.config, study.store, "angle");
  ASSERT_EQ(angle.size(), 14u);
  EXPECT_EQ(angle.samples.front(), 2);
  EXPECT_EQ(angle.samples.back(), 15);
  ASSERT_EQ(angle.unit.cols(), 3);
  ASSERT_EQ(angle.physical.cols(), 3);
  for (Eigen::Index i = 0; i < angle.unit.rows(); ++i) {
    const SampleRow& row = study.samples.at(static_cast<std::size_t>(angle.samples[static_cast<std::size_t>(i)]));
    for (Eigen::Index j = 0; j < 3; ++j) {
      EXPECT_EQ(angle.unit(i, j), row.unit[static_cast<std::size_t>(j)]);
      EXPECT_EQ(angle.physical(i, j), row.physical[static_cast<std::size_t>(j)]);
    }
    EXPECT_EQ(angle.y(i), angle_of(row.unit));
  }
  // e_r is the second column: its physical values lie in its range.
  EXPECT_GE(angle.physical.col(1).minCoeff(), 0.2);
  EXPECT_LE(angle.physical.col(1).maxCoeff(), 0.6);

  const TrainingData height = training_data(study.config, study.store, "pile_height");
  EXPECT_EQ(height.size(), 13u);
  EXPECT_EQ(height.samples.front(), 3);
  EXPECT_EQ(training_data(study.config, study.store, "settlement_1").size(), 0u);
}

TEST(Fit, EachKindFittedOrItsReasonAndTheBestByQ2) {
  TempDir dir;
  const SyntheticStudy study = write_study(dir.path());
  const TrainingData angle = training_data(study.config, study.store, "angle");
  const std::vector<FittedMetamodel> fits =
      fit_metamodels(metamodel_kinds(study.config.analysis.metamodels), study.config.analysis.metamodel_options(),
                     angle.unit, angle.y);
  ASSERT_EQ(fits.size(), 3u);
  // 14 samples are too few for the 20 terms of a cubic RSM in three inputs.
  EXPECT_EQ(fits[0].name(), "rsm3");
  EXPECT_FALSE(fits[0].ok());
  EXPECT_FALSE(fits[0].error.empty());
  EXPECT_TRUE(fits[0].exception);
  EXPECT_TRUE(fits[1].ok()) << fits[1].error;
  EXPECT_TRUE(fits[2].ok()) << fits[2].error;
  EXPECT_EQ(fits[2].quality.samples, 14);
  EXPECT_NEAR(fits[2].quality.r2, 1.0, 1e-9);  // the angle is quadratic
  EXPECT_LT(fits[1].quality.q2, fits[2].quality.q2);
  EXPECT_EQ(best_by_q2(fits), std::optional<std::size_t>(2));
}

TEST(Fit, BestByQ2RanksNonFiniteLastAndKeepsTheFirstOfEquals) {
  std::vector<FittedMetamodel> fits(4);
  EXPECT_EQ(best_by_q2(fits), std::nullopt);  // none fitted
  const auto fitted = [](double q2) {
    FittedMetamodel f;
    f.model = sobol::make_metamodel(sobol::MetamodelKind::rsm1);
    f.quality.q2 = q2;
    return f;
  };
  fits[0] = fitted(k_nan);
  EXPECT_EQ(best_by_q2(fits), std::optional<std::size_t>(0));
  fits[1] = fitted(-5.0);
  fits[2] = fitted(0.5);
  fits[3] = fitted(0.5);
  EXPECT_EQ(best_by_q2(fits), std::optional<std::size_t>(2));
  EXPECT_THROW(metamodel_kinds({"rsm2", "kriging"}), sobol::InputError);
}

TEST(AnalysisJson, TheWrittenFileReadsBackToTheSameDocument) {
  TempDir dir;
  write_study(dir.path());
  AnalyzeOptions options;
  options.dir = dir.path();
  options.second_order = 1;
  const AnalysisSummary written = analyze_study(options);
  const fs::path file = dir / "analysis" / "analysis.json";
  const AnalysisSummary read = read_analysis(file);
  EXPECT_EQ(read_file(file), analysis_to_json(read));
  EXPECT_EQ(read.out_dir, file.parent_path());
  EXPECT_EQ(read.study, "training");
  EXPECT_EQ(read.parameters, (std::vector<std::string>{"mu_pp", "e_r", "mu_r_pp"}));
  EXPECT_EQ(read.samples_left_out, (std::vector<int>{0, 1}));
  ASSERT_EQ(read.observables.size(), written.observables.size());
  const ObservableAnalysis& angle = read.observables.at(0);
  EXPECT_EQ(angle.name, "angle");
  EXPECT_EQ(angle.samples, 14);
  ASSERT_EQ(angle.models.size(), 3u);
  EXPECT_FALSE(angle.models[0].ok);
  EXPECT_EQ(angle.models[0].error, written.observables[0].models[0].error);
  const ModelAnalysis& rsm2 = angle.models[2];
  ASSERT_TRUE(rsm2.ok);
  EXPECT_EQ(rsm2.model, "rsm2");
  EXPECT_EQ(rsm2.quality.terms, 10);
  ASSERT_EQ(rsm2.indices.first.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_EQ(rsm2.indices.first[k].value, written.observables[0].models[2].indices.first[k].value);
  ASSERT_EQ(rsm2.indices.second.size(), 3u);  // (0,1), (0,2), (1,2)
  EXPECT_EQ(rsm2.indices.second[2].i, 1);
  EXPECT_EQ(rsm2.indices.second[2].j, 2);
  // The angle is additive: its S1 sum to one.
  EXPECT_NEAR(rsm2.indices.residual.value, 0.0, 1e-9);
}

TEST(AnalysisJson, ErrorsNameTheFile) {
  TempDir dir;
  const fs::path missing = dir / "analysis.json";
  try {
    read_analysis(missing);
    FAIL() << "read a missing file";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  write_file(missing, "{\"study\": \"x\", \"parameters\": [\"mu_pp\"]}");
  try {
    read_analysis(missing);
    FAIL() << "read an incomplete file";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string() + ": not an analysis file"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace demsa::test
