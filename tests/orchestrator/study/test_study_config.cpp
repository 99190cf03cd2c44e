// The study file parser: values, defaults, presets, and a message naming file, line and value for every mistake.
#include "orchestrator/experiments/oedometer/oedometer.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <string>

namespace demsa {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::experiments;
namespace {

const char* k_minimal = R"(
[study]
name = "s"
experiment = "pile"

[parameters]
mu_r_pp = { low = 0.45, high = 4.5 }
E = { low = 1e8, high = 1e9, scale = "log" }
)";

std::string error_of(const std::string& text) {
  return test::message_of<UserError>([&] { parse_study(text, "study.toml"); });
}

TEST(StudyConfig, MinimalFileTakesDefaultsAndPaperOrder) {
  const StudyConfig c = parse_study(k_minimal, "dir/study.toml");
  EXPECT_EQ(c.name, "s");
  EXPECT_EQ(c.experiment, "pile");
  ASSERT_EQ(c.parameters.size(), 2u);
  EXPECT_EQ(c.parameters[0].name, "E");  // paper eq. (1) order, not file order
  EXPECT_EQ(c.parameters[1].name, "mu_r_pp");
  EXPECT_EQ(c.parameters[0].bounds.scale, sobol::Scale::log_uniform);
  EXPECT_DOUBLE_EQ(c.parameters[1].bounds.high, 4.5);
  EXPECT_EQ(c.parameters[1].line, 7);
  EXPECT_DOUBLE_EQ(c.timestep.fraction, 0.15);
  EXPECT_DOUBLE_EQ(pile::settings(c).settle_time, 0.6);
  EXPECT_EQ(oedometer::settings(c).trial_steps, 15000);
  EXPECT_EQ(oedometer::settings(c).relax_steps, 80000);
  EXPECT_DOUBLE_EQ(oedometer::settings(c).trial_step0, 0.0075e-3);
}

TEST(StudyConfig, PilePresetsFillTable2AndExplicitKeysOverride) {
  StudyConfig c = parse_study(std::string(k_minimal) + "[pile]\npreset = \"set2\"\n", "study.toml");
  EXPECT_EQ(pile::settings(c).particles, 8000);
  EXPECT_DOUBLE_EQ(pile::settings(c).radii.r_min, 0.8e-3);
  EXPECT_DOUBLE_EQ(pile::settings(c).radii.r_max, 2.5e-3);
  EXPECT_DOUBLE_EQ(pile::settings(c).radii.mean, 1.5e-3);
  EXPECT_DOUBLE_EQ(pile::settings(c).radii.sd, 0.35e-3);
  c = parse_study(std::string(k_minimal) + "[pile]\nparticles = 300\npreset = \"set1\"\n", "study.toml");
  EXPECT_EQ(pile::settings(c).particles, 300);
  EXPECT_DOUBLE_EQ(pile::settings(c).radii.r_max, 3.5e-3);
}

TEST(StudyConfig, OedometerSectionIsRead) {
  std::string oedometer = k_minimal;
  oedometer.replace(oedometer.find("\"pile\""), 6, "\"oedometer\"");
  const StudyConfig c = parse_study(oedometer + R"(
[oedometer]
preset = "paper"
loads = [100, 400.0, 1100, 2700]
measured_settlements = [1e-3, 2e-3, 3e-3]
plate_mode = "trial-step"
trial_steps = 100
)",
                                    "study.toml");
  EXPECT_EQ(oedometer::settings(c).particles, 4642);
  EXPECT_EQ(oedometer::settings(c).plate_mode, oedometer::PlateMode::trial_step);
  ASSERT_EQ(oedometer::settings(c).loads.size(), 4u);
  EXPECT_DOUBLE_EQ(oedometer::settings(c).loads[2], 1100.0);
  EXPECT_EQ(oedometer::settings(c).trial_steps, 100);
}

