// A study with a tied parameter (`mu_pw = { same_as = "mu_pp" }`) through the real binary and the fake LIGGGHTS
// (tests/integration/fake_liggghts): run, analyze, calibrate on its own and together with a study that varies both,
// and the report's names.
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace demsa {
namespace {

namespace fs = std::filesystem;

std::string study_toml(const std::string& name, const std::string& parameters) {
  return test::StudyToml{
      .name = name,
      .seed = 7,
      .samples = 12,
      .parameters = parameters,
      .tables = "[pile]\nparticles = 300\n",
      .run = test::fake_liggghts_run_lines() + "parallel = 2\noversubscribe = true\n",
      .analysis = "metamodels = [\"rsm2\"]\nbootstrap = 0\nbase_samples = 512\nsecond_order = false\n"}
      .text();
}

const std::string k_tied =
    "mu_pp = { low = 0.2, high = 0.8 }\nmu_r_pp = { low = 0.05, high = 0.3 }\nmu_pw = { same_as = \"mu_pp\" }\n";
const std::string k_free = "mu_pp = { low = 0.2, high = 0.8 }\nmu_pw = { low = 0.3, high = 0.9 }\n";

TEST(TiedParametersFake, RunAnalyzeCalibrateAndReportTreatThePairAsOne) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study_toml("tied", k_tied));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const fs::path dir = tmp / "study";

  // The design: one column for the pair; every case: both values.
  const std::string design = test::read_file(dir / "design.csv");
  EXPECT_EQ(design.substr(0, design.find('\n')), "sample,u_mu_pp,u_mu_r_pp,mu_pp,mu_r_pp");
  for (const char* sample : {"000000", "000007"}) {
    const nlohmann::json c = nlohmann::json::parse(test::read_file(dir / "cases" / sample / "case.json"));
    EXPECT_DOUBLE_EQ(c.at("parameters").at("mu_pw").get<double>(), c.at("parameters").at("mu_pp").get<double>());
    const std::string params = test::read_file(dir / "cases" / sample / "params.liggghts");
    // The same number on both lines of params.liggghts, as written for mu_pp.
    const std::string key = "variable mu_pp                equal ";
    const std::size_t at = params.find(key);
    ASSERT_NE(at, std::string::npos) << params;
    const std::string value = params.substr(at + key.size(), params.find(' ', at + key.size()) - at - key.size());
    EXPECT_NE(params.find("variable mu_pw                equal " + value + " "), std::string::npos) << params;
  }

  // The analysis: metamodels and Sobol' indices over the two design parameters.
  const test::CommandResult analyze = test::run_demsa({"analyze", dir.string()});
  ASSERT_EQ(analyze.exit_code, 0) << analyze.out << analyze.err;
  const nlohmann::json analysis = nlohmann::json::parse(test::read_file(dir / "analysis" / "analysis.json"));
  EXPECT_EQ(analysis.at("parameters").get<std::vector<std::string>>(), (std::vector<std::string>{"mu_pp", "mu_r_pp"}));

  // Calibration of the study alone names the tie.
  const test::CommandResult calibrate = test::run_demsa({"calibrate", dir.string(), "--target", "angle=30"});
  ASSERT_EQ(calibrate.exit_code, 0) << calibrate.out << calibrate.err;
  EXPECT_NE(calibrate.out.find("mu_pw    = mu_pp (tied, same_as)"), std::string::npos) << calibrate.out;
  const nlohmann::json calibration = nlohmann::json::parse(test::read_file(dir / "analysis" / "calibration.json"));
  EXPECT_EQ(calibration.at("parameters").size(), 2U);
  EXPECT_EQ(calibration.at("ties").at(0).at("name"), "mu_pw");
  EXPECT_EQ(calibration.at("ties").at(0).at("same_as"), "mu_pp");

  // The report names the pair.
  const test::CommandResult report = test::run_demsa({"report", dir.string()});
  ASSERT_EQ(report.exit_code, 0) << report.out << report.err;
  const std::string md = test::read_file(dir / "report" / "report.md");
  EXPECT_NE(md.find("| mu_pp | μ_PP = μ_PW |"), std::string::npos) << md;
  EXPECT_NE(md.find("| mu_pw | μ_PP = μ_PW | same as mu_pp |"), std::string::npos) << md;
}

TEST(TiedParametersFake, ATiedStudyAndAFreeOneCalibrateTogetherOnThePartner) {
  test::TempDir a, b;
  test::write_file(a / "study.toml", study_toml("tied", k_tied));
  test::write_file(b / "study.toml", study_toml("free", k_free));
  {
    test::FakeLiggghtsEnvironment env("", a.path(), 0.0);
    ASSERT_EQ(test::run_demsa(test::run_args(a, {"--quiet"})).exit_code, 0);
  }
  {
    test::FakeLiggghtsEnvironment env("", b.path(), 0.0);
    ASSERT_EQ(test::run_demsa(test::run_args(b, {"--quiet"})).exit_code, 0);
  }
  const test::CommandResult joint =
      test::run_demsa({"calibrate", (a / "study").string(), (b / "study").string(), "--target", "tied:angle=30±1",
                       "--target", "free:angle=30±1", "--steps", "300", "--json", "--no-plots"});
  ASSERT_EQ(joint.exit_code == 0 || joint.exit_code == 1, true) << joint.out << joint.err;
  const nlohmann::json j = nlohmann::json::parse(joint.out);
  // mu_pw is tied in one study, so the free study's mu_pw is the joint mu_pp: two parameters, not three, and mu_pp's
  // prior is the intersection of [0.2, 0.8] (both studies' mu_pp) and [0.3, 0.9] (the free study's mu_pw).
  ASSERT_EQ(j.at("parameters").size(), 2U) << j.at("parameters").dump();
  const nlohmann::json& mu = j.at("parameters").at(0);
  EXPECT_EQ(mu.at("name"), "mu_pp");
  EXPECT_EQ(mu.at("tied").get<std::vector<std::string>>(), std::vector<std::string>{"mu_pw"});
  EXPECT_DOUBLE_EQ(mu.at("low").get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(mu.at("high").get<double>(), 0.8);
  EXPECT_EQ(j.at("parameters").at(1).at("name"), "mu_r_pp");

  // Ties that disagree between studies are refused, naming both.
  test::TempDir c;
  test::write_file(c / "study.toml",
                   study_toml("other", "mu_pw = { low = 0.2, high = 0.8 }\nmu_pp = { same_as = \"mu_pw\" }\n"));
  {
    test::FakeLiggghtsEnvironment env("", c.path(), 0.0);
    ASSERT_EQ(test::run_demsa(test::run_args(c, {"--quiet"})).exit_code, 0);
  }
  const test::CommandResult chained =
      test::run_demsa({"calibrate", (a / "study").string(), (c / "study").string(), "--target", "tied:angle=30±1",
                       "--target", "other:angle=30±1", "--steps", "300", "--no-plots"});
  EXPECT_EQ(chained.exit_code, 2) << chained.out << chained.err;
  EXPECT_NE(chained.err.find("parameter mu_pw: " + (a / "study").string() + " ties it to mu_pp, which " +
                             (c / "study").string() + " ties to mu_pw"),
            std::string::npos)
      << chained.err;
}

}  // namespace
}  // namespace demsa
