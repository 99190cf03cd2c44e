// `demsa calibrate --method bayes` through the real binary: synthetic study folders (store written directly) for
// the posterior, its files and its errors; the fake LIGGGHTS for a joint pile + oedometer calibration with --verify.
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <vector>

using namespace demsa::study;

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

/// angle depends on mu_pw strongly and on mu_r_pw weakly (u coordinates of the study's own ranges).
double angle_of(double u1, double u2) { return 21.0 + 12.0 * u1 + 0.3 * u2; }

void write_pile(const fs::path& dir, const std::string& ranges, const std::string& name = "pile-synthetic",
                double (*angle)(double, double) = angle_of) {
  SyntheticStudy study = start_synthetic_study(
      dir,
      StudyToml{.name = name,
                .seed = 3,
                .samples = 30,
                .parameters = ranges,
                .analysis = "metamodels = [\"rsm2\", \"gp\"]\nbootstrap = 5\nbase_samples = 256\n"}
          .text(),
      2);
  record_every_sample_done(study, [&angle](const SampleRow& row) -> std::map<std::string, double> {
    return {{"angle", angle(row.unit[0], row.unit[1])}};
  });
}

/// An oedometer study over mu_pw only (its own range): settlement_k = k · (1 + u) mm.
void write_oedometer(const fs::path& dir, const std::string& ranges) {
  SyntheticStudy study =
      start_synthetic_study(dir,
                            StudyToml{.name = "oedometer-synthetic",
                                      .experiment = "oedometer",
                                      .seed = 4,
                                      .samples = 20,
                                      .parameters = ranges,
                                      .analysis = "metamodels = [\"rsm2\"]\nbootstrap = 5\nbase_samples = 256\n"}
                                .text(),
                            3);
  record_every_sample_done(study, [](const SampleRow& row) {
    std::map<std::string, double> v;
    for (int k = 1; k <= 3; ++k) v[fmt::format("settlement_{}", k)] = k * 1e-3 * (1.0 + row.unit[0]);
    return v;
  });
}

const std::string k_ranges = "mu_pw = { low = 0.4, high = 1.9 }\nmu_r_pw = { low = 0.1, high = 0.5 }\n";