TEST(StudyConfig, UnknownKeyNamesLineAndValidKeys) {
  const std::string e = error_of(std::string(k_minimal) + "[pile]\nparticles = 10\nsettle = 0.5\n");
  EXPECT_NE(e.find("study.toml:11: unknown key 'settle' in [pile]"), std::string::npos) << e;
  EXPECT_NE(e.find("settle_time"), std::string::npos) << e;
}

TEST(StudyConfig, UnknownSectionIsRefused) {
  const std::string e = error_of(std::string(k_minimal) + "[piles]\nparticles = 10\n");
  EXPECT_NE(e.find("study.toml:9: unknown section [piles]"), std::string::npos) << e;
}

TEST(StudyConfig, WrongTypeNamesTheValue) {
  const std::string e = error_of(std::string(k_minimal) + "[pile]\nparticles = \"many\"\n");
  EXPECT_NE(e.find("study.toml:10: [pile] particles: expected an integer, got the string \"many\""), std::string::npos)
      << e;
}

TEST(StudyConfig, ImpossibleValuesAreRefused) {
  EXPECT_NE(error_of(std::string(k_minimal) + "[material]\nnu = 0.5\n")
                .find("study.toml:10: [material] nu: must lie "
                      "in (0, 0.5), got 0.5"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(k_minimal) + "[timestep]\nfraction = 0.4\n").find("must lie in [1e-06, 0.3], got 0.4"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(k_minimal) + "[oedometer]\nloads = [400, 100]\n").find("loads must increase"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(k_minimal) + "[pile]\nr_min = 4e-3\n").find("r_min (0.004) must be less than r_max"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(k_minimal) + "[oedometer]\nplate_mode = \"hydraulic\"\n")
                .find("unknown value 'hydraulic' (valid: servo, trial-step)"),
            std::string::npos);
}

TEST(StudyConfig, GpSettingsOfTheAnalysis) {
  const StudyConfig c = parse_study(
      std::string(k_minimal) + "[analysis]\ngp_kernel = \"matern52\"\ngp_trend = \"linear\"\ngp_nugget = true\n",
      "study.toml");
  const sobol::MetamodelOptions o = c.analysis.metamodel_options();
  EXPECT_EQ(o.gp.kernel, sobol::GpKernel::matern52);
  EXPECT_EQ(o.gp.trend, sobol::GpTrend::linear);
  EXPECT_TRUE(o.gp.nugget);
  const sobol::MetamodelOptions d = parse_study(k_minimal, "study.toml").analysis.metamodel_options();
  EXPECT_EQ(d.gp.kernel, sobol::GpKernel::squared_exponential);
  EXPECT_FALSE(d.gp.nugget);
  EXPECT_NE(error_of(std::string(k_minimal) + "[analysis]\ngp_kernel = \"rbf\"\n")
                .find("study.toml:10: [analysis] gp_kernel: unknown GP kernel 'rbf' (valid: squared-exponential, "
                      "matern52)"),
            std::string::npos)
      << error_of(std::string(k_minimal) + "[analysis]\ngp_kernel = \"rbf\"\n");
}

TEST(StudyConfig, ParameterRangesAreChecked) {
  const std::string base = "[study]\nname = \"s\"\nexperiment = \"pile\"\n[parameters]\n";
  EXPECT_NE(error_of(base + "E = { low = 1e9, high = 1e8 }\n").find("study.toml:5: [parameters] E:"),
            std::string::npos);
  EXPECT_NE(error_of(base + "nu = { low = 0.2, high = 0.6 }\n").find("must lie in (0, 0.5)"), std::string::npos);
  EXPECT_NE(error_of(base + "E = { low = 1e8 }\n").find("needs both 'low' and 'high'"), std::string::npos);
  EXPECT_NE(error_of(base + "E = { low = 1e8, high = 2e8, scale = \"cubic\" }\n").find("unknown scale 'cubic'"),
            std::string::npos);
  EXPECT_NE(error_of(base + "young = { low = 1e8, high = 2e8 }\n").find("unknown key 'young' in [parameters]"),
            std::string::npos);
}

