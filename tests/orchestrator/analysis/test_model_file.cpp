// Metamodels as files (model_file.hpp): a model written and read back predicts bit for bit and gives the same Sobol'
// indices (with a design bootstrap, which refits the read model); a broken file is a UserError naming the file and
// the field.
#include "orchestrator/analysis/model_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "sobol/gp.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/random.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <functional>
#include <string>

using namespace demsa::analysis;
using demsa::util::UserError;
using nlohmann::json;

namespace demsa::test {
namespace {

constexpr double k_pi = 3.14159265358979323846;

/// Ishigami (Ishigami & Homma 1990) on [-π, π]³, here from the unit cube.
double ishigami(double u1, double u2, double u3) {
  const double x1 = -k_pi + 2 * k_pi * u1, x2 = -k_pi + 2 * k_pi * u2, x3 = -k_pi + 2 * k_pi * u3;
  return std::sin(x1) + 7 * std::sin(x2) * std::sin(x2) + 0.1 * std::pow(x3, 4) * std::sin(x1);
}

SavedModel fitted(const std::string& kind, int n = 60) {
  sobol::Random rng(7);
  Eigen::MatrixXd x(n, 3);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) x(i, k) = (i + rng.uniform()) / n;  // one point per stratum of each input...
  }
  for (int k = 1; k < 3; ++k)  // ...with the strata of the other inputs shuffled: a Latin hypercube
    for (int i = n - 1; i > 0; --i) std::swap(x(i, k), x(static_cast<int>(rng.uniform() * (i + 1)), k));
  for (int i = 0; i < n; ++i) y(i) = ishigami(x(i, 0), x(i, 1), x(i, 2));
  sobol::MetamodelOptions options;
  options.gp.starts = 2;
  SavedModel saved;
  saved.model = sobol::make_metamodel(kind, options);
  saved.model->fit(x, y);
  saved.inputs = {"E", "mu_pp", "e_r"};
  saved.bounds = {{1e7, 1e9, sobol::Scale::log_uniform}, {0.1, 1.0, sobol::Scale::uniform}, {0.2, 0.6}};
  saved.output = "angle";
  return saved;
}

void expect_same_indices(const sobol::SobolResult& a, const sobol::SobolResult& b) {
  ASSERT_EQ(a.first.size(), b.first.size());
  for (std::size_t k = 0; k < a.first.size(); ++k) {
    EXPECT_EQ(a.first[k].value, b.first[k].value);
    EXPECT_EQ(a.first[k].lower, b.first[k].lower);
    EXPECT_EQ(a.first[k].upper, b.first[k].upper);
    EXPECT_EQ(a.total[k].value, b.total[k].value);
    EXPECT_EQ(a.total[k].upper, b.total[k].upper);
  }
  EXPECT_EQ(a.variance, b.variance);
}

class ModelFileRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(ModelFileRoundTrip, PredictsBitForBitAndGivesTheSameSobolIndices) {
  const SavedModel saved = fitted(GetParam());
  const std::string text = model_to_json(saved);
  const SavedModel read = parse_model_json(text, "m.json");
  EXPECT_EQ(read.model->name(), GetParam());
  EXPECT_EQ(read.inputs, saved.inputs);
  EXPECT_EQ(read.output, "angle");
  EXPECT_EQ(read.bounds[0].scale, sobol::Scale::log_uniform);
  EXPECT_EQ(read.bounds[0].low, 1e7);
  EXPECT_FALSE(read.demsa_version.empty());

