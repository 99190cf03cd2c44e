// Sobol' indices of any simulator through the library calls (analysis/sensitivity.hpp): a Saltelli design written by
// the design file's writer and read back gives the Ishigami indices (Ishigami & Homma 1990) within their intervals,
// and without intervals writes null bounds; metamodels on data give the exact indices of a linear function; a
// mistake in the options names the field.
#include "orchestrator/analysis/saltelli_design_file.hpp"
#include "orchestrator/analysis/sensitivity.hpp"
#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"
#include "sobol/saltelli.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace demsa::analysis;
using demsa::util::UserError;

namespace demsa::test {
namespace {

constexpr double k_pi = 3.14159265358979323846;

/// Ishigami (a = 7, b = 0.1) on [-π, π]³; its S1 are 0.3139, 0.4424 and 0.
Eigen::VectorXd ishigami(const Eigen::MatrixXd& x) {
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const double s2 = std::sin(x(i, 1));
    y(i) = std::sin(x(i, 0)) + 7.0 * s2 * s2 + 0.1 * std::pow(x(i, 2), 4) * std::sin(x(i, 0));
  }
  return y;
}

/// A Saltelli design of the Ishigami inputs (N = 4096) as `demsa design saltelli` writes it, and its responses.
SaltelliSensitivityOptions ishigami_files(const TempDir& dir, int replicates) {
  sobol::SaltelliOptions design_options;
  design_options.base = 4096;
  design_options.dimension = 3;
  design_options.seed = 7;
  design_options.replicates = replicates;
  const sobol::SaltelliDesign design = sobol::saltelli_design(design_options);
  const Eigen::MatrixXd x = (2.0 * k_pi * design.stacked()).array() - k_pi;
  write_saltelli_design((dir / "design.csv").string(), design, x, {"x1", "x2", "x3"});
  util::write_csv(dir / "y.csv", {"y"}, ishigami(x));
  SaltelliSensitivityOptions options;
  options.design = (dir / "design.csv").string();
  options.responses_file = (dir / "y.csv").string();
  return options;
}

TEST(Sensitivity, SaltelliDesignWrittenAndReadBackGivesTheIshigamiIndices) {
  TempDir dir;
  const SaltelliSensitivityOptions options = ishigami_files(dir, 8);
  const SaltelliDesignFile file = saltelli_design_of(read_saltelli_csv(options.design), {});
  EXPECT_EQ(file.parameters, (std::vector<std::string>{"x1", "x2", "x3"}));
  EXPECT_EQ(file.replicates(), 8);
  EXPECT_EQ(file.base(), 512);
  const SaltelliSensitivity result = saltelli_sensitivity(options);
  ASSERT_EQ(result.outputs.size(), 1u);
  const sobol::SobolResult& r = result.outputs[0].indices;
  EXPECT_EQ(r.replicates, 8);
  const std::vector<double> s1{0.3139, 0.4424, 0.0};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(r.first[k].value, s1[k], 0.03) << k;
    EXPECT_LT(r.first[k].lower, r.first[k].upper) << k;
  }
  const nlohmann::json j = saltelli_sensitivity_json(result);
  EXPECT_TRUE(j["outputs"][0]["S1"]["x1"]["lower"].is_number()) << j.dump();
}

TEST(Sensitivity, OneScrambledDesignWritesNullBounds) {
  TempDir dir;
  const SaltelliSensitivity result = saltelli_sensitivity(ishigami_files(dir, 1));
  const nlohmann::json j = saltelli_sensitivity_json(result)["outputs"][0];
  EXPECT_NEAR(j["S1"]["x2"]["value"].get<double>(), 0.4424, 0.03);
  EXPECT_TRUE(j["S1"]["x2"]["lower"].is_null()) << j.dump();
  EXPECT_TRUE(j["ST"]["x3"]["upper"].is_null()) << j.dump();
  EXPECT_TRUE(j["residual"]["lower"].is_null()) << j.dump();
}

/// `data` (columns a, b, y) written to DIR/data.csv, and the options of y's rsm2 on a and b, without intervals.
DataSensitivityOptions rsm2_of_y(const TempDir& dir, const Eigen::MatrixXd& data) {
  util::write_csv(dir / "data.csv", {"a", "b", "y"}, data);
  DataSensitivityOptions options;
  options.data = (dir / "data.csv").string();
  options.inputs = {"a", "b"};
  options.responses = {"y"};
  options.metamodels = {sobol::MetamodelKind::rsm2};
  options.indices.bootstrap = 0;
  return options;
}

TEST(Sensitivity, MetamodelOfALinearFunctionGivesItsExactIndices) {
  TempDir dir;
  // y = 2 a + b on [0, 1]²: variances 4/12 and 1/12, S1 = 0.8 and 0.2, no interaction.
  Eigen::MatrixXd data(16, 3);
  for (int i = 0; i < 16; ++i) {
    const double a = (i % 4) / 3.0, b = (i / 4) / 3.0;
    data.row(i) << a, b, 2 * a + b;
  }
  DataSensitivityOptions options = rsm2_of_y(dir, data);
  const DataSensitivity result = data_sensitivity(options);
  ASSERT_EQ(result.outputs.size(), 1u);
  const sobol::SobolResult& r = result.outputs[0].models[0].indices;
  EXPECT_NEAR(r.first[0].value, 0.8, 1e-9);
  EXPECT_NEAR(r.first[1].value, 0.2, 1e-9);
  EXPECT_NEAR(r.total[0].value, 0.8, 1e-9);
  EXPECT_DOUBLE_EQ(result.coverage[0], 1.0);
  EXPECT_EQ(data_sensitivity_json(result)["bounds"][1]["high"].get<double>(), 1.0);

  options.bounds["c"] = sobol::Bounds{0.0, 1.0};
  try {
    data_sensitivity(options);
    FAIL() << "a bound of no input was accepted";
  } catch (const UserError& e) {
    EXPECT_STREQ(e.what(), "DataSensitivityOptions.bounds: 'c' is not one of the inputs");
  }
}

TEST(Sensitivity, AMetamodelWhoseQ2IsNotComputableGivesNoIndicesButAnErrorNamingTheFile) {
  TempDir dir;
  // rsm2 of two inputs has 6 terms: on 6 samples it passes through each, and no sample can be left out.
  Eigen::MatrixXd data(6, 3);
  const double a[] = {0.0, 1.0, 0.0, 1.0, 0.5, 0.2}, b[] = {0.0, 0.0, 1.0, 1.0, 0.5, 0.9};
  for (int i = 0; i < 6; ++i) data.row(i) << a[i], b[i], 2 * a[i] + b[i] + 0.1 * a[i] * b[i];
  DataSensitivityOptions options = rsm2_of_y(dir, data);
  try {
    data_sensitivity(options);
    FAIL() << "indices of a fit whose leave-one-out error cannot be measured";
  } catch (const UserError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("data.csv"), std::string::npos) << what;
    EXPECT_NE(what.find("output 'y', metamodel rsm2"), std::string::npos) << what;
    EXPECT_NE(what.find("Q²"), std::string::npos) << what;
  }
  options.metamodels = {sobol::MetamodelKind::rsm1};  // 3 terms on 6 samples: measured
  EXPECT_EQ(data_sensitivity(options).outputs.size(), 1u);
}

}  // namespace
}  // namespace demsa::test
