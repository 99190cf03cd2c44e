// `demsa design lhs|sobol|saltelli` through the real binary: files, metrics, and usage errors.
#include "orchestrator/csv.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <set>

namespace demsa::test {
namespace {

TEST(CliDesign, LhsMaximinWithBoundsWritesOnePointPerStratum) {
  TempDir dir;
  const CommandResult r = run_demsa({"design", "lhs", "-n", "40", "--param", "E:1e8:1e9:log", "--param", "nu:0.2:0.4",
                                     "--param", "mu:0.7:1.9", "--criterion", "maximin", "--time-limit", "0.5", "--seed",
                                     "3", "-o", (dir / "d.csv").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["design"], "lhs-maximin");
  EXPECT_EQ(j["seed"], 3);
  EXPECT_GT(j["metrics"]["min_distance"].get<double>(), 0.0);
  const CsvTable t = read_csv(dir / "d.csv");
  ASSERT_EQ(t.columns, (std::vector<std::string>{"E", "nu", "mu"}));
  ASSERT_EQ(t.rows(), 40);
  // Strata in the unit cube: log scale for E.
  std::set<int> e, nu;
  for (int i = 0; i < 40; ++i) {
    e.insert(static_cast<int>(std::floor(std::log(t.values(i, 0) / 1e8) / std::log(10.0) * 40)));
    nu.insert(static_cast<int>(std::floor((t.values(i, 1) - 0.2) / 0.2 * 40)));
  }
  EXPECT_EQ(e.size(), 40u);
  EXPECT_EQ(nu.size(), 40u);
}

TEST(CliDesign, SobolAndCentredOnTheUnitCube) {
  TempDir dir;
  CommandResult r = run_demsa({"design", "sobol", "-n", "64", "--dim", "3", "-o", (dir / "s.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("centred L2 discrepancy"), std::string::npos) << r.out;
  const CsvTable t = read_csv(dir / "s.csv");
  EXPECT_EQ(t.columns, (std::vector<std::string>{"x1", "x2", "x3"}));
  EXPECT_EQ(t.rows(), 64);
  r = run_demsa({"design", "lhs", "-n", "8", "--dim", "2", "--centred", "-o", (dir / "c.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvTable c = read_csv(dir / "c.csv");
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(std::fmod(c.values(i, 0) * 8, 1.0), 0.5, 1e-12);
}

TEST(CliDesign, SaltelliWritesBlocks) {
  TempDir dir;
  const CommandResult r = run_demsa({"design", "saltelli", "-N", "32", "--param", "a:0:1", "--param", "b:-1:1",
                                     "--second-order", "-o", (dir / "s.csv").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["rows"], 32 * 6);
  const CsvTable t = read_csv(dir / "s.csv");
  EXPECT_EQ(t.columns, (std::vector<std::string>{"block", "a", "b"}));
  ASSERT_EQ(t.rows(), 192);
  EXPECT_EQ(t.values(0, 0), 0.0);
  EXPECT_EQ(t.values(191, 0), 5.0);
  // AB_1 row r takes a from B and b from A.
  EXPECT_EQ(t.values(64 + 5, 1), t.values(32 + 5, 1));
  EXPECT_EQ(t.values(64 + 5, 2), t.values(5, 2));
}

TEST(CliDesignErrors, BadArguments) {
  TempDir dir;
  const std::string out = (dir / "x.csv").string();
  CommandResult r = run_demsa({"design", "lhs", "-n", "10", "--dim", "2", "--criterion", "entropy", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown LHS criterion 'entropy' (valid: maximin, cl2)"), std::string::npos) << r.err;
  r = run_demsa({"design", "lhs", "-n", "10", "--param", "E:5:1", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("low (5) must be less than high (1)"), std::string::npos) << r.err;
  r = run_demsa({"design", "lhs", "-n", "10", "--param", "E:abc:1", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("'abc' is not a number"), std::string::npos) << r.err;
  r = run_demsa({"design", "sobol", "-n", "10", "--dim", "41", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("at most 40"), std::string::npos) << r.err;
  r = run_demsa({"design", "saltelli", "-N", "16", "--dim", "21", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  r = run_demsa({"design", "lhs", "-n", "10", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--dim"), std::string::npos) << r.err;
  r = run_demsa({"design", "halton", "-n", "10"});
  EXPECT_EQ(r.exit_code, 2);
}

}  // namespace
}  // namespace demsa::test