  sobol::Random rng(11);
  Eigen::MatrixXd points(500, 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (int k = 0; k < 3; ++k) points(i, k) = rng.uniform();
  const Eigen::VectorXd a = saved.model->predict(points);
  const Eigen::VectorXd b = read.model->predict(points);
  for (Eigen::Index i = 0; i < a.size(); ++i) ASSERT_EQ(a(i), b(i)) << "point " << i;
  EXPECT_EQ(saved.model->summary().q2, read.model->summary().q2);

  sobol::MetamodelSobolOptions options;
  options.base = 512;
  options.bootstrap = 8;  // refits of the read model: its training data and hyperparameters must be the same
  expect_same_indices(sobol::metamodel_sobol(*saved.model, options), sobol::metamodel_sobol(*read.model, options));
  options.exact_for_rsm = false;
  expect_same_indices(sobol::metamodel_sobol(*saved.model, options), sobol::metamodel_sobol(*read.model, options));

  // Written again, the file is the same document, but for the GP's count of likelihood evaluations: a model read
  // back was not searched for (its summary says 0).
  json again = json::parse(model_to_json(read));
  json first = json::parse(text);
  for (json* j : {&again, &first}) (*j)["quality"]["parameters"].erase("likelihood_evaluations");
  EXPECT_EQ(again, first);
}

INSTANTIATE_TEST_SUITE_P(EveryKind, ModelFileRoundTrip,
                         ::testing::Values("rsm1", "rsm2", "rsm3", "rbf-cubic", "rbf-tps", "gp"),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

TEST(ModelFile, GpStandardDeviationSurvivesTheRoundTrip) {
  const SavedModel saved = fitted("gp");
  const SavedModel read = parse_model_json(model_to_json(saved), "m.json");
  const Eigen::MatrixXd points = Eigen::MatrixXd::Constant(3, 3, 0.37);
  const auto& a = dynamic_cast<const sobol::GaussianProcess&>(*saved.model);
  const auto& b = dynamic_cast<const sobol::GaussianProcess&>(*read.model);
  EXPECT_EQ(a.predict_sd(points), b.predict_sd(points));
}

/// parse_model_json of the gp file after `edit`: the UserError's message.
std::string error_of(const std::function<void(json&)>& edit, const std::string& kind = "rbf-cubic") {
  json j = json::parse(model_to_json(fitted(kind, 30)));
  edit(j);
  try {
    parse_model_json(j.dump(), "model.json");
  } catch (const UserError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ModelFile, BadFilesNameTheFileAndTheField) {
  EXPECT_EQ(error_of([](json& j) { j["kind"] = "rsm9"; }).rfind("model.json: field 'kind': unknown metamodel", 0), 0u)
      << error_of([](json& j) { j["kind"] = "rsm9"; });
  EXPECT_EQ(error_of([](json& j) { j.erase("output"); }), "model.json: field 'output': missing");
  EXPECT_EQ(error_of([](json& j) { j["rbf"]["weights"].erase(0); }),
            "model.json: field 'rbf.weights': 29 entries, expected 30");
  EXPECT_EQ(error_of([](json& j) { j["rbf"]["tail_coefficients"][2] = nullptr; }),
            "model.json: field 'rbf.tail_coefficients[2]': null (not a finite number)");
  EXPECT_EQ(error_of([](json& j) { j["training"]["unit_inputs"][3][1] = "x"; }),
            "model.json: field 'training.unit_inputs[3][1]': \"x\" is not a number");
  EXPECT_EQ(error_of([](json& j) { j["format"] = "other"; }),
            "model.json: field 'format': 'other' is not 'demsa-metamodel'");
  EXPECT_EQ(error_of([](json& j) { j["format_version"] = 7; }),
            "model.json: field 'format_version': 7: this demsa reads version 1");
  EXPECT_EQ(error_of([](json& j) { j["kind"] = "rbf-tps"; }),
            "model.json: field 'rbf.kernel': 'cubic' for kind 'rbf-tps' (expected 'thin-plate')");
  EXPECT_EQ(error_of([](json& j) { j["inputs"][1]["high"] = -5; }).rfind("model.json: field 'inputs[1]': ", 0), 0u);
  EXPECT_EQ(error_of([](json& j) { j["rsm"]["coefficients"].push_back(1.0); }, "rsm2"),
            "model.json: field 'rsm.coefficients': 11 entries, expected 10");
  EXPECT_EQ(error_of(
                [](json& j) {
                  j["rsm"]["terms"][1] = {0, 0, 2};
                },
                "rsm2"),
            "model.json: field 'rsm.terms[1]': [0,0,2] is not the multi-index [1,0,0] of this basis");
  EXPECT_EQ(error_of([](json& j) { j["gp"]["lengths"][0] = -1.0; }, "gp"),
            "model.json: model 'gp': gp: length scale 1 is -1: must be a positive number");
  EXPECT_EQ(error_of([](json& j) { j["gp"]["weights"].push_back(0.0); }, "gp"),
            "model.json: field 'gp.weights': 31 entries, expected 30");
  EXPECT_EQ(
      error_of([](json& j) { j["training"]["unit_inputs"][4][0] = 1.5; }).rfind("model.json: field 'training': ", 0),
      0u);
  try {
    parse_model_json("{\"format\": ", "broken.json");
    FAIL() << "no error";
  } catch (const UserError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("broken.json: not a JSON document: ", 0), 0u) << e.what();
  }
  // A number beyond a double was the JSON library's own error, exit 3, without the file's name.
  try {
    parse_model_json("{\"format\": 1e999}", "huge.json");
    FAIL() << "no error";
  } catch (const UserError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("huge.json: a number out of range: ", 0), 0u) << e.what();
  }
}

TEST(ModelFile, NamesAreUniqueAndFromASafeCharacterSet) {
  EXPECT_EQ(error_of([](json& j) { j["inputs"][2]["name"] = "E"; }),
            "model.json: field 'inputs[2].name': 'E' is also inputs[0]: names must be unique");
  EXPECT_EQ(error_of([](json& j) {
              j["output"] = "mu_pp";
            }).rfind("model.json: field 'output': 'mu_pp' is also the name of inputs[1]", 0),
            0u);
  EXPECT_EQ(error_of([](json& j) { j["output"] = "e_r_sd"; }).rfind("model.json: field 'output'", 0),
            std::string::npos);
  for (const std::string bad : {"=cmd|' /C calc'!A0", "a,b", "two\nlines", "+1", "-x", "@sum", "", "x y"}) {
    const std::string e = error_of([&](json& j) { j["inputs"][0]["name"] = bad; });
    EXPECT_EQ(e.rfind("model.json: field 'inputs[0].name': ", 0), 0u) << bad << ": " << e;
    const std::string o = error_of([&](json& j) { j["output"] = bad; });
    EXPECT_EQ(o.rfind("model.json: field 'output': ", 0), 0u) << bad << ": " << o;
  }
  EXPECT_NE(error_of([](json& j) { j["output"] = "two\nlines"; }).find("'two\\x0alines' is not a name"),
            std::string::npos);
  EXPECT_EQ(bad_name_reason("settlement_1"), "");
  EXPECT_EQ(bad_name_reason("x.1-b"), "");
}

TEST(ModelFile, TooManyTrainingRowsAreRefusedBeforeAnyFit) {
  json j = json::parse(model_to_json(fitted("rsm1", 30)));
  json& outputs = j["training"]["outputs"];
  while (outputs.size() <= static_cast<std::size_t>(k_max_model_rows)) outputs.push_back(0.5);
  try {
    parse_model_json(j.dump(), "big.json");
    FAIL() << "no error";
  } catch (const UserError& e) {
    EXPECT_EQ(std::string(e.what()),
              fmt::format("big.json: field 'training.outputs': {} entries, more than the {} read", k_max_model_rows + 1,
                          k_max_model_rows));
  }
}

}  // namespace
}  // namespace demsa::test
