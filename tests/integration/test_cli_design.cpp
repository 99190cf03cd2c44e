// `demsa design lhs|sobol|saltelli` through the real binary: files, metrics, and usage errors.
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/csv.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

using namespace demsa::util;

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
                                     "--second-order", "--replicates", "1", "-o", (dir / "s.csv").string(), "--json"});
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

TEST(CliDesign, SaltelliComesInReplicatesByDefault) {
  TempDir dir;
  const std::string out = (dir / "s.csv").string();
  CommandResult r = run_demsa({"design", "saltelli", "-N", "1024", "--dim", "2", "-o", out, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["replicates"], 8);
  const CsvTable t = read_csv(out);
  ASSERT_EQ(t.columns, (std::vector<std::string>{"block", "replicate", "x1", "x2"}));
  EXPECT_EQ(t.values(0, 1), 1.0);
  EXPECT_EQ(t.values(127, 1), 1.0);
  EXPECT_EQ(t.values(128, 1), 2.0);
  EXPECT_EQ(t.values(1023, 1), 8.0);
  // Fewer below N = 128, each replicate keeping 16 rows; none at N = 16; the text says which.
  r = run_demsa({"design", "saltelli", "-N", "32", "--dim", "2", "-o", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("2 independently scrambled replicates of 16 base rows"), std::string::npos) << r.out;
  r = run_demsa({"design", "saltelli", "-N", "16", "--dim", "2", "-o", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("one scrambled design (no replicates)"), std::string::npos) << r.out;
  EXPECT_EQ(read_csv(out).columns[1], "x1");
  r = run_demsa({"design", "saltelli", "-N", "64", "--dim", "2", "--replicates", "3", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--replicates 3: must divide the base N = 64"), std::string::npos) << r.err;
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
  EXPECT_NE(r.err.find("--dim 21: a Saltelli design supports at most 20 parameters"), std::string::npos) << r.err;
  r = run_demsa({"design", "lhs", "-n", "10", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--dim"), std::string::npos) << r.err;
  r = run_demsa({"design", "halton", "-n", "10"});
  EXPECT_EQ(r.exit_code, 2);
}

// Each error names the option as typed on the command line and its rule, not a field of the sobol/ library's
// Options structs (those names stay in the library's own messages).
TEST(CliDesignErrors, ValuesOutOfRangeNameTheOption) {
  TempDir dir;
  const std::string out = (dir / "x.csv").string();
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases = {
      {{"lhs", "-n", "1", "--dim", "2"}, "demsa: error: -n 1: a Latin hypercube needs at least 2 samples"},
      {{"lhs", "-n", "10", "--dim", "2", "--criterion", "maximin", "--time-limit", "0"},
       "demsa: error: --time-limit 0: the safety stop must be > 0 seconds"},
      {{"lhs", "-n", "10", "--dim", "2", "--criterion", "maximin", "--iterations", "0"},
       "demsa: error: --iterations 0: the optimisation needs at least 1 iteration"},
      {{"lhs", "-n", "5000", "--dim", "2", "--criterion", "cl2"},
       "demsa: error: -n 5000: an optimised Latin hypercube keeps n x n tables of pairs; at most 4096 samples"},
      {{"lhs", "-n", "10", "--dim", "2", "--phi-p", "0.5"},
       "demsa: error: --phi-p 0.5: p must be a finite number >= 1"},
      {{"sobol", "-n", "0", "--dim", "2"}, "demsa: error: -n 0: the number of samples must be at least 1"},
      {{"sobol", "-n", "2000000000", "--dim", "2"},
       "demsa: error: -n 2000000000: the Sobol' sequence has at most 2^30 = 1073741824 points"},
      {{"sobol", "-n", "16", "--dim", "41"},
       "demsa: error: --dim 41: the Sobol' sequence supports at most 40 parameters"},
      {{"saltelli", "--base", "1", "--dim", "2"}, "demsa: error: --base 1: the base sample size must be at least 2"},
      {{"saltelli", "-N", "1", "--dim", "2"}, "demsa: error: --base 1: the base sample size must be at least 2"},
      // One cap with the study file's [analysis] base_samples, before anything is allocated.
      {{"saltelli", "--base", "1048577", "--dim", "2"}, "demsa: error: --base 1048577: at most 2^20 = 1048576"},
      // -n 200000000 --dim 2 held 10 GB.
      {{"lhs", "-n", "200000000", "--dim", "2"},
       "demsa: error: -n 200000000: 200000000 samples x --dim 2 = 400000000 values, more than 2^26 = 67108864"},
      {{"sobol", "-n", "67108864", "--dim", "2"}, "more than 2^26 = 67108864"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args{"design"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    args.insert(args.end(), {"-o", out});
    const CommandResult r = run_demsa(args);
    EXPECT_EQ(r.exit_code, 2) << c.message;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    for (const char* field : {"design samples", "time_limit", "phi_p_power", "saltelli base", "design dimension"})
      EXPECT_EQ(r.err.find(field), std::string::npos) << r.err;
  }
}

TEST(CliDesignErrors, DimensionZeroIsNotADimension) {
  TempDir dir;
  const std::string out = (dir / "x.csv").string();
  for (const std::string kind : {"lhs", "sobol", "saltelli"}) {
    const CommandResult r =
        run_demsa({"design", kind, kind == "saltelli" ? "-N" : "-n", "16", "--dim", "0", "-o", out});
    EXPECT_EQ(r.exit_code, 2) << kind;
    EXPECT_NE(r.err.find("--dim 0: not a valid dimension, the number of parameters must be at least 1"),
              std::string::npos)
        << r.err;
  }
  const CommandResult r = run_demsa({"design", "lhs", "-n", "16", "--dim", "0", "--param", "a:0:1", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("give either --dim or --param, not both"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(CliDesignErrors, MissingOrUnknownKindListsTheKinds) {
  CommandResult r = run_demsa({"design", "halton", "-n", "10"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("demsa: error: unknown design 'halton' (valid: lhs, sobol, saltelli)"), std::string::npos)
      << r.err;
  r = run_demsa({"design"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("demsa: error: give the kind of design: demsa design lhs|sobol|saltelli"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("A subcommand is required"), std::string::npos) << r.err;
  r = run_demsa({"design", "--help"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("saltelli"), std::string::npos) << r.out;
}

// The sequence is scrambled (random linear matrix scrambling and digital shift): its first point is not the origin.
TEST(CliDesign, SobolHelpDescribesTheScrambling) {
  const CommandResult r = run_demsa({"design", "sobol", "--help"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("origin"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("random linear matrix scrambling and digital shift"), std::string::npos) << r.out;
  TempDir dir;
  ASSERT_EQ(run_demsa({"design", "sobol", "-n", "8", "--dim", "3", "-o", (dir / "s.csv").string()}).exit_code, 0);
  const CsvTable t = read_csv(dir / "s.csv");
  EXPECT_GT(t.values.row(0).norm(), 0.0);
}

// A scrambled Sobol' sequence is balanced only at powers of two: other sizes are written, with a warning on standard
// error that names the value and the nearest powers of two; the JSON on standard output is unchanged.
TEST(CliDesign, SizesOtherThanPowersOfTwoWarnOnStandardError) {
  TempDir dir;
  const std::string out = (dir / "x.csv").string();
  CommandResult r = run_demsa({"design", "sobol", "-n", "10", "--dim", "2", "-o", out, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("demsa: warning: -n 10 is not a power of two (nearest: 8 and 16)"), std::string::npos) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["samples"], 10);
  EXPECT_EQ(read_csv(out).rows(), 10);

  r = run_demsa({"design", "saltelli", "--base", "100", "--dim", "2", "-o", out, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("demsa: warning: --base 100 is not a power of two: rounded up to 128"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("Saltelli 2010"), std::string::npos) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["base"], 128);
  EXPECT_EQ(read_csv(out).rows(), 512);

  r = run_demsa({"design", "sobol", "-n", "16", "--dim", "2", "-o", out, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  r = run_demsa({"design", "saltelli", "-N", "16", "--dim", "2", "-o", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  // Latin hypercubes have no such constraint.
  r = run_demsa({"design", "lhs", "-n", "10", "--dim", "2", "-o", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
}

// A Saltelli base that is not a power of two is rounded up to the next one (Sobol' points are balanced only there);
// the help says so.
TEST(CliDesign, SaltelliBaseIsRoundedUpToAPowerOfTwo) {
  TempDir dir;
  const std::string out = (dir / "x.csv").string();
  CommandResult r = run_demsa({"design", "saltelli", "-N", "10000", "--dim", "3", "-o", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("--base 10000 is not a power of two: rounded up to 16384"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("saltelli design: base 16384 x 3 parameters"), std::string::npos) << r.out;
  EXPECT_EQ(read_csv(out).rows(), 16384 * 5);
  r = run_demsa({"design", "saltelli", "--help"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("rounded up"), std::string::npos) << r.out;
}

// A missing output folder is the user's error, named, before any work (it was an I/O error, exit 3).
TEST(CliDesignErrors, MissingOutputFolderIsAUserError) {
  TempDir dir;
  const std::string out = (dir / "no" / "such" / "x.csv").string();
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"lhs", "-n", "8"}, {"sobol", "-n", "8"}, {"saltelli", "-N", "8"}}) {
    std::vector<std::string> full{"design"};
    full.insert(full.end(), args.begin(), args.end());
    full.insert(full.end(), {"--dim", "2", "-o", out});
    const CommandResult r = run_demsa(full);
    EXPECT_EQ(r.exit_code, 2) << args[0] << ": " << r.err;
    EXPECT_NE(
        r.err.find("demsa: error: -o " + out + ": the folder '" + (dir / "no" / "such").string() + "' does not exist"),
        std::string::npos)
        << r.err;
  }
}

// The metrics of block A are computed only for --json, in O(N) memory: at N = 2^15 the old n x n tables died with
// bad_alloc after the CSV was written. Above the pair-metric limit, phi_p and C2 are null and a warning says so.
TEST(CliDesign, SaltelliMetricsOnlyOnRequestAndBoundedAtLargeN) {
  TempDir dir;
  const std::string out = (dir / "x.csv").string();
  CommandResult r = run_demsa({"design", "saltelli", "-N", "32768", "--dim", "1", "-o", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  r = run_demsa({"design", "saltelli", "-N", "32768", "--dim", "1", "-o", out, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["metrics_of_a"]["phi_p"].is_null());
  EXPECT_TRUE(j["metrics_of_a"]["centred_l2_discrepancy"].is_null());
  // 2^15 points of a scrambled 1-D net: one per interval of 2^-15, so neighbours are at most 2^-14 apart.
  const double dmin = j["metrics_of_a"]["min_distance"].get<double>();
  EXPECT_GT(dmin, 0.0);
  EXPECT_LT(dmin, 1.0 / 16384);
  EXPECT_NE(r.err.find("phi_p and the centred L2 discrepancy are not computed for 32768 points"), std::string::npos)
      << r.err;
  EXPECT_EQ(read_csv(out).rows(), 32768 * 3);
}

// The optimisation budget is counted in iterations: the same seed gives the same design whatever the time cap (the
// cap was the budget, so the design depended on the machine's load). A cap that ends the search warns.
TEST(CliDesign, LhsSameSeedSameDesignWhateverTheTimeCap) {
  TempDir dir;
  std::vector<std::string> texts;
  for (const char* cap : {"5", "20"}) {
    const std::string out = (dir / (std::string("d") + cap + ".csv")).string();
    const CommandResult r = run_demsa({"design", "lhs", "-n", "30", "--dim", "3", "--criterion", "maximin", "--seed",
                                       "5", "--time-limit", cap, "-o", out, "--json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_NE(j["stop"], "time limit");
    texts.push_back(demsa::util::read_file(out));
  }
  EXPECT_EQ(texts[0], texts[1]);
  const CommandResult r = run_demsa({"design", "lhs", "-n", "200", "--dim", "5", "--criterion", "maximin",
                                     "--time-limit", "1e-9", "-o", (dir / "t.csv").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["stop"], "time limit");
  EXPECT_NE(r.err.find("demsa: warning: --time-limit 1e-09: the optimisation stopped at the safety time limit"),
            std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace demsa::test
