// `demsa predict` through the real binary (a study folder's saved metamodels and single model files), the deprecated
// `--output` spellings, and response columns appended to a Saltelli design.
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/csv.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <sstream>

using namespace demsa::util;
using namespace demsa::study;

namespace demsa::test {
namespace {

namespace fs = std::filesystem;

/// DIR/study.toml and DIR/study.db with 30 done samples of two observables (mu_pp in [0.7, 1.9], mu_r_pp in
/// [0.05, 0.5]), analysed with rsm2, rbf-cubic and gp.
void write_analysed_study(const fs::path& dir) {
  const StudyToml toml{
      .name = "synthetic",
      .seed = 7,
      .samples = 30,
      .analysis = "metamodels = [\"rsm2\", \"rbf-cubic\", \"gp\"]\nbootstrap = 0\nbase_samples = 64\n"};
  SyntheticStudy study = start_synthetic_study(dir, toml.text(), 3);
  for (const SampleRow& row : study.samples) {
    const long run = study.store.add_run(row.sample, 1);
    RunOutcome outcome;
    outcome.exit_code = 0;
    const double u1 = row.unit[0], u2 = row.unit[1];
    study.store.record_done(run, outcome,
                            {{"angle", 22.0 + 14.0 * u2 + 5.0 * u1 * u1 + std::sin(6.0 * u1 * u2)},
                             {"pile_height", 0.02 + 0.01 * u1 + 0.004 * u2}});
  }
  const CommandResult r = run_demsa({"analyze", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
}

TEST(CliPredict, StudyFolderModelsReproduceTheTrainingDataAndTheBestIsChosenByQ2) {
  TempDir tmp;
  const fs::path study = tmp / "study";
  write_analysed_study(study);
  for (const std::string o : {"angle", "pile_height"})
    for (const std::string m : {"rsm2", "rbf-cubic", "gp"})
      EXPECT_TRUE(fs::exists(study / "analysis" / "models" / (o + "." + m + ".json"))) << o << " " << m;

  // The training points in physical units, columns in another order and one more column: found by name.
  const CsvTable observed = read_csv(study / "analysis" / "observables.csv");
  std::string points = "mu_r_pp,sample,mu_pp\n";
  for (int i = 0; i < observed.rows(); ++i)
    points += fmt::format("{:.17g},{},{:.17g}\n", observed.values(i, observed.column_index("mu_r_pp")), i,
                          observed.values(i, observed.column_index("mu_pp")));
  write_file(tmp / "points.csv", points);

  CommandResult r = run_demsa({"predict", study.string(), "--points", (tmp / "points.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("the study has 2 observables with metamodels (angle, pile_height): choose one with "
                       "--observable"),
            std::string::npos)
      << r.err;

  // An interpolant reproduces its training data (observables.csv holds 10 significant digits of inputs and angle).
  r = run_demsa({"predict", study.string(), "--observable", "angle", "--model", "rbf-cubic", "--points",
                 (tmp / "points.csv").string(), "-o", (tmp / "rbf.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvTable rbf = read_csv(tmp / "rbf.csv");
  ASSERT_EQ(rbf.columns, (std::vector<std::string>{"mu_pp", "mu_r_pp", "angle"}));
  ASSERT_EQ(rbf.rows(), observed.rows());
  for (int i = 0; i < rbf.rows(); ++i)
    EXPECT_NEAR(rbf.values(i, 2), observed.values(i, observed.column_index("angle")), 1e-7) << i;

  // Without --model: the largest Q² of analysis.json.
  const nlohmann::json analysis = nlohmann::json::parse(read_file(study / "analysis" / "analysis.json"));
  std::string best;
  double best_q2 = -1e300;
  for (const nlohmann::json& o : analysis["observables"])
    if (o["name"] == "angle")
      for (const nlohmann::json& m : o["models"])
        if (m["ok"].get<bool>() && m["quality"]["q2"].get<double>() > best_q2) {
          best_q2 = m["quality"]["q2"].get<double>();
          best = m["model"].get<std::string>();
        }
  ASSERT_FALSE(best.empty()) << analysis.dump(1);
  r = run_demsa({"predict", study.string(), "--observable", "angle", "--points", (tmp / "points.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("observable 'angle': metamodel " + best + " (largest leave-one-out Q2"), std::string::npos)
      << r.err;
  const CommandResult file =
      run_demsa({"predict", (study / "analysis" / "models" / ("angle." + best + ".json")).string(), "--points",
                 (tmp / "points.csv").string()});
  ASSERT_EQ(file.exit_code, 0) << file.err;
  EXPECT_EQ(r.out, file.out);

  // --std: the GP's standard deviation, near zero at its own training points; refused for the others.
  r = run_demsa({"predict", study.string(), "--observable", "angle", "--model", "gp", "--std", "--points",
                 (tmp / "points.csv").string(), "-o", (tmp / "gp.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvTable gp = read_csv(tmp / "gp.csv");
  ASSERT_EQ(gp.columns.back(), "angle_sd");
  EXPECT_LT(gp.values.col(3).maxCoeff(), 1e-3);
  r = run_demsa({"predict", study.string(), "--observable", "angle", "--model", "rsm2", "--std", "--points",
                 (tmp / "points.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--std: the rsm2 metamodel of " + (study / "analysis" / "models" / "angle.rsm2.json").string() +
                       " has no predictive standard deviation (only gp has one)"),
            std::string::npos)
      << r.err;
  r = run_demsa({"predict", study.string(), "--observable", "angle", "--model", "rsm3", "--points",
                 (tmp / "points.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--model rsm3: no such metamodel of 'angle'"), std::string::npos) << r.err;
}

TEST(CliPredict, PointsFileErrorsAndPointsOutsideTheBounds) {
  TempDir tmp;
  const fs::path study = tmp / "study";
  write_analysed_study(study);
  const std::string model = (study / "analysis" / "models" / "angle.rsm2.json").string();
  write_file(tmp / "missing.csv", "mu_pp,other\n1.0,2\n");
  CommandResult r = run_demsa({"predict", model, "--points", (tmp / "missing.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find((tmp / "missing.csv").string() + ":1: no column 'mu_r_pp' (columns: mu_pp, other)"),
            std::string::npos)
      << r.err;
  // Two of three points outside [0.7, 1.9] x [0.05, 0.5]: predicted, with a warning that counts them.
  write_file(tmp / "outside.csv", "mu_pp,mu_r_pp\n1.0,0.1\n2.5,0.1\n1.0,0.0\n");
  r = run_demsa({"predict", model, "--points", (tmp / "outside.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("2 of 3 points lie outside the bounds of the model's inputs"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 4) << r.out;
  write_file(tmp / "bad.csv", "mu_pp,mu_r_pp\n1.0,abc\n");
  r = run_demsa({"predict", model, "--points", (tmp / "bad.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.csv:2: column 'mu_r_pp': 'abc' is not a number"), std::string::npos) << r.err;
  // A broken model file names the file and the field.
  std::string text = read_file(model);
  text.replace(text.find("\"kind\": \"rsm2\""), 14, "\"kind\": \"rsm7\"");
  write_file(tmp / "broken.json", text);
  r = run_demsa({"predict", (tmp / "broken.json").string(), "--points", (tmp / "outside.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find((tmp / "broken.json").string() + ": field 'kind': unknown metamodel 'rsm7'"), std::string::npos)
      << r.err;
  r = run_demsa({"predict", (tmp / "none.json").string(), "--points", (tmp / "outside.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("none.json: no such study folder or model file"), std::string::npos) << r.err;
}

TEST(CliOptionNames, OldOutputSpellingWarnsAndStillWorks) {
  TempDir tmp;
  CommandResult r = run_demsa({"design", "lhs", "-n", "8", "--dim", "2", "--output", (tmp / "d.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("--output is deprecated and will be removed in the next version: use -o/--out"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::exists(tmp / "d.csv"));
  r = run_demsa({"design", "lhs", "-n", "8", "--dim", "2", "--out", (tmp / "e.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("deprecated"), std::string::npos) << r.err;
  r = run_demsa({"design", "sobol", "-n", "8", "--dim", "2"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("-o/--out FILE is required"), std::string::npos) << r.err;

  const StudyToml toml;
  write_file(tmp / "study.toml", toml.text());
  r = run_demsa({"case", (tmp / "study.toml").string(), "--sample", "0", "--output", (tmp / "case0").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("--output is deprecated and will be removed in the next version: use -o/--out"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::exists(tmp / "case0" / "case.json"));

  std::string data = "a,b,y\n";
  for (int i = 0; i < 20; ++i) data += fmt::format("{},{},{}\n", i * 0.05, (i * 7 % 20) * 0.05, i * 0.1 + (i % 3));
  write_file(tmp / "data.csv", data);
  r = run_demsa({"sensitivity", "--data", (tmp / "data.csv").string(), "--inputs", "a,b", "--output", "y",
                 "--metamodels", "rsm2", "--bootstrap", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("--output is deprecated and will be removed in the next version: use --response"),
            std::string::npos)
      << r.err;
}

TEST(CliPredict, SaveModelWritesOneFileOrAFolder) {
  TempDir tmp;
  std::string data = "a,b,y\n";
  for (int i = 0; i < 20; ++i)
    data += fmt::format("{},{},{}\n", i * 0.05, (i * 7 % 20) * 0.05, std::sin(i * 0.3) + 0.2 * (i * 7 % 20));
  write_file(tmp / "data.csv", data);
  const std::vector<std::string> common{
      "sensitivity", "--data", (tmp / "data.csv").string(), "--inputs", "a,b", "--response", "y", "--bootstrap", "0",
      "--base",      "64"};
  std::vector<std::string> args = common;
  args.insert(args.end(), {"--metamodels", "rsm2", "--save-model", (tmp / "one.json").string()});
  CommandResult r = run_demsa(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(read_file(tmp / "one.json"))["kind"], "rsm2");
  args = common;
  args.insert(args.end(), {"--metamodels", "rsm2,rbf-tps", "--save-model", (tmp / "two.json").string()});
  r = run_demsa(args);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("2 metamodels (1 response(s) x 2 kind(s)) need a folder, not a .json file"), std::string::npos)
      << r.err;
  args = common;
  args.insert(args.end(), {"--metamodels", "rsm2,rbf-tps", "--save-model", (tmp / "models").string()});
  r = run_demsa(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(tmp / "models" / "y.rsm2.json"));
  EXPECT_TRUE(fs::exists(tmp / "models" / "y.rbf-tps.json"));
  // The Saltelli path fits no metamodel.
  r = run_demsa({"sensitivity", "--saltelli", (tmp / "data.csv").string(), "--response", "y", "--save-model",
                 (tmp / "m.json").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--save-model: a Saltelli design gives indices without a metamodel"), std::string::npos)
      << r.err;
}

TEST(CliSensitivitySaltelli, ResponseColumnsAppendedToTheDesign) {
  TempDir tmp;
  ASSERT_EQ(run_demsa({"design", "saltelli", "-N", "256", "--dim", "3", "--seed", "5", "--replicates", "1", "-o",
                       (tmp / "design.csv").string()})
                .exit_code,
            0);
  const CsvTable design = read_csv(tmp / "design.csv");
  std::ostringstream y, appended;
  y.precision(17);
  appended.precision(17);
  y << "y\n";
  appended << "block,x1,x2,x3,y\n";
  for (int i = 0; i < design.rows(); ++i) {
    const double x1 = design.values(i, 1), x2 = design.values(i, 2), x3 = design.values(i, 3);
    const double v = x1 + 2.0 * x2 * x3 + x3 * x3;
    y << v << "\n";
    appended << design.values(i, 0) << "," << x1 << "," << x2 << "," << x3 << "," << v << "\n";
  }
  write_file(tmp / "y.csv", y.str());
  write_file(tmp / "design_y.csv", appended.str());
  CommandResult separate =
      run_demsa({"sensitivity", "--saltelli", (tmp / "design.csv").string(), "--responses", (tmp / "y.csv").string(),
                 "--bootstrap", "20", "--json", (tmp / "separate.json").string()});
  ASSERT_EQ(separate.exit_code, 0) << separate.err;
  CommandResult one = run_demsa({"sensitivity", "--saltelli", (tmp / "design_y.csv").string(), "--response", "y",
                                 "--bootstrap", "20", "--json", (tmp / "one.json").string()});
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const nlohmann::json a = nlohmann::json::parse(read_file(tmp / "separate.json"));
  const nlohmann::json b = nlohmann::json::parse(read_file(tmp / "one.json"));
  EXPECT_EQ(b["inputs"], (nlohmann::json{"x1", "x2", "x3"}));
  EXPECT_EQ(a["outputs"], b["outputs"]);

  // Not named: the design's last column could be a parameter or a response.
  CommandResult r = run_demsa({"sensitivity", "--saltelli", (tmp / "design_y.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--response NAME[,...] naming response columns appended to the design file"), std::string::npos)
      << r.err;
  // Named, but also in --responses: ambiguous.
  r = run_demsa({"sensitivity", "--saltelli", (tmp / "design_y.csv").string(), "--responses", (tmp / "y.csv").string(),
                 "--response", "y"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--response y: ambiguous: 'y' is a column of the design"), std::string::npos) << r.err;
  r = run_demsa({"sensitivity", "--saltelli", (tmp / "design_y.csv").string(), "--response", "z"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("design_y.csv:1: no column 'z' (columns: block, x1, x2, x3, y)"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace demsa::test
