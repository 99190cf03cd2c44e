// `demsa sensitivity` through the real binary: Ishigami evaluated outside on a Saltelli design, metamodels on data
// the user already has, and every bad-input path naming file, line, column and value.
#include "orchestrator/util/csv.hpp"
#include "support/process.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <map>
#include <sstream>
#include <thread>

using namespace demsa::util;

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
                 "--second-order", "--seed", "7", "--replicates", "1", "-o", (dir / "design.csv").string()});
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
  // One scrambled design: a bootstrap interval, with what it assumes.
  EXPECT_NE(o["note"].get<std::string>().find("treat the base rows as independent random draws"), std::string::npos);
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

/// data_csv with a fourth input that is the first in other units: every metamodel's system is singular.
std::string collinear_csv(int n) {
  std::istringstream in(data_csv(n));
  std::string out, line;
  for (int row = 0; std::getline(in, line); ++row) {
    const std::size_t first = line.find(','), fourth = line.find(',', line.find(',', first + 1) + 1);
    const std::size_t fifth = line.find(',', fourth + 1);
    const std::string a = line.substr(0, first);
    out += line.substr(0, fourth + 1) + (row == 0 ? "a_per_cent" : fmt::format("{}", 100 * std::stod(a))) +
           line.substr(fifth) + "\n";
  }
  return out;
}