TEST(CalibratePosteriorCli, ATargetWithAnUncertaintyGivesThePosteriorAndItsFiles) {
  TempDir dir;
  write_pile(dir / "study", k_ranges);
  // angle 30 ± 0.5 puts u1 near 0.75 (mu_pw = 1.525); mu_r_pw moves the angle by 0.3° over its range: free.
  const CommandResult r = run_demsa({"calibrate", (dir / "study").string(), "--target", "angle=30±0.5", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const nlohmann::json& mu = j.at("parameters").at(0);
  EXPECT_EQ(mu.at("name").get<std::string>(), "mu_pw");
  EXPECT_NEAR(mu.at("q50").get<double>(), 0.4 + 1.5 * 0.75, 0.03);
  EXPECT_LT(mu.at("width_ratio").get<double>(), 0.2);
  EXPECT_EQ(mu.at("identified").get<std::string>(), "yes");
  EXPECT_GT(j.at("parameters").at(1).at("width_ratio").get<double>(), 0.8);
  EXPECT_EQ(j.at("parameters").at(1).at("identified").get<std::string>(), "no");
  EXPECT_TRUE(j.at("diagnostics").at("converged").get<bool>()) << j.at("diagnostics").dump();
  const fs::path out = dir / "study" / "calibration";
  for (const char* f : {"posterior.json", "posterior_samples.csv", "posterior_marginals.png", "posterior_corner.png",
                        "posterior_predictive.png"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  // The report picks the posterior up.
  const CommandResult report = run_demsa({"report", (dir / "study").string()});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  EXPECT_NE(read_file(dir / "study" / "report" / "report.md").find("Posterior calibration"), std::string::npos);
}

TEST(CalibratePosteriorCli, ATargetTheStudyCannotProduceFailsTheCheckInsteadOfBeingIdentified) {
  TempDir dir;
  write_pile(dir / "study", k_ranges);
  // The study's angles span about 21 to 33°: 60 ± 0.5 pins the draws on the corner of the prior box.
  const CommandResult r = run_demsa(
      {"calibrate", (dir / "study").string(), "--target", "angle=60±0.5", "--steps", "300", "--json", "--no-plots"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(j.at("checks").at("passed").get<bool>());
  const nlohmann::json& t = j.at("targets").at(0);
  EXPECT_TRUE(t.at("contradicted").get<bool>());
  EXPECT_LT(t.at("tail_probability").get<double>(), 1e-3);
  EXPECT_LT(t.at("observed_high").get<double>(), 33.5);
  EXPECT_EQ(j.at("parameters").at(0).at("identified").get<std::string>(), "at bound");
  EXPECT_EQ(j.at("parameters").at(0).at("at_bound").get<std::string>(), "high");
  EXPECT_NE(r.err.find("check failed: angle = 60 ° ± 0.5"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("in study pile-synthetic, angle of repose spans "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("60 ° is above it: the measurement contradicts the study"), std::string::npos) << r.err;
  // The text says it too, and the report marks the posterior.
  const CommandResult text =
      run_demsa({"calibrate", (dir / "study").string(), "--target", "angle=60±0.5", "--steps", "300", "--no-plots"});
  EXPECT_EQ(text.exit_code, 1);
  EXPECT_NE(text.out.find("CHECK FAILED"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("CONTRADICTED"), std::string::npos) << text.out;
  ASSERT_EQ(run_demsa({"report", (dir / "study").string()}).exit_code, 0);
  EXPECT_NE(read_file(dir / "study" / "report" / "report.md").find("Check failed: the measurements contradict"),
            std::string::npos);
  // A target inside the study's range passes (with the automatic length: a chain of 300 steps has not converged).
  const CommandResult fine =
      run_demsa({"calibrate", (dir / "study").string(), "--target", "angle=30±0.5", "--json", "--no-plots"});
  EXPECT_EQ(fine.exit_code, 0) << fine.err;
  EXPECT_TRUE(nlohmann::json::parse(fine.out).at("checks").at("passed").get<bool>());
}

TEST(CalibratePosteriorCli, TextOutputPrintsTheTableAndAShortChainFailsTheCheckUnconverged) {
  TempDir dir;
  write_pile(dir / "study", k_ranges);
  const CommandResult r = run_demsa({"calibrate", (dir / "study").string(), "--target", "angle=30+-0.5", "--steps",
                                     "20", "--burn-in", "0", "--no-plots"});
  // Printed and written all the same, with the verdict; exit 1, as `demsa plan` with an unconverged truth (it was 0).
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.out.find("identified"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("UNCONVERGED: 20 steps per walker are fewer than 50 τ"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("raise the steps per walker"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("CHECK FAILED: the chain has not converged; this posterior is not an answer"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("correlations with |r| >= 0.3"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("check failed: UNCONVERGED: "), std::string::npos) << r.err;
  const nlohmann::json j = nlohmann::json::parse(read_file(dir / "study" / "calibration" / "posterior.json"));
  EXPECT_FALSE(j.at("checks").at("passed").get<bool>());
  EXPECT_EQ(j.at("checks").at("problems").at(0).get<std::string>().rfind("UNCONVERGED: ", 0), 0u) << j.dump();
  // The report says it too.
  ASSERT_EQ(run_demsa({"report", (dir / "study").string()}).exit_code, 0);
  EXPECT_NE(read_file(dir / "study" / "report" / "report.md").find("Check failed: the chain has not converged"),
            std::string::npos);
}

/// The angle on a circle's arc: a target of it leaves a thin curved ridge, which the stretch move crosses slowly.
double angle_on_arc(double u1, double u2) { return 21.0 + 12.0 * (u1 * u1 + u2 * u2); }

TEST(CalibratePosteriorCli, TheDefaultLengthGrowsUntilTheChainHoldsFiftyAutocorrelationTimes) {
  TempDir dir;
  write_pile(dir / "study", k_ranges, "pile-arc", angle_on_arc);
  const CommandResult r = run_demsa(
      {"calibrate", (dir / "study").string(), "--target", "angle=27±0.2", "--model", "rsm2", "--json", "--no-plots"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const auto runs = j.at("sampler").at("auto_steps").get<std::vector<int>>();
  ASSERT_GE(runs.size(), 2u) << j.at("sampler").dump();  // 3000 steps were not enough here
  EXPECT_EQ(runs.front(), 3000);
  EXPECT_EQ(runs.back(), j.at("sampler").at("steps").get<int>());
  double max_tau = 0.0;
  for (const auto& p : j.at("parameters")) max_tau = std::max(max_tau, p.at("tau").get<double>());
  EXPECT_GE(runs.back(), 50.0 * max_tau);
  EXPECT_TRUE(j.at("diagnostics").at("converged").get<bool>()) << j.at("diagnostics").dump();
  // A fixed length is kept as given, and the same target then reports the short chain: a failed check (exit 1).
  const CommandResult fixed = run_demsa({"calibrate", (dir / "study").string(), "--target", "angle=27±0.2", "--model",
                                         "rsm2", "--steps", "3000", "--json", "--no-plots"});
  ASSERT_EQ(fixed.exit_code, 1) << fixed.err;
  const nlohmann::json k = nlohmann::json::parse(fixed.out);
  EXPECT_EQ(k.at("sampler").at("steps").get<int>(), 3000);
  EXPECT_TRUE(k.at("sampler").at("auto_steps").empty());
  EXPECT_FALSE(k.at("diagnostics").at("converged").get<bool>()) << k.at("diagnostics").dump();
  EXPECT_FALSE(k.at("checks").at("passed").get<bool>()) << k.at("checks").dump();
}

TEST(CalibratePosteriorCli, TwoStudiesShareTheIntersectionOfTheirRanges) {
  TempDir dir;
  write_pile(dir / "pile", k_ranges);
  write_oedometer(dir / "oedometer", "mu_pw = { low = 1.0, high = 2.5 }\n");
  // settlement_k = k (1 + u) mm with u on [1.0, 2.5]: u = 0.3 is mu_pw = 1.45, which gives the angle 21 + 12·0.7.
  const CommandResult r =
      run_demsa({"calibrate", (dir / "pile").string(), (dir / "oedometer").string(), "--target", "angle=29.4±0.5",
                 "--target", "settlement=1.3e-3,2.6e-3,3.9e-3±0.05e-3", "--json", "--no-plots"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const nlohmann::json& mu = j.at("parameters").at(0);
  EXPECT_EQ(mu.at("low").get<double>(), 1.0);
  EXPECT_EQ(mu.at("high").get<double>(), 1.9);
  EXPECT_NEAR(mu.at("q50").get<double>(), 1.45, 0.03);
  ASSERT_EQ(j.at("targets").size(), 4u);
  EXPECT_EQ(j.at("targets").at(1).at("study").get<std::string>(), "oedometer-synthetic");
  EXPECT_EQ(j.at("studies").size(), 2u);
}

/// A second pile whose angle follows mu_r_pw instead (a rough base would follow the particle-particle parameters).
double angle_of_rolling(double u1, double u2) { return 25.0 + 0.3 * u1 + 10.0 * u2; }

TEST(CalibratePosteriorCli, TwoStudiesMeasuringOneNameTakeATargetEach) {
  TempDir dir;
  write_pile(dir / "wall", k_ranges, "pile-wall");
  write_pile(dir / "rough", k_ranges, "pile-rough", angle_of_rolling);
  const std::string wall = (dir / "wall").string(), rough = (dir / "rough").string();
  // A bare name both studies measure is refused, naming it and the studies.
  const CommandResult bare = run_demsa({"calibrate", wall, rough, "--target", "angle=30±0.5"});
  EXPECT_EQ(bare.exit_code, 2);
  EXPECT_NE(bare.err.find("--target angle: ambiguous: the studies pile-wall, pile-rough all measure 'angle'; say "
                          "which with --target STUDY:angle=..."),
            std::string::npos)
      << bare.err;
  const CommandResult unknown = run_demsa({"calibrate", wall, rough, "--target", "pile:angle=30±0.5"});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("--target pile:angle: no study is named 'pile' (the studies: pile-wall, pile-rough)"),
            std::string::npos)
      << unknown.err;
  const CommandResult twice =
      run_demsa({"calibrate", wall, rough, "--target", "pile-wall:angle=30±0.5", "--target", "pile-wall:angle=31±0.5"});
  EXPECT_EQ(twice.exit_code, 2);
  EXPECT_NE(twice.err.find("is given twice"), std::string::npos) << twice.err;
  // One target per study: angle 30 on the wall pins u1 = 0.75 (mu_pw 1.525), angle 30 on the rough base u2 = 0.5
  // (mu_r_pw 0.3); either alone leaves the other parameter free.
  const CommandResult r = run_demsa({"calibrate", wall, rough, "--target", "pile-wall:angle=29.1±0.3", "--target",
                                     "pile-rough:angle=30.2±0.3", "--json", "--no-plots"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.at("targets").size(), 2u);
  EXPECT_EQ(j.at("targets").at(0).at("name").get<std::string>(), "angle");
  EXPECT_EQ(j.at("targets").at(0).at("study").get<std::string>(), "pile-wall");
  EXPECT_EQ(j.at("targets").at(1).at("study").get<std::string>(), "pile-rough");
  // 29.1 = 21 + 12 u1 + 0.3 u2 and 30.2 = 25 + 0.3 u1 + 10 u2: u1 = 0.65, u2 = 0.5.
  EXPECT_NEAR(j.at("parameters").at(0).at("q50").get<double>(), 0.4 + 1.5 * 0.6625, 0.05);
  EXPECT_NEAR(j.at("parameters").at(1).at("q50").get<double>(), 0.1 + 0.4 * 0.5, 0.03);
}

TEST(CalibratePosteriorCli, AJointCalibrationNamesTheStudyThatCannotProduceItsTarget) {
  TempDir dir;
  write_pile(dir / "pile", k_ranges);
  write_oedometer(dir / "oedometer", "mu_pw = { low = 1.0, high = 2.5 }\n");
  const CommandResult r =
      run_demsa({"calibrate", (dir / "pile").string(), (dir / "oedometer").string(), "--target", "angle=60±0.5",
                 "--target", "settlement=1.3e-3,2.6e-3,3.9e-3±0.05e-3", "--steps", "300", "--json", "--no-plots"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(j.at("checks").at("passed").get<bool>());
  EXPECT_TRUE(j.at("targets").at(0).at("contradicted").get<bool>());
  EXPECT_NE(r.err.find("in study pile-synthetic, angle of repose spans"), std::string::npos) << r.err;
}

TEST(CalibratePosteriorCli, TheSameStudyTwiceIsRefusedNamingBothArguments) {
  TempDir dir;
  write_pile(dir / "study", k_ranges);
  const std::string same = (dir / "study").string();
  const std::string other_spelling = (dir / "study" / ".." / "study" / "").string();
  const CommandResult r = run_demsa({"calibrate", same, other_spelling, "--target", "angle=30±0.5"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("study folders '" + same + "' and '" + other_spelling + "' are the same study"),
            std::string::npos)
      << r.err;
}

TEST(CalibratePosteriorCli, SamplerSizesThatOverflowOrExceedMemoryNameTheOption) {
  TempDir dir;
  write_pile(dir / "study", k_ranges);
  const CommandResult burn = run_demsa({"calibrate", (dir / "study").string(), "--target", "angle=30±0.5", "--burn-in",
                                        "2147483548", "--steps", "100", "--no-plots"});
  EXPECT_EQ(burn.exit_code, 2) << burn.out;
  EXPECT_NE(burn.err.find("demsa: error: --burn-in 2147483548: 32 walkers"), std::string::npos) << burn.err;
  const CommandResult steps = run_demsa(
      {"calibrate", (dir / "study").string(), "--target", "angle=30±0.5", "--steps", "100000000", "--no-plots"});
  EXPECT_EQ(steps.exit_code, 2) << steps.out;
  EXPECT_NE(steps.err.find("demsa: error: --steps 100000000:"), std::string::npos) << steps.err;
  EXPECT_NE(steps.err.find("the sampler keeps in memory"), std::string::npos) << steps.err;
}

TEST(CalibratePosteriorCli, DisjointRangesNameTheParameterAndBothStudies) {
  TempDir dir;
  write_pile(dir / "pile", k_ranges);
  write_oedometer(dir / "oedometer", "mu_pw = { low = 2.0, high = 2.5 }\n");
  const CommandResult r =
      run_demsa({"calibrate", (dir / "pile").string(), (dir / "oedometer").string(), "--target", "angle=29±1"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("parameter mu_pw: the ranges [0.4, 1.9] of " + (dir / "pile").string() + " and [2, 2.5] of " +
                       (dir / "oedometer").string() + " do not overlap"),
            std::string::npos)
      << r.err;
}

TEST(CalibratePosteriorCli, BadTargetsNameTheOptionAndTheValue) {
  TempDir dir;
  write_pile(dir / "study", k_ranges);
  const std::vector<std::pair<std::string, std::string>> cases{
      {"angle=30±x", "--target 'angle=30±x': 'x' is not a number"},
      {"angle=30±", "--target 'angle=30±': no uncertainty after '±'"},
      {"angle=30±-1", "--target 'angle=30±-1': uncertainty -1 must be > 0"},
      {"angle=30±0", "--target 'angle=30±0': uncertainty 0 must be > 0 (the measurement's standard deviation"},
      {"angle=30+-0.0", "--target 'angle=30+-0.0': uncertainty 0 must be > 0"},
      {"settlement=1,2,3±1,2", "--target 'settlement=1,2,3±1,2': 2 uncertainties for 3 values"},
      {"slope=3±1", "--target slope: no study has this observable"}};
  for (const auto& [target, message] : cases) {
    const CommandResult r = run_demsa({"calibrate", (dir / "study").string(), "--target", target});
    EXPECT_EQ(r.exit_code, 2) << target;
    EXPECT_NE(r.err.find(message), std::string::npos) << target << ": " << r.err;
  }
  const CommandResult optimize_two =
      run_demsa({"calibrate", (dir / "study").string(), (dir / "study").string(), "--method", "optimize"});
  EXPECT_EQ(optimize_two.exit_code, 2);
  EXPECT_NE(optimize_two.err.find("--method optimize: one study folder"), std::string::npos) << optimize_two.err;
}

TEST(CalibratePosteriorCli, AMetamodelWhoseErrorCannotBeMeasuredIsRefused) {
  // issue 45: a study with half its cases failed left rsm2 (6 terms in 2 parameters) fitted on 6 samples: its
  // leave-one-out Q² was NaN, its error taken as 0, and calibrate said "converged, identified" with intervals that
  // excluded the truth.
  TempDir dir;
  SyntheticStudy study = start_synthetic_study(dir / "study",
                                               StudyToml{.name = "half-failed",
                                                         .seed = 3,
                                                         .samples = 12,
                                                         .parameters = k_ranges,
                                                         .analysis = "metamodels = [\"rsm2\"]\n"}
                                                   .text(),
                                               2);
  for (size_t i = 0; i < 6; ++i) {  // the other 6 samples have no done run
    const SampleRow& row = study.samples[i];
    RunOutcome done;
    done.exit_code = 0;
    study.store.record_done(study.store.add_run(row.sample, 1), done,
                            {{"angle", 20.0 + 10.0 * row.unit[0] + 3.0 * row.unit[1] * row.unit[1]}});
  }
  const std::string folder = (dir / "study").string();
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"calibrate", folder, "--target", "angle=27±0.5", "--no-plots"},
        std::vector<std::string>{"calibrate", folder, "--target", "angle=27", "--method", "optimize"},
        std::vector<std::string>{"plan", folder, "--no-plots"}}) {
    const CommandResult r = run_demsa(args);
    EXPECT_EQ(r.exit_code, 2) << args[0] << ": " << r.out << r.err;
    EXPECT_NE(r.err.find("no metamodel of angle whose error can be measured"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("rsm2: leave-one-out Q² is not finite on 6 samples"), std::string::npos) << r.err;
  }
  EXPECT_NE(run_demsa({"plan", folder, "--no-plots"}).err.find("(--model rsm1)"), std::string::npos);
  // With a metamodel of fewer terms (rsm1: 3) the error is measured and the calibration runs.
  const CommandResult rsm1 =
      run_demsa({"calibrate", folder, "--target", "angle=27±0.5", "--model", "rsm1", "--no-plots", "--steps", "500"});
  EXPECT_NE(rsm1.exit_code, 2) << rsm1.err;
  // On as many samples as rsm1's terms, the advice is to run more cases, not to name rsm1 again.
  SyntheticStudy three = start_synthetic_study(
      dir / "three",
      StudyToml{
          .name = "three", .seed = 3, .samples = 12, .parameters = k_ranges, .analysis = "metamodels = [\"rsm1\"]\n"}
          .text(),
      2);
  for (size_t i = 0; i < 3; ++i) {
    RunOutcome done;
    done.exit_code = 0;
    three.store.record_done(three.store.add_run(three.samples[i].sample, 1), done,
                            {{"angle", 20.0 + 10.0 * three.samples[i].unit[0]}});
  }
  const CommandResult r = run_demsa({"plan", (dir / "three").string(), "--no-plots"});
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find("rsm1: leave-one-out Q² is not finite on 3 samples"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("run more cases of the study"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("--model rsm1"), std::string::npos) << r.err;
}

TEST(CalibratePosteriorCli, AMeasuredCurveFromACsvFile) {
  TempDir dir;
  write_oedometer(dir / "oedometer", "mu_pw = { low = 1.0, high = 2.5 }\n");
  // Six tests with min/max bars: σ = (high - low) / d₂(6).
  write_file(dir / "curve.csv",
             "mean,low,high,tests\n1.3e-3,1.2e-3,1.4e-3,6\n2.6e-3,2.4e-3,2.8e-3,6\n"
             "3.9e-3,3.7e-3,4.1e-3,6\n");
  const CommandResult r = run_demsa({"calibrate", (dir / "oedometer").string(), "--target-file",
                                     "settlement=" + (dir / "curve.csv").string(), "--json", "--no-plots"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.at("targets").size(), 3u);
  EXPECT_NEAR(j.at("targets").at(0).at("sd").get<double>(), 0.2e-3 / 2.534, 1e-9);
  EXPECT_EQ(j.at("targets").at(2).at("name").get<std::string>(), "settlement_3");
  EXPECT_NEAR(j.at("parameters").at(0).at("q50").get<double>(), 1.45, 0.05);
  write_file(dir / "bad.csv", "mean,low\n1.3e-3,1.2e-3\n");
  const CommandResult bad = run_demsa(
      {"calibrate", (dir / "oedometer").string(), "--target-file", "settlement=" + (dir / "bad.csv").string()});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("bad.csv: needs a column 'sd', or the columns 'low', 'high' and 'tests'"), std::string::npos)
      << bad.err;
  write_file(dir / "exact.csv", "mean,sd\n1.3e-3,0\n");
  const CommandResult exact = run_demsa(
      {"calibrate", (dir / "oedometer").string(), "--target-file", "settlement=" + (dir / "exact.csv").string()});
  EXPECT_EQ(exact.exit_code, 2);
  EXPECT_NE(exact.err.find("exact.csv:2: column 'sd': 0 must be > 0"), std::string::npos) << exact.err;
}

TEST(CalibratePosteriorCli, JointFakeRunsVerifyTheMapAndDrawsAndResume) {
  TempDir tmp;
  const std::string ranges = "mu_pp = { low = 0.3, high = 0.9 }\n";
  write_file(tmp / "pile.toml", StudyToml{.name = "fake-pile",
                                          .samples = 6,
                                          .parameters = ranges + "mu_r_pp = { low = 0.05, high = 0.3 }\n",
                                          .tables = "[pile]\nparticles = 300\n",
                                          .run = fake_liggghts_run_lines(),
                                          .analysis = "metamodels = [\"rsm1\"]\nbootstrap = 0\n"}
                                    .text());
  write_file(tmp / "oedometer.toml", StudyToml{.name = "fake-oedometer",
                                               .experiment = "oedometer",
                                               .samples = 6,
                                               .parameters = "mu_pp = { low = 0.2, high = 0.8 }\n",
                                               .tables = "[oedometer]\nparticles = 200\n",
                                               .run = fake_liggghts_run_lines(),
                                               .analysis = "metamodels = [\"rsm1\"]\nbootstrap = 0\n"}
                                         .text());
  FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  for (const char* s : {"pile", "oedometer"}) {
    const CommandResult run = run_demsa(
        {"run", (tmp / (std::string(s) + ".toml")).string(), "--dir", (tmp / s).string(), "--no-analyze", "--quiet"});
    ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  }
  const Store pile = Store::open_read_only((tmp / "pile" / "study.db").string());
  const Store oedometer = Store::open_read_only((tmp / "oedometer" / "study.db").string());
  const double angle = pile.observables().begin()->second.at("angle");
  const double s1 = oedometer.observables().begin()->second.at("settlement_1");
  const std::vector<std::string> args{"calibrate",
                                      (tmp / "pile").string(),
                                      (tmp / "oedometer").string(),
                                      "--target",
                                      fmt::format("angle={:.6g}±2", angle),
                                      "--target",
                                      fmt::format("settlement_1={:.6g}±{:.3g}", s1, 0.2 * std::abs(s1) + 1e-6),
                                      "--steps",
                                      "200",
                                      "--verify",
                                      "2",
                                      "--json",
                                      "--no-plots"};
  // 200 steps have not converged: a failed check (exit 1), and the verification is run and written all the same.
  const CommandResult r = run_demsa(args);
  ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.at("checks").at("problems").size(), 1u) << j.at("checks").dump();
  EXPECT_EQ(j.at("checks").at("problems").at(0).get<std::string>().rfind("UNCONVERGED: ", 0), 0u);
  ASSERT_EQ(j.at("verification").size(), 3u);
  EXPECT_EQ(j.at("verification").at(0).at("label").get<std::string>(), "map");
  for (const nlohmann::json& v : j.at("verification")) {
    EXPECT_TRUE(v.at("errors").empty()) << v.dump();
    ASSERT_EQ(v.at("measured").size(), 2u) << v.dump();
    for (const nlohmann::json& m : v.at("measured")) {
      EXPECT_TRUE(m.at("value").is_number()) << m.dump();
      EXPECT_LT(m.at("low").get<double>(), m.at("high").get<double>());
    }
  }
  const fs::path out = tmp / "pile" / "calibration" / "verify";
  EXPECT_TRUE(fs::exists(out / "map" / "fake-pile.json"));
  EXPECT_TRUE(fs::exists(out / "draw-2" / "fake-oedometer.json"));
  // A second call measures nothing again: every point is read back from its record.
  const std::string starts = read_file(tmp / "starts.log");
  const CommandResult again = run_demsa(args);
  ASSERT_EQ(again.exit_code, 1) << again.err;
  EXPECT_EQ(read_file(tmp / "starts.log"), starts);
  EXPECT_EQ(nlohmann::json::parse(again.out).at("verification"), j.at("verification"));
}

}  // namespace
}  // namespace demsa::test