TEST(StudyConfig, YoungModulusOutsideLiggghtsLimitsNeedsTheFlag) {
  const std::string base =
      "[study]\nname = \"s\"\nexperiment = \"pile\"\n[parameters]\nmu_pp = { low = 0.5, high = 1 }\n";
  // Above 1e9 Pa: refused at the line of the E entry, naming the bound and the flag.
  const std::string hard = error_of(base + "E = { low = 1e8, high = 2e9, scale = \"log\" }\n");
  EXPECT_NE(hard.find("study.toml:6: [parameters] E: range [1e+08, 2e+09] Pa reaches above 1e+09 Pa, which LIGGGHTS "
                      "refuses in SI units: set [material] hard_particles = true"),
            std::string::npos)
      << hard;
  // Below 5e6 Pa.
  const std::string soft = error_of(base + "E = { low = 1e6, high = 1e8 }\n");
  EXPECT_NE(soft.find("study.toml:6: [parameters] E: range [1e+06, 1e+08] Pa reaches below 5e+06 Pa"),
            std::string::npos)
      << soft;
  EXPECT_NE(soft.find("set [material] soft_particles = true"), std::string::npos) << soft;
  // The bounds themselves pass; the flags allow the rest, wherever [material] stands in the file.
  EXPECT_NO_THROW(parse_study(base + "E = { low = 5e6, high = 1e9 }\n", "study.toml"));
  EXPECT_NO_THROW(
      parse_study("[material]\nhard_particles = true\n" + base + "E = { low = 1e8, high = 2e9 }\n", "study.toml"));
  EXPECT_NO_THROW(
      parse_study(base + "E = { low = 1e6, high = 1e8 }\n[material]\nsoft_particles = true\n", "study.toml"));
  // A fixed E outside the limits, at the line of [material] E.
  const std::string fixed = error_of(base + "[material]\nnu = 0.3\nE = 3e9\n");
  EXPECT_NE(fixed.find("study.toml:8: [material] E: 3e+09 Pa reaches above 1e+09 Pa"), std::string::npos) << fixed;
  // Varied E: the fixed [material] E is not used, so it is not checked.
  EXPECT_NO_THROW(parse_study(base + "E = { low = 1e8, high = 1e9 }\n[material]\nE = 3e9\n", "study.toml"));
}

TEST(StudyConfig, MissingRequiredParts) {
  EXPECT_NE(error_of("[study]\nname = \"s\"\n").find("experiment is required"), std::string::npos);
  EXPECT_NE(error_of("[study]\nname = \"s\"\nexperiment = \"pile\"\n").find("[parameters] must vary"),
            std::string::npos);
}

TEST(StudyConfig, TomlSyntaxErrorHasLine) {
  const std::string e = error_of(std::string(k_minimal) + "[pile\n");
  EXPECT_EQ(e.rfind("study.toml:9:", 0), 0u) << e;
}

TEST(StudyConfig, DesignHashIgnoresRunAndAnalysisButNotPhysics) {
  const StudyConfig a = parse_study(k_minimal, "study.toml");
  const StudyConfig b =
      parse_study(std::string(k_minimal) + "[run]\nparallel = 2\n[analysis]\nbootstrap = 5\n", "study.toml");
  const StudyConfig c = parse_study(std::string(k_minimal) + "[material]\ndensity = 2600\n", "study.toml");
  EXPECT_EQ(design_hash(a), design_hash(b));
  EXPECT_NE(design_hash(a), design_hash(c));
  EXPECT_EQ(design_hash(a).size(), 16u);
}

TEST(StudyConfig, MaterialForSetsTheVariedParameters) {
  const StudyConfig c = parse_study(k_minimal, "study.toml");
  const Material m = material_for(c, {3e8, 2.0});
  EXPECT_DOUBLE_EQ(m.E, 3e8);
  EXPECT_DOUBLE_EQ(m.mu_r_pp, 2.0);
  EXPECT_DOUBLE_EQ(m.nu, c.material.nu);
}

TEST(StudyConfig, LoadStudyReportsMissingFile) { EXPECT_THROW(load_study("/nonexistent/study.toml"), UserError); }

}  // namespace
}  // namespace demsa