TEST(CliSensitivity, MetamodelsOnUserData) {
  TempDir dir;
  write_file(dir / "data.csv", data_csv(60));
  const CommandResult r = run_demsa({"sensitivity", "--data", (dir / "data.csv").string(), "--inputs", "a,b,c",
                                     "--response", "y", "--bounds", "a=0:10", "--metamodels", "rsm2,rbf-cubic",
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

TEST(CliSensitivity, BoundsFarWiderThanTheDataAreRefusedUnlessExtrapolationIsAllowed) {
  TempDir dir;
  write_file(dir / "data.csv", data_csv(60));  // a in [0, 9.9]
  const std::vector<std::string> common{"sensitivity",
                                        "--data",
                                        (dir / "data.csv").string(),
                                        "--inputs",
                                        "a,b,c",
                                        "--response",
                                        "y",
                                        "--bounds",
                                        "a=0:100",
                                        "--metamodels",
                                        "rsm2"};
  const CommandResult refused = run_demsa(common);
  EXPECT_EQ(refused.exit_code, 2) << refused.out;
  EXPECT_NE(refused.err.find("--bounds a=0:100: the data cover a in [0, 9."), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("% of the bounds (less than 50 %)"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("give --allow-extrapolation"), std::string::npos) << refused.err;
  std::vector<std::string> allowed = common;
  for (const char* a : {"--allow-extrapolation", "--json", "-"}) allowed.emplace_back(a);
  const CommandResult r = run_demsa(allowed);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("demsa: warning: --bounds a=0:100: the data cover a"), std::string::npos) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_LT(j["bounds"][0]["coverage"].get<double>(), 0.1);
  EXPECT_TRUE(j["bounds"][0]["extrapolated"].get<bool>());
  EXPECT_FALSE(j["bounds"][1]["extrapolated"].get<bool>());
}

TEST(CliSensitivity, DataBaseThatIsNotAPowerOfTwoIsRoundedUpAndSaysSo) {
  TempDir dir;
  write_file(dir / "data.csv", data_csv(60));
  const CommandResult r =
      run_demsa({"sensitivity", "--data", (dir / "data.csv").string(), "--inputs", "a,b,c", "--response", "y",
                 "--metamodels", "rbf-cubic", "--bootstrap", "0", "--base", "1000", "--json", "-"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("--base 1000 is not a power of two: rounded up to 1024"), std::string::npos) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["outputs"][0]["metamodels"][0]["sobol"]["base"].get<int>(), 1024) << r.out;
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
      {"no column", good, {"--response", "z"}, "no column 'z' (columns: a, b, c, const, y)"},
      {"too few", data_csv(12), {"--metamodels", "rsm3"}, "rsm3 needs at least 20 samples for 3 inputs (got 12)"},
      {"duplicate",
       replace_line(good, 12, "0,0.10000000000000001,0.29999999999999999,4,0.01"),
       {"--metamodels", "rbf-tps"},
       "data.csv:12: duplicates the point of sample 1"},
      {"duplicate's point",
       replace_line(good, 12, "0,0.10000000000000001,0.29999999999999999,4,0.01"),
       {"--metamodels", "gp"},
       "(sample 1 is line 2: a = 0, b = 0.1, c = 0.3)"},
      {"collinear",
       collinear_csv(60),
       {"--inputs", "a,b,c,a_per_cent"},
       "data.csv: columns 'a' and 'a_per_cent' are collinear (a_per_cent = 100 * a + 0 in every sample)"},
      {"input twice", good, {"--inputs", "a,b,a"}, "--inputs: 'a' is listed twice"},
      {"output as input", good, {"--inputs", "a,b,y"}, "'y' is both an input (--inputs) and a response (--response)"},
      {"bounds twice", good, {"--bounds", "a=0:10,a=0:20"}, "--bounds: 'a' is given twice"},
      {"bootstrap", good, {"--bootstrap", "-5"}, "--bootstrap -5: must be >= 0"},
      {"confidence", good, {"--confidence", "1.5"}, "--confidence 1.5: must be strictly between 0 and 1"},
      {"base", good, {"--base", "1"}, "--base 1: must be at least 16"},
      {"base above the cap", good, {"--base", "1048577"}, "--base 1048577: at most 2^20 = 1048576"},
      {"kernel", good, {"--gp-kernel", "rbf"}, "--gp-kernel: unknown GP kernel 'rbf' (valid: squared-exponential"},
      {"trend", good, {"--gp-trend", "cubic"}, "--gp-trend: unknown GP trend 'cubic' (valid: constant, linear)"},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.name);
    TempDir dir;
    write_file(dir / "data.csv", c.data);
    std::vector<std::string> args{"sensitivity", "--data", (dir / "data.csv").string()};
    // the common options, unless the case gives its own
    const std::vector<std::pair<std::string, std::string>> defaults{
        {"--bootstrap", "0"}, {"--base", "256"}, {"--inputs", "a,b,c"}, {"--response", "y"}, {"--metamodels", "rsm2"}};
    for (const auto& [option, value] : defaults)
      if (std::find(c.extra.begin(), c.extra.end(), option) == c.extra.end()) args.insert(args.end(), {option, value});
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

/// One output per row of a design CSV (columns x1, x2, x3): y = x1 + 2 x2 x3 + x3².
std::string responses_of(const std::filesystem::path& design) {
  const CsvTable d = read_csv(design);
  const int x1 = d.column_index("x1");
  std::string y = "y\n";
  for (int i = 0; i < d.rows(); ++i) {
    const double a = d.values(i, x1), b = d.values(i, x1 + 1), c = d.values(i, x1 + 2);
    y += fmt::format("{}\n", a + 2 * b * c + c * c);
  }
  return y;
}

TEST(CliSensitivityErrors, DesignsThatAreNotSaltelliDesigns) {
  TempDir dir;
  ASSERT_EQ(run_demsa({"design", "saltelli", "-N", "64", "--dim", "3", "-o", (dir / "d.csv").string()}).exit_code, 0);
  write_file(dir / "y.csv", responses_of(dir / "d.csv"));
  CommandResult r = run_demsa({"sensitivity", "--saltelli", (dir / "d.csv").string(), "--responses",
                               (dir / "y.csv").string(), "--bootstrap", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;

  // An AB_2 row whose third column is not A's: file, line, column and both values.
  std::istringstream in(read_file(dir / "d.csv"));
  std::string edited, line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (n == 1 + 3 * 64 + 5) line = line.substr(0, line.rfind(',')) + ",0.123456";  // row 5 of block AB2
    edited += line + "\n";
  }
  write_file(dir / "edited.csv", edited);
  r = run_demsa({"sensitivity", "--saltelli", (dir / "edited.csv").string(), "--responses", (dir / "y.csv").string(),
                 "--bootstrap", "0"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("edited.csv:198: column 'x3': 0.123456 differs from"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("in row 5 of block A: block AB2 is A with column 2 taken from B"), std::string::npos) << r.err;

  // A and B as consecutive halves of one 3-dimensional sequence, AB_i built from them correctly: refused.
  ASSERT_EQ(run_demsa({"design", "sobol", "-n", "128", "--dim", "3", "-o", (dir / "s.csv").string()}).exit_code, 0);
  const CsvTable seq = read_csv(dir / "s.csv");
  std::string design = "block,x1,x2,x3\n";
  for (int block = 0; block < 5; ++block)
    for (int t = 0; t < 64; ++t) {
      design += std::to_string(block);
      for (int k = 0; k < 3; ++k) {
        const bool from_b = block == 1 || (block >= 2 && k == block - 2);
        design += fmt::format(",{}", seq.values(from_b ? 64 + t : t, k));
      }
      design += "\n";
    }
  write_file(dir / "halves.csv", design);
  write_file(dir / "yh.csv", responses_of(dir / "halves.csv"));
  r = run_demsa({"sensitivity", "--saltelli", (dir / "halves.csv").string(), "--responses", (dir / "yh.csv").string(),
                 "--bootstrap", "0"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("halves.csv: column 'x1': the A and B rows are rank-correlated"), std::string::npos) << r.err;
}

TEST(CliSensitivity, GpOptionsAndLabelColumns) {
  TempDir dir;
  // a label column that is not an input or output is not read as a number
  std::istringstream in(data_csv(60));
  std::string text, line;
  for (int n = 0; std::getline(in, line); ++n) text += line + (n == 0 ? ",label\n" : fmt::format(",run {}\n", n));
  write_file(dir / "data.csv", text);
  const CommandResult r = run_demsa({"sensitivity",
                                     "--data",
                                     (dir / "data.csv").string(),
                                     "--inputs",
                                     "a,b,c",
                                     "--response",
                                     "y",
                                     "--metamodels",
                                     "gp",
                                     "--gp-kernel",
                                     "matern52",
                                     "--gp-trend",
                                     "linear",
                                     "--gp-nugget",
                                     "--bootstrap",
                                     "0",
                                     "--base",
                                     "1024",
                                     "--json",
                                     "-"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const nlohmann::json& gp = j["outputs"][0]["metamodels"][0];
  EXPECT_EQ(gp["metamodel"], "gp");
  EXPECT_GT(gp["quality"]["q2"].get<double>(), 0.95);
  EXPECT_GT(gp["sobol"]["S1"]["a"]["value"].get<double>(), 0.9);
  EXPECT_GT(gp["quality"]["parameters"]["nugget"].get<double>(), 0.0) << gp["quality"].dump();  // estimated
}

/// `demsa design saltelli` of Ishigami's three inputs in DIR/design.csv and its outputs in DIR/y.csv.
void ishigami_files(const TempDir& dir, const std::vector<std::string>& design_options) {
  const std::string p = "-3.14159265358979323846:3.14159265358979323846";
  std::vector<std::string> args{"design",  "saltelli", "--param", "x1:" + p, "--param",
                                "x2:" + p, "--param",  "x3:" + p, "-o",      (dir / "design.csv").string()};
  args.insert(args.end(), design_options.begin(), design_options.end());
  const CommandResult r = run_demsa(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvTable design = read_csv(dir / "design.csv");
  const int first = design.column_index("x1");
  std::ostringstream y;
  y.precision(17);
  y << "y\n";
  for (int i = 0; i < design.rows(); ++i)
    y << ishigami(design.values(i, first), design.values(i, first + 1), design.values(i, first + 2)) << "\n";
  write_file(dir / "y.csv", y.str());
}

TEST(CliSensitivity, ReplicatedDesignGivesStudentTIntervals) {
  TempDir dir;
  ishigami_files(dir, {"-N", "1024", "--replicates", "16", "--seed", "3"});
  const CsvTable design = read_csv(dir / "design.csv");
  EXPECT_EQ(design.columns[1], "replicate");
  const CommandResult r = run_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses",
                                     (dir / "y.csv").string(), "--json", (dir / "out.json").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Student-t intervals from 16 independently scrambled replicates"), std::string::npos) << r.out;
  const nlohmann::json o = nlohmann::json::parse(read_file(dir / "out.json"))["outputs"][0];
  EXPECT_EQ(o["replicates"], 16);
  EXPECT_EQ(o["bootstrap"], 0);
  EXPECT_FALSE(o.contains("note"));
  EXPECT_NEAR(o["S1"]["x1"]["value"].get<double>(), 0.3139, 0.03);
  EXPECT_LT(o["S1"]["x1"]["lower"].get<double>(), o["S1"]["x1"]["upper"].get<double>());
  // A replicate column that does not follow the blocks is named with its line.
  std::string text = read_file(dir / "design.csv");
  const std::size_t line_start = text.find("\n1,1,") + 1;  // first row of block B, replicate 1
  text.replace(line_start, 4, "1,2,");
  write_file(dir / "bad.csv", text);
  const CommandResult bad =
      run_demsa({"sensitivity", "--saltelli", (dir / "bad.csv").string(), "--responses", (dir / "y.csv").string()});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("bad.csv:1026"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("column 'replicate'"), std::string::npos) << bad.err;
}

TEST(CliSensitivity, DefaultIntervalsComeFromTheReplicatesOfTheDefaultDesign) {
  TempDir dir;
  ishigami_files(dir, {"-N", "1024", "--seed", "5"});
  const CsvTable design = read_csv(dir / "design.csv");
  ASSERT_EQ(design.columns[1], "replicate");
  EXPECT_EQ(design.values.col(1).maxCoeff(), 8.0);  // 8 replicates by default
  const CommandResult r = run_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses",
                                     (dir / "y.csv").string(), "--json", (dir / "out.json").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Student-t intervals from 8 independently scrambled replicates"), std::string::npos) << r.out;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  const nlohmann::json o = nlohmann::json::parse(read_file(dir / "out.json"))["outputs"][0];
  EXPECT_EQ(o["replicates"], 8);
  EXPECT_EQ(o["bootstrap"], 0);
  EXPECT_LT(o["S1"]["x2"]["lower"].get<double>(), o["S1"]["x2"]["upper"].get<double>());
  // The bootstrap by name, on the same design.
  const CommandResult boot = run_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses",
                                        (dir / "y.csv").string(), "--interval", "bootstrap", "--json", "-"});
  ASSERT_EQ(boot.exit_code, 0) << boot.err;
  const nlohmann::json b = nlohmann::json::parse(boot.out)["outputs"][0];
  EXPECT_EQ(b["bootstrap"], 200);
  EXPECT_FALSE(b.contains("replicates"));
}

TEST(CliSensitivity, OneScrambledDesignHasNoIntervalsUnlessTheBootstrapIsNamed) {
  TempDir dir;
  ishigami_files(dir, {"-N", "256", "--replicates", "1"});
  const CommandResult r = run_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses",
                                     (dir / "y.csv").string(), "--json", "-"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("design.csv: one scrambled design, without independently scrambled replicates"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("--interval bootstrap"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("wholly outside"), std::string::npos) << r.err;  // no interval, nothing to say
  const nlohmann::json o = nlohmann::json::parse(r.out)["outputs"][0];
  EXPECT_EQ(o["bootstrap"], 0);
  EXPECT_FALSE(o.contains("replicates"));
  // No interval: no zero-width one either (null bounds, as the text shows none).
  for (const char* index : {"S1", "ST"})
    for (const char* input : {"x1", "x2", "x3"}) {
      EXPECT_TRUE(o[index][input]["value"].is_number()) << o.dump();
      EXPECT_TRUE(o[index][input]["lower"].is_null()) << index << " " << input << ": " << o.dump();
      EXPECT_TRUE(o[index][input]["upper"].is_null()) << index << " " << input << ": " << o.dump();
    }
  EXPECT_TRUE(o["residual"]["lower"].is_null() && o["residual"]["upper"].is_null()) << o.dump();
  EXPECT_NE(o["note"].get<std::string>().find("no intervals"), std::string::npos) << o.dump();
  // --interval bootstrap, or --bootstrap B alone, names the bootstrap.
  for (const std::vector<std::string>& named :
       {std::vector<std::string>{"--interval", "bootstrap"}, std::vector<std::string>{"--bootstrap", "40"}}) {
    std::vector<std::string> args{
        "sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses", (dir / "y.csv").string(),
        "--json",      "-"};
    args.insert(args.end(), named.begin(), named.end());
    const CommandResult boot = run_demsa(args);
    ASSERT_EQ(boot.exit_code, 0) << boot.err;
    EXPECT_EQ(boot.err.find("warning"), std::string::npos) << boot.err;
    EXPECT_EQ(nlohmann::json::parse(boot.out)["outputs"][0]["bootstrap"], named[0] == "--bootstrap" ? 40 : 200);
  }
}

TEST(CliSensitivityErrors, IntervalOptionsThatDoNotGoTogether) {
  TempDir dir;
  ishigami_files(dir, {"-N", "64"});
  const std::vector<std::string> common{"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses",
                                        (dir / "y.csv").string()};
  const auto error_of = [&common](const std::vector<std::string>& extra) {
    std::vector<std::string> args = common;
    args.insert(args.end(), extra.begin(), extra.end());
    const CommandResult r = run_demsa(args);
    EXPECT_EQ(r.exit_code, 2) << r.out;
    return r.err;
  };
  EXPECT_NE(error_of({"--interval", "student"})
                .find("--interval: unknown interval method 'student' (valid: "
                      "replicates, bootstrap, none)"),
            std::string::npos);
  EXPECT_NE(error_of({"--interval", "replicates", "--bootstrap", "50"})
                .find("--bootstrap 50 gives the resamples of --interval bootstrap, not of --interval replicates"),
            std::string::npos);
  write_file(dir / "data.csv", data_csv(60));
  const CommandResult data = run_demsa({"sensitivity", "--data", (dir / "data.csv").string(), "--inputs", "a,b,c",
                                        "--response", "y", "--interval", "bootstrap"});
  EXPECT_EQ(data.exit_code, 2);
  EXPECT_NE(data.err.find("--interval goes with --saltelli"), std::string::npos) << data.err;
}

TEST(CliSensitivity, BootstrapOnOneScrambledDesignSaysWhatItAssumes) {
  TempDir dir;
  ishigami_files(dir, {"-N", "256"});
  const CommandResult r = run_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses",
                                     (dir / "y.csv").string(), "--bootstrap", "50"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("bootstrap intervals: they treat the base rows as independent random draws"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("--replicates R"), std::string::npos) << r.out;
}

TEST(CliSensitivity, BaseThatIsNotAPowerOfTwoIsWarnedAbout) {
  TempDir dir;
  // `demsa design saltelli` rounds N up to a power of two, so a design of N = 1000 is cut from one of 1024 (without
  // replicates): the first 1000 rows of every block.
  ishigami_files(dir, {"-N", "1024", "--replicates", "1"});
  {
    std::istringstream in(read_file(dir / "design.csv"));
    std::ostringstream cut, y;
    y.precision(17);
    y << "y\n";
    std::map<std::string, int> seen;
    std::string line;
    std::getline(in, line);
    cut << line << "\n";
    const CsvTable design = read_csv(dir / "design.csv");
    const int first = design.column_index("x1");
    for (int i = 0; std::getline(in, line); ++i) {
      if (seen[line.substr(0, line.find(','))]++ >= 1000) continue;
      cut << line << "\n";
      y << ishigami(design.values(i, first), design.values(i, first + 1), design.values(i, first + 2)) << "\n";
    }
    write_file(dir / "design.csv", cut.str());
    write_file(dir / "y.csv", y.str());
  }
  const CommandResult r = run_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses",
                                     (dir / "y.csv").string(), "--bootstrap", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("the base N = 1000 is not a power of two"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("rounds N up to a power of two"), std::string::npos) << r.err;
  ishigami_files(dir, {"-N", "1024", "--replicates", "1"});
  const CommandResult fine = run_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses",
                                        (dir / "y.csv").string(), "--bootstrap", "0"});
  EXPECT_EQ(fine.err.find("power of two"), std::string::npos) << fine.err;
}

TEST(CliSensitivityErrors, ConstantOutputIsAnErrorOnBothPaths) {
  TempDir dir;
  // --data: every y = 1 (the metamodels would fit it with R² NaN and give indices of round-off).
  std::string data = "a,b,c,y\n";
  for (int i = 0; i < 30; ++i)
    data += fmt::format("{},{},{},1\n", std::fmod(0.618034 * i, 1.0), std::fmod(0.7548777 * i + 0.1, 1.0),
                        std::fmod(0.5698403 * i + 0.3, 1.0));
  write_file(dir / "c.csv", data);
  const CommandResult r = run_demsa({"sensitivity", "--data", (dir / "c.csv").string(), "--inputs", "a,b,c",
                                     "--response", "y", "--metamodels", "rsm2,rbf-cubic"});
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find("c.csv"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("output 'y' is constant (every one of its 30 samples is 1"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("S1"), std::string::npos) << r.out;
  // --saltelli: outputs equal up to the last bit (0.1 + 0.2 against 0.3).
  ishigami_files(dir, {"-N", "64"});
  const CsvTable design = read_csv(dir / "design.csv");
  std::string y = "y\n";
  for (int i = 0; i < design.rows(); ++i) y += i % 2 ? "0.30000000000000004\n" : "0.3\n";
  write_file(dir / "y.csv", y);
  const CommandResult s =
      run_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses", (dir / "y.csv").string()});
  EXPECT_EQ(s.exit_code, 2) << s.out;
  EXPECT_NE(s.err.find("column 'y': the output is constant"), std::string::npos) << s.err;
  // A constant beyond 1e100 (scaled before its moments are taken) is named by its own mean, not the scaled one.
  std::string large = "y\n";
  for (int i = 0; i < design.rows(); ++i) large += "1e200\n";
  write_file(dir / "large.csv", large);
  const CommandResult l = run_demsa(
      {"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses", (dir / "large.csv").string()});
  EXPECT_EQ(l.exit_code, 2) << l.out;
  EXPECT_NE(l.err.find("the output is constant (mean 1e+200,"), std::string::npos) << l.err;
}

TEST(CliSensitivity, OutputsWhoseVarianceOverflowsAreScaledOrRefusedWithTheCause) {
  TempDir dir;
  // --data: y near 1e200 (finite; its squares are not): refused naming the magnitude and the remedy, no NaN printed.
  std::string data = "a,b,c,y\n";
  for (int i = 0; i < 30; ++i) {
    const double a = std::fmod(0.618034 * i, 1.0), b = std::fmod(0.7548777 * i + 0.1, 1.0);
    data += fmt::format("{},{},{},{:.17g}\n", a, b, std::fmod(0.5698403 * i + 0.3, 1.0), 1e200 * (1.0 + a + 0.5 * b));
  }
  write_file(dir / "big.csv", data);
  for (const char* model : {"rsm2", "rbf-cubic", "gp"}) {
    const CommandResult r = run_demsa({"sensitivity", "--data", (dir / "big.csv").string(), "--inputs", "a,b,c",
                                       "--response", "y", "--metamodels", model});
    EXPECT_EQ(r.exit_code, 2) << model << r.out;
    EXPECT_NE(r.err.find("output 'y': values reach"), std::string::npos) << model << r.err;
    EXPECT_NE(r.err.find("would overflow double precision"), std::string::npos) << model << r.err;
    EXPECT_EQ(r.out.find("nan"), std::string::npos) << model << r.out;
  }
  // --saltelli: y = 1e308 x1 gives the indices of y = x1 (S1 of x1 = 1).
  ishigami_files(dir, {"-N", "256"});
  const CsvTable design = read_csv(dir / "design.csv");
  const int first = design.column_index("x1");
  std::ostringstream y;
  y.precision(17);
  y << "y\n";
  for (int i = 0; i < design.rows(); ++i) y << 1e308 * (design.values(i, first) / 3.14159265358979323846) << "\n";
  write_file(dir / "y.csv", y.str());
  const CommandResult s = run_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses",
                                     (dir / "y.csv").string(), "--json", "-"});
  ASSERT_EQ(s.exit_code, 0) << s.err;
  EXPECT_EQ(s.out.find("nan"), std::string::npos) << s.out;
  const nlohmann::json j = nlohmann::json::parse(s.out);
  EXPECT_NEAR(j["outputs"][0]["S1"]["x1"]["value"].get<double>(), 1.0, 0.05) << s.out;
  EXPECT_NEAR(j["outputs"][0]["ST"]["x2"]["value"].get<double>(), 0.0, 0.05) << s.out;
}

TEST(CliSensitivity, IndicesWhollyOutsideTheUnitIntervalPointAtMismatchedRows) {
  TempDir dir;
  ishigami_files(dir, {"-N", "256"});
  // The responses sorted: no longer in the design's row order.
  std::istringstream in(read_file(dir / "y.csv"));
  std::string line;
  std::getline(in, line);
  std::vector<double> values;
  while (std::getline(in, line)) values.push_back(std::stod(line));
  std::sort(values.begin(), values.end());
  std::ostringstream y;
  y.precision(17);
  y << "y\n";
  for (const double v : values) y << v << "\n";
  write_file(dir / "sorted.csv", y.str());
  const CommandResult r = run_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses",
                                     (dir / "sorted.csv").string(), "--json", "-"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("lie wholly outside [0, 1]: the responses may not match the design's rows"), std::string::npos)
      << r.err;
  EXPECT_TRUE(nlohmann::json::parse(r.out)["outputs"][0].contains("warning")) << r.out;
  // In the design's order, no such warning.
  const CommandResult fine =
      run_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses", (dir / "y.csv").string()});
  ASSERT_EQ(fine.exit_code, 0) << fine.err;
  EXPECT_EQ(fine.err.find("wholly outside"), std::string::npos) << fine.err;
}

TEST(CliSensitivity, SigintStopsTheBootstrapAndWritesNoJson) {
  TempDir dir;
  ishigami_files(dir, {"-N", "1024"});
  const pid_t pid =
      spawn_demsa({"sensitivity", "--saltelli", (dir / "design.csv").string(), "--responses", (dir / "y.csv").string(),
                   "--bootstrap", "100000000", "--json", (dir / "out.json").string()},
                  dir / "demsa.log");
  std::this_thread::sleep_for(std::chrono::seconds(1));
  ::kill(pid, SIGINT);
  const auto sent = std::chrono::steady_clock::now();
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count(), 3.0);
  ASSERT_TRUE(WIFEXITED(status)) << read_file(dir / "demsa.log");
  EXPECT_EQ(WEXITSTATUS(status), 130) << read_file(dir / "demsa.log");
  EXPECT_FALSE(std::filesystem::exists(dir / "out.json"));
}

}  // namespace
}  // namespace demsa::test
