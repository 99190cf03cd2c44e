// `demsa sensitivity` through the real binary: Ishigami evaluated outside on a Saltelli design, metamodels on data
// the user already has, and every bad-input path naming file, line, column and value.
#include "orchestrator/csv.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>

namespace demsa::test {
namespace {

double ishigami(double x1, double x2, double x3) {
  return std::sin(x1) + 7.0 * std::sin(x2) * std::sin(x2) + 0.1 * std::pow(x3, 4) * std::sin(x1);
}

TEST(CliSensitivity, IshigamiThroughTheCommandLine) {
  TempDir dir;
  const std::string p = "-3.14159265358979323846:3.14159265358979323846";
  CommandResult r =
      run_demsa({"design", "saltelli", "-N", "2048", "--param", "x1:" + p, "--param", "x2:" + p, "--param", "x3:" + p,
                 "--second-order", "--seed", "7", "-o", (dir / "design.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The simulator, outside demsa.
  const CsvTable design = read_csv(dir / "design.csv");
  std::ostringstream y;
  y.precision(17);
  y << "y\n";
  for (int i = 0; i < design.rows(); ++i)
    y << ishigami(design.values(i, 1), design.values(i, 2), design.values(i, 3)) << "\n";
  write_file(dir / "y.csv", y.str());
  r = run_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses", (dir / "y.csv").string(),
                 "--second-order", "--bootstrap", "100", "--json", (dir / "out.json").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("residual 1 - sum S1"), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(read_file(dir / "out.json"));
  const nlohmann::json& o = j["outputs"][0];
  const double s1[] = {0.3139, 0.4424, 0.0}, st[] = {0.5576, 0.4424, 0.2437};
  for (int k = 0; k < 3; ++k) {
    const std::string x = std::vector<std::string>{"x1", "x2", "x3"}[static_cast<std::size_t>(k)];
    EXPECT_NEAR(o["S1"][x]["value"].get<double>(), s1[k], 0.005) << x;
    EXPECT_NEAR(o["ST"][x]["value"].get<double>(), st[k], 0.005) << x;
    EXPECT_LE(o["S1"][x]["lower"].get<double>(), o["S1"][x]["value"].get<double>()) << x;
    EXPECT_GE(o["S1"][x]["upper"].get<double>(), o["S1"][x]["value"].get<double>()) << x;
  }
  EXPECT_EQ(o["S2"][1]["i"], "x1");
  EXPECT_EQ(o["S2"][1]["j"], "x3");
  EXPECT_NEAR(o["S2"][1]["S2"]["value"].get<double>(), 0.2437, 0.01);
  EXPECT_FALSE(o.contains("note"));
  EXPECT_EQ(o["bootstrap"], 100);
}

/// A data file: y = 3a + b² + 0.5 a c on a 60-point grid-free design, plus a constant column.
std::string data_csv(int n) {
  std::ostringstream out;
  out.precision(17);
  out << "a,b,c,const,y\n";
  for (int i = 0; i < n; ++i) {
    const double a = std::fmod(0.618034 * i, 1.0), b = std::fmod(0.7548777 * i + 0.1, 1.0),
                 c = std::fmod(0.5698403 * i + 0.3, 1.0);
    out << 10 * a << "," << b << "," << c << ",4," << 3 * a + b * b + 0.5 * a * c << "\n";
  }
  return out.str();
}

TEST(CliSensitivity, MetamodelsOnUserData) {
  TempDir dir;
  write_file(dir / "data.csv", data_csv(60));
  const CommandResult r = run_demsa({"sensitivity", "--data", (dir / "data.csv").string(), "--inputs", "a,b,c",
                                     "--output", "y", "--bounds", "a=0:10", "--metamodels", "rsm2,rbf-cubic",
                                     "--bootstrap", "20", "--base", "1024", "--json", (dir / "out.json").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(read_file(dir / "out.json"));
  const nlohmann::json& models = j["outputs"][0]["metamodels"];
  ASSERT_EQ(models.size(), 2u);
  EXPECT_EQ(models[0]["metamodel"], "rsm2");
  EXPECT_EQ(models[0]["sobol"]["method"], "rsm-exact");
  EXPECT_NEAR(models[0]["quality"]["r2"].get<double>(), 1.0, 1e-9);  // y is quadratic in (a/10, b, c)
  EXPECT_EQ(models[1]["sobol"]["method"], "metamodel-qmc");
  // y = 3a + b² + 0.5ac with a on [0,10]: a dominates.
  EXPECT_GT(models[0]["sobol"]["S1"]["a"]["value"].get<double>(), 0.9);
  EXPECT_TRUE(models[0]["quality"]["q2"].is_number());
  EXPECT_EQ(j["bounds"][0]["high"], 10.0);
}

struct BadCase {
  std::string name;
  std::string data;                ///< content of data.csv
  std::vector<std::string> extra;  ///< arguments after the common ones
  std::string expected;            ///< substring of the error
};

TEST(CliSensitivityErrors, EachBadInputNamesFileRowColumnAndValue) {
  const std::string good = data_csv(60);
  std::string nan_cell = good, text_cell = good, short_row = good, empty_cell = good;
  auto replace_line = [](std::string text, int line, const std::string& with) {
    std::istringstream in(text);
    std::string out, l;
    for (int n = 1; std::getline(in, l); ++n) out += (n == line ? with : l) + "\n";
    return out;
  };
  const std::vector<BadCase> cases{
      {"nan", replace_line(good, 7, "1,0.5,nan,4,2"), {}, "data.csv:7: column 'c': 'nan' is not a finite number"},
      {"text", replace_line(good, 9, "1,abc,0.5,4,2"), {}, "data.csv:9: column 'b': 'abc' is not a number"},
      {"empty", replace_line(good, 4, "1,,0.5,4,2"), {}, "data.csv:4: column 'b': empty cell"},
      {"columns", replace_line(good, 5, "1,0.5,4,2"), {}, "data.csv:5: 4 values for 5 columns"},
      {"empty file", "", {}, "data.csv: empty file"},
      {"constant", good, {"--inputs", "a,b,const"}, "column 'const': constant input (every sample is 4)"},
      {"bounds", good, {"--bounds", "a=10:0"}, "low (10) must be less than high (0)"},
      {"outside", good, {"--bounds", "a=0:5"}, "is outside the bounds [0, 5]"},
      {"metamodel", good, {"--metamodels", "rsm2,krig"}, "unknown metamodel 'krig' (valid: rsm1, rsm2, rsm3"},
      {"no column", good, {"--output", "z"}, "no column 'z' (columns: a, b, c, const, y)"},
      {"too few", data_csv(12), {"--metamodels", "rsm3"}, "rsm3 needs at least 20 samples for 3 inputs (got 12)"},
      {"duplicate",
       replace_line(good, 12, "0,0.10000000000000001,0.29999999999999999,4,0.01"),
       {"--metamodels", "rbf-tps"},
       "data.csv:12: duplicates the point of sample 1"},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.name);
    TempDir dir;
    write_file(dir / "data.csv", c.data);
    std::vector<std::string> args{"sensitivity", "--data", (dir / "data.csv").string(), "--bootstrap", "0",
                                  "--base",      "256"};
    bool has_inputs = false, has_output = false, has_models = false;
    for (const std::string& a : c.extra) {
      has_inputs |= a == "--inputs";
      has_output |= a == "--output";
      has_models |= a == "--metamodels";
    }
    if (!has_inputs) args.insert(args.end(), {"--inputs", "a,b,c"});
    if (!has_output) args.insert(args.end(), {"--output", "y"});
    if (!has_models) args.insert(args.end(), {"--metamodels", "rsm2"});
    args.insert(args.end(), c.extra.begin(), c.extra.end());
    const CommandResult r = run_demsa(args, dir.path());
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
    EXPECT_EQ(r.err.rfind("demsa: error: ", 0), 0u) << r.err;
  }
}

TEST(CliSensitivityErrors, SaltelliFilesThatDoNotMatch) {
  TempDir dir;
  ASSERT_EQ(run_demsa({"design", "saltelli", "-N", "16", "--dim", "2", "-o", (dir / "d.csv").string()}).exit_code, 0);
  std::string y = "y\n";
  for (int i = 0; i < 63; ++i) y += std::to_string(i % 7) + "\n";
  write_file(dir / "y.csv", y);
  CommandResult r =
      run_demsa({"sensitivity", "--saltelli", (dir / "d.csv").string(), "--responses", (dir / "y.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("63 rows, but the design"), std::string::npos) << r.err;
  write_file(dir / "y.csv", y + "nan\n");
  r = run_demsa({"sensitivity", "--saltelli", (dir / "d.csv").string(), "--responses", (dir / "y.csv").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("y.csv:65: column 'y': 'nan' is not a finite number"), std::string::npos) << r.err;
  r = run_demsa({"sensitivity", "--data", "a.csv", "--saltelli", "b.csv"});
  EXPECT_EQ(r.exit_code, 2);
}

}  // namespace
}  // namespace demsa::test
