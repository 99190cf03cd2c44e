// A real LIGGGHTS run of a tiny incline (written by `demsa case`, run by hand with run.sh, measured by `demsa
// measure`): its free probes roll at tan θ = μ_R,PW (`cdt`) and its locked probes slide at tan θ = μ_PW, within a few
// tenths of a degree once the lag of their start is corrected (docs/explanation/experiments.md). A few seconds.
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>

namespace demsa {
namespace {

namespace fs = std::filesystem;

double atan_deg(double mu) { return std::atan(mu) * 180.0 / std::numbers::pi; }

TEST(InclineReal, ProbesRollAtTheRollingFrictionAndSlideAtTheWallFriction) {
  test::TempDir tmp;
  const fs::path dir = tmp / "case";
  const test::CommandResult w = test::run_demsa({"case", test::data_path("cases/tiny_incline.toml").string(), "--set",
                                                 "mu_pw=1.0,mu_r_pw=0.2", "-o", dir.string()});
  ASSERT_EQ(w.exit_code, 0) << w.out << w.err;
  const test::CommandResult r = test::run_command({(dir / "run.sh").string()}, tmp.path());
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err << test::read_file(dir / "screen.txt");
  const test::CommandResult m = test::run_demsa({"measure", dir.string(), "--json"});
  ASSERT_EQ(m.exit_code, 0) << m.out << m.err;
  const nlohmann::json j = nlohmann::json::parse(m.out)["observables"];
  EXPECT_NEAR(j["roll_angle"].get<double>(), atan_deg(0.2), 0.3) << m.out;
  EXPECT_NEAR(j["slide_angle"].get<double>(), atan_deg(1.0), 0.3) << m.out;
  EXPECT_EQ(j["probes_rolled"].get<double>(), 4);
  EXPECT_EQ(j["probes_slid"].get<double>(), 4);
  // Every probe left the plate down the slope and was removed, none lost.
  EXPECT_NE(test::read_file(dir / "incline_end.txt").find("removed 8"), std::string::npos)
      << test::read_file(dir / "incline_end.txt");
}

}  // namespace
}  // namespace demsa
