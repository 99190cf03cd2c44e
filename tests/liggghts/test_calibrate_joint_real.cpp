// A joint Bayesian calibration of a tiny pile study and a tiny oedometer study (real LIGGGHTS runs) that share
// mu_pp, verified with `--verify 2`: the MAP and two posterior draws run in both studies and are measured.
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

/// The tiny pile of test_report_real.cpp, on mu_pp and mu_r_pp.
const std::string k_pile =
    StudyToml{
        .name = "joint-pile",
        .seed = 31,
        .samples = 6,
        .parameters = "mu_pp = { low = 0.4, high = 0.9 }\nmu_r_pp = { low = 0.05, high = 0.4 }\n",
        .tables = "[pile]\nparticles = 200\nfill_height = 0.03\nsettle_time = 0.15\ndirections = 36\nlevels = 4\n",
        .run = "ranks = 1\n",
        .analysis = "metamodels = [\"rsm1\"]\nbootstrap = 0\nbase_samples = 512\n"}
        .text();

/// The mean of an observable over a study's analysis.
double mean_of(const fs::path& study, const std::string& name) {
  const nlohmann::json a = nlohmann::json::parse(read_file(study / "analysis" / "analysis.json"));
  for (const auto& o : a.at("observables"))
    if (o.at("name") == name) return o.at("mean").get<double>();
  ADD_FAILURE() << name << " not in " << study;
  return 0.0;
}

TEST(CalibrateJointReal, TinyPileAndOedometerWithVerify2) {
  TempDir dir;
  write_file(dir / "pile.toml", k_pile);
  // tests/data/cases/tiny_oedometer_trial.toml (E and mu_pp, 4 samples) with a linear RSM (3 terms).
  std::string oedometer = read_file(data_path("cases/tiny_oedometer_trial.toml"));
  oedometer += "\n[analysis]\nmetamodels = [\"rsm1\"]\nbootstrap = 0\nbase_samples = 512\n";
  write_file(dir / "oedometer.toml", oedometer);
  for (const char* s : {"pile", "oedometer"}) {
    const CommandResult run =
        run_demsa({"run", (dir / (std::string(s) + ".toml")).string(), "--dir", (dir / s).string(), "--quiet"});
    ASSERT_EQ(run.exit_code, 0) << s << run.out << run.err;
  }
  const double angle = mean_of(dir / "pile", "angle");
  const double settlement = mean_of(dir / "oedometer", "settlement_1");
  const CommandResult cal = run_demsa(
      {"calibrate", (dir / "pile").string(), (dir / "oedometer").string(), "--target",
       fmt::format("angle={:.6g}±2", angle), "--target",
       fmt::format("settlement_1={:.6g}±{:.6g}", settlement, 0.25 * std::abs(settlement)), "--verify", "2", "--json"});
  ASSERT_EQ(cal.exit_code, 0) << cal.out << cal.err;
  const nlohmann::json c = nlohmann::json::parse(cal.out);
  const nlohmann::json& mu = c.at("parameters").at(0);
  EXPECT_EQ(mu.at("name").get<std::string>(), "mu_pp");
  EXPECT_EQ(mu.at("low").get<double>(), 0.4);
  EXPECT_EQ(mu.at("high").get<double>(), 0.9);  // the intersection of [0.4, 0.9] and [0.4, 1.0]
  ASSERT_EQ(c.at("verification").size(), 3u);
  for (const nlohmann::json& v : c.at("verification")) {
    EXPECT_TRUE(v.at("errors").empty()) << v.dump();
    ASSERT_EQ(v.at("measured").size(), 2u) << v.dump();
    for (const nlohmann::json& m : v.at("measured")) EXPECT_TRUE(m.at("value").is_number()) << m.dump();
  }
  for (const char* png : {"posterior_marginals.png", "posterior_corner.png", "posterior_predictive.png"})
    EXPECT_TRUE(fs::exists(dir / "pile" / "calibration" / png)) << png;
  EXPECT_TRUE(fs::exists(dir / "pile" / "calibration" / "verify" / "map" / "joint-pile" / "pile_final.dump"));
}

}  // namespace
}  // namespace demsa::test
