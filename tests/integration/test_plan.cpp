// `demsa plan` through the real binary, on synthetic studies whose answers are known: two observables that each
// leave two parameters on a ridge and pin both together, a parameter no observable depends on, and a linear-Gaussian
// posterior whose width halves with the sd.
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/store.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <functional>
#include <map>

using namespace demsa::study;

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

/// The study orders its parameters mu_pp, mu_pw, mu_r_pw: a = mu_pp, b = mu_pw, c = mu_r_pw (unit coordinates of the
/// study's ranges); c enters no observable.
const std::string k_ranges =
    "mu_pw = { low = 0.4, high = 1.9 }\nmu_r_pw = { low = 0.1, high = 0.5 }\nmu_pp = { low = 0.7, high = 1.9 }\n";

/// A pile study of 30 samples whose angle is `angle(u)`, each case recorded with `cpu` CPU seconds.
void write_study(const fs::path& dir, const std::string& name, unsigned seed,
                 const std::function<double(const std::vector<double>&)>& angle, double cpu = 0.0,
                 const std::string& metamodels = "[\"rsm1\"]") {
  SyntheticStudy study = start_synthetic_study(dir,
                                               StudyToml{.name = name,
                                                         .seed = 5,
                                                         .samples = 30,
                                                         .parameters = k_ranges,
                                                         .analysis = "metamodels = " + metamodels + "\n"}
                                                   .text(),
                                               seed);
  for (const SampleRow& row : study.samples) {
    RunOutcome done;
    done.exit_code = 0;
    done.cpu_seconds = cpu;
    study.store.record_done(study.store.add_run(row.sample, 1), done, {{"angle", angle(row.unit)}});
  }
}

nlohmann::json plan(const std::vector<std::string>& args) {
  std::vector<std::string> all{"plan"};
  all.insert(all.end(), args.begin(), args.end());
  all.push_back("--json");
  const CommandResult r = run_demsa(all);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out);
}

const nlohmann::json& subset(const nlohmann::json& j, const std::vector<std::string>& studies) {
  for (const nlohmann::json& s : j.at("subsets"))
    if (s.at("studies").get<std::vector<std::string>>() == studies) return s;
  throw std::runtime_error("no such subset");
}

double width(const nlohmann::json& s, int parameter) { return s.at("width").at(parameter).get<double>(); }

/// Two studies "sum" and "difference": y1 = a + b and y2 = a - b, in degrees, with 40 and 10 CPU-s a case.
void write_ridge_pair(const fs::path& dir) {
  write_study(
      dir / "sum", "sum", 11, [](const std::vector<double>& u) { return 20.0 + 5.0 * (u[0] + u[1]); }, 40.0);
  write_study(
      dir / "difference", "difference", 12, [](const std::vector<double>& u) { return 30.0 + 5.0 * (u[0] - u[1]); },
      10.0);
}

TEST(PlanCli, TwoObservablesThatEachLeaveARidgePinBothParametersTogether) {
  TempDir dir;
  // y1 = a + b and y2 = a - b, in degrees: each alone fixes one combination, together both.
  write_ridge_pair(dir.path());
  const nlohmann::json j = plan({(dir / "sum").string(), (dir / "difference").string(), "--sd", "sum:angle=0.25",
                                 "--sd", "difference:angle=0.25"});
  ASSERT_EQ(j.at("subsets").size(), 3u);
  const nlohmann::json& sum = subset(j, {"sum"});
  const nlohmann::json& difference = subset(j, {"difference"});
  const nlohmann::json& both = subset(j, {"sum", "difference"});
  for (const nlohmann::json* alone : {&sum, &difference}) {
    EXPECT_GT(width(*alone, 0), 0.4) << alone->dump();
    EXPECT_GT(width(*alone, 1), 0.4) << alone->dump();
  }
  // Together: a = (y1 + y2 - 50) / 10 has sd 0.25 / (5 √2), a 90 % width of 0.116; so has b.
  EXPECT_NEAR(width(both, 0), 0.116, 0.03) << both.dump();
  EXPECT_NEAR(width(both, 1), 0.116, 0.03) << both.dump();
  // c enters no observable: it keeps about 0.9 of its width in every subset and is not counted as sensitive.
  for (const nlohmann::json& s : j.at("subsets")) EXPECT_NEAR(width(s, 2), 0.9, 0.05) << s.dump();
  EXPECT_EQ(j.at("sensitive").get<std::vector<std::string>>(), (std::vector<std::string>{"mu_pp", "mu_pw"}));
  // The planner's own calibration: the truth falls outside its 90 % interval about 10 % of the time.
  for (const nlohmann::json& s : j.at("subsets")) {
    EXPECT_GE(s.at("outside_all").get<double>(), 0.05) << s.dump();
    EXPECT_LE(s.at("outside_all").get<double>(), 0.20) << s.dump();
  }
  // Cost: 30 samples at the median CPU per case of each study.
  EXPECT_DOUBLE_EQ(both.at("cpu_seconds").get<double>(), 30 * 40.0 + 30 * 10.0);
  // Only both together meet the goal: that is the recommendation.
  EXPECT_TRUE(both.at("meets_goal").get<bool>());
  EXPECT_FALSE(sum.at("meets_goal").get<bool>());
  EXPECT_EQ(j.at("subsets").at(j.at("recommended").get<int>()), both);
  EXPECT_NE(j.at("recommendation").get<std::string>().find("measure sum + difference"), std::string::npos)
      << j.at("recommendation");
  // plan.json, the figure, the printed table and the report section.
  EXPECT_TRUE(fs::exists(dir / "sum" / "plan" / "plan.json"));
  EXPECT_TRUE(fs::exists(dir / "sum" / "plan" / "plan_widths.png"));
  const CommandResult text = run_demsa({"plan", (dir / "sum").string(), (dir / "difference").string(), "--sd",
                                        "angle=0.25", "--truths", "10", "--no-plots"});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("sum + difference"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("<- recommended"), std::string::npos) << text.out;
  ASSERT_EQ(run_demsa({"report", (dir / "sum").string()}).exit_code, 0);
  EXPECT_NE(read_file(dir / "sum" / "report" / "report.md").find("Which experiments to run"), std::string::npos);
}

TEST(PlanCli, TruthsSideBySideGiveTheSamePlanAsOneAtATime) {
  TempDir dir;
  // Narrow posteriors (sd 0.1 on a 10-degree span), so that most subsets' truths are sampled beyond the prior sample
  // (adaptive importance sampling or the ensemble sampler), the part that runs on several threads.
  write_ridge_pair(dir.path());
  write_study(
      dir / "third", "third", 14, [](const std::vector<double>& u) { return 25.0 + 4.0 * u[2] + u[0]; }, 20.0);
  const std::vector<std::string> args{(dir / "sum").string(),
                                      (dir / "difference").string(),
                                      (dir / "third").string(),
                                      "--sd",
                                      "sum:angle=0.1",
                                      "--sd",
                                      "difference:angle=0.1",
                                      "--sd",
                                      "third:angle=0.1",
                                      "--truths",
                                      "8",
                                      "--no-plots"};
  std::vector<std::string> one = args, three = args;
  one.insert(one.end(), {"--threads", "1", "--out", (dir / "one").string()});
  three.insert(three.end(), {"--threads", "3", "--out", (dir / "three").string()});
  const nlohmann::json a = plan(one);
  const nlohmann::json b = plan(three);
  ASSERT_EQ(a.at("subsets").size(), 7u);
  int sampled = 0;
  for (const nlohmann::json& s : a.at("subsets")) sampled += s.at("adapted").get<int>() + s.at("sampled").get<int>();
  EXPECT_GT(sampled, 0) << "no truth needed more than the prior sample: the test would not see the threads";
  EXPECT_EQ(a.at("subsets"), b.at("subsets"));
  EXPECT_EQ(a.at("recommended"), b.at("recommended"));
}

TEST(PlanCli, HalvingTheSdHalvesALinearGaussianPosterior) {
  TempDir dir;
  write_study(dir / "line", "line", 13, [](const std::vector<double>& u) { return 20.0 + 10.0 * u[0]; });
  // Width of a: 2 · 1.645 · sd / 10 (where the interval stays inside the range): 0.066 at sd 0.2, 0.033 at 0.1.
  const double wide = width(plan({(dir / "line").string(), "--sd", "angle=0.2"}).at("subsets").at(0), 0);
  const double narrow = width(plan({(dir / "line").string(), "--sd", "angle=0.1"}).at("subsets").at(0), 0);
  EXPECT_NEAR(wide, 0.066, 0.008);
  EXPECT_NEAR(narrow / wide, 0.5, 0.05) << wide << " " << narrow;
}

/// The 90 % width of mu_pp over its prior width in `demsa calibrate` on both studies at a = b = 0.5, each measured
/// with sd `sd`.
double calibrated_width(const fs::path& dir, double sd) {
  const CommandResult r =
      run_demsa({"calibrate", (dir / "sum").string(), (dir / "difference").string(), "--target",
                 fmt::format("sum:angle=25±{}", sd), "--target", fmt::format("difference:angle=30±{}", sd), "--json",
                 "--no-plots", "--out", (dir / fmt::format("calibration-{}", sd)).string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out).at("parameters").at(0).at("width_ratio").get<double>();
}

TEST(PlanCli, AMorePreciseMeasurementNeverPlansWiderAndAgreesWithCalibrate) {
  // issue 45: the fallback sampler's fixed chain, started uniformly in the box, could not reach a narrow posterior:
  // below some sd its widths were its starting spread (0.03, 0.01, 0.36, 0.80, 0.84 over falling sds).
  TempDir dir;
  write_study(dir / "sum", "sum", 11, [](const std::vector<double>& u) { return 20.0 + 5.0 * (u[0] + u[1]); });
  write_study(dir / "difference", "difference", 12,
              [](const std::vector<double>& u) { return 30.0 + 5.0 * (u[0] - u[1]); });
  double previous = 1.0;
  for (const double sd : {0.3, 0.1, 0.03, 0.01, 0.003, 0.001}) {
    const nlohmann::json j =
        plan({(dir / "sum").string(), (dir / "difference").string(), "--sd", fmt::format("angle={}", sd), "--truths",
              "10", "--no-plots", "--out", (dir / fmt::format("plan-{}", sd)).string()});
    const nlohmann::json& both = subset(j, {"sum", "difference"});
    const double w = width(both, 0);
    // a = (y1 + y2 - 50) / 10: sd √2 sd / 10, a 90 % width of 0.465 sd (a little less where the range cuts it).
    EXPECT_LE(w, 0.465 * sd * 1.15) << "sd " << sd << ": " << both.dump();
    EXPECT_GE(w, 0.465 * sd * 0.7) << "sd " << sd << ": " << both.dump();
    EXPECT_LT(w, previous) << "sd " << sd;
    previous = w;
    EXPECT_TRUE(j.at("checks").at("passed").get<bool>()) << j.at("checks").dump();
    EXPECT_NEAR(w, calibrated_width(dir.path(), sd), 0.05) << "sd " << sd;
  }
}

TEST(PlanCli, OnAnInclineLikePairOfGpsTheWidthsShrinkWithTheSdAsCalibrateSays) {
  // issue 45's reproducer on the incline: each angle follows one friction coefficient (slide: atan μ_PW, roll: atan
  // μ_R,PW), fitted by GPs. Started uniformly in the box, the fallback's fixed chain planned 0.0008, 0.073, 0.40 for
  // μ_PW at sd 0.01°, 0.001°, 0.0002°: a more precise measurement planned wider, while calibrate pins it.
  TempDir dir;
  write_study(
      dir / "slide", "slide", 11, [](const std::vector<double>& u) { return std::atan(0.4 + 1.5 * u[1]) * 57.3; }, 0,
      "[\"gp\"]");
  write_study(
      dir / "roll", "roll", 12, [](const std::vector<double>& u) { return std::atan(0.1 + 0.4 * u[2]) * 57.3; }, 0,
      "[\"gp\"]");
  // The analytic width is 2 · 1.645 sd / (dy/du) at u = 0.5 (slide: 57.3 · 1.5 / (1 + 1.15²) = 37.0 °, roll: 57.3 ·
  // 0.4 / 1.09 = 21.0 °), widened by the GPs' own variance.
  const std::vector<double> slope{37.0, 21.0};
  std::vector<double> previous{1.0, 1.0}, previous_calibrated{1.0, 1.0};
  for (const double sd : {0.3, 0.1, 0.01, 0.001, 0.0002}) {
    SCOPED_TRACE(fmt::format("sd {}", sd));
    const nlohmann::json j =
        plan({(dir / "slide").string(), (dir / "roll").string(), "--sd", fmt::format("angle={}", sd), "--truths", "10",
              "--no-plots", "--out", (dir / fmt::format("plan-{}", sd)).string()});
    EXPECT_TRUE(j.at("checks").at("passed").get<bool>()) << j.at("checks").dump();
    const nlohmann::json& both = subset(j, {"slide", "roll"});
    for (int p : {1, 2}) {
      const double w = width(both, p);
      EXPECT_LT(w, previous[static_cast<size_t>(p - 1)]) << "parameter " << p << ": " << both.dump();
      previous[static_cast<size_t>(p - 1)] = w;
      const double analytic = 3.29 * sd / slope[static_cast<size_t>(p - 1)];
      EXPECT_GT(w, 0.5 * analytic) << "parameter " << p;
      EXPECT_LT(w, 3.0 * analytic) << "parameter " << p;
    }
    // `calibrate` at b = c = 0.5 (angles 48.99° and 16.70°), converged. At 0.0002° its own chain, started uniformly
    // in the box, did not reach the posterior either: it reported widths of 0.44 and 0.13, its walkers apart.
    const CommandResult r =
        run_demsa({"calibrate", (dir / "slide").string(), (dir / "roll").string(), "--target",
                   fmt::format("slide:angle=48.99±{}", sd), "--target", fmt::format("roll:angle=16.70±{}", sd),
                   "--json", "--no-plots", "--out", (dir / fmt::format("calibration-{}", sd)).string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json posterior = nlohmann::json::parse(r.out);
    EXPECT_TRUE(posterior.at("diagnostics").at("converged").get<bool>()) << posterior.at("diagnostics").dump();
    const nlohmann::json& calibrated = posterior.at("parameters");
    for (int p : {1, 2}) {
      const double w = calibrated.at(p).at("width_ratio").get<double>();
      EXPECT_NEAR(width(both, p), w, 0.05) << "parameter " << p;
      // Below 0.05 itself, the same bounds as the plan's: narrower with the sd, near the analytic width.
      EXPECT_LT(w, previous_calibrated[static_cast<size_t>(p - 1)]) << "parameter " << p;
      previous_calibrated[static_cast<size_t>(p - 1)] = w;
      const double analytic = 3.29 * sd / slope[static_cast<size_t>(p - 1)];
      EXPECT_GT(w, 0.5 * analytic) << "parameter " << p;
      EXPECT_LT(w, 3.0 * analytic) << "parameter " << p;
    }
  }
  // d(slide)/db = 57.3 · 1.5 / (1 + 1.15²) = 37.0 °: at sd 0.0002° a 90 % width of 9e-6, far below the 0.40 before.
  EXPECT_LT(previous[0], 1e-3);
}

TEST(PlanCli, NearAGuessedValueTheWidthsAreThoseAroundIt) {
  TempDir dir;
  write_study(dir / "line", "line", 13, [](const std::vector<double>& u) { return 20.0 + 10.0 * u[0]; });
  // sd 1: a 90 % interval of 0.33 of the range in the middle, cut by the range's end near a = 0.
  const auto width_near = [&](const std::string& near) {
    const nlohmann::json j = plan({(dir / "line").string(), "--sd", "angle=1", "--near", near});
    EXPECT_EQ(j.at("near").at(0).get<std::string>(), near);
    return width(j.at("subsets").at(0), 0);
  };
  const double middle = width_near("angle=25±0.2");
  const double edge = width_near("angle=20.2±0.2");
  EXPECT_NEAR(middle, 0.33, 0.03);
  EXPECT_LT(edge, middle - 0.06) << edge;
  // A value the study cannot produce is refused, not planned around.
  const CommandResult r = run_demsa({"plan", (dir / "line").string(), "--near", "angle=60±0.1"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--near angle=60±0.1: only 0 of 1000000 parameter points"), std::string::npos) << r.err;
}

TEST(PlanCli, TheDefaultSdIsTwoPercentOfTheMedianAndStatedAsSuch) {
  TempDir dir;
  write_study(dir / "line", "line", 13, [](const std::vector<double>& u) { return 20.0 + 10.0 * u[0]; });
  const nlohmann::json j = plan({(dir / "line").string(), "--truths", "5"});
  const nlohmann::json& o = j.at("observables").at(0);
  EXPECT_EQ(o.at("source").get<std::string>(), "default error (no replicates)");
  EXPECT_NEAR(o.at("sd").get<double>(), 0.02 * o.at("median").get<double>(), 1e-12);
  EXPECT_TRUE(o.at("noise_sd").is_null());
  // A goal no set reaches: the best there is, and what stays wide.
  const CommandResult r = run_demsa({"plan", (dir / "line").string(), "--truths", "5", "--goal", "0.01", "--no-plots"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("<- best there is"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("an experiment that follows mu_pp is missing"), std::string::npos) << r.out;
}

TEST(PlanCli, AStudyWithReplicatesAddsItsDemNoiseToTheDefaultSd) {
  TempDir dir;
  write_study(dir / "line", "line", 13, [](const std::vector<double>& u) { return 20.0 + 10.0 * u[0]; });
  // Points 1..4 twice more, 0.5° above and below their design value: pooled noise variance (0.5² + 0.5²) / 2.
  Store store((dir / "line" / "study.db").string());
  const std::vector<SampleRow> samples = store.samples();
  const std::map<int, std::map<std::string, double>> values = store.observables();
  std::vector<ReplicateRow> replicates;
  for (int k = 0; k < 4; ++k)
    for (int repeat = 1; repeat <= 2; ++repeat)
      replicates.push_back({replicate_sample_id(samples[k].sample, repeat), samples[k].sample, repeat,
                            static_cast<std::uint64_t>(100 + repeat), samples[k].unit, samples[k].physical});
  store.add_replicates(replicates);
  for (const ReplicateRow& r : replicates) {
    RunOutcome done;
    done.exit_code = 0;
    store.record_done(store.add_run(r.sample, 1), done,
                      {{"angle", values.at(r.point).at("angle") + (r.repeat == 1 ? 0.5 : -0.5)}});
  }
  const nlohmann::json j = plan({(dir / "line").string(), "--truths", "5"});
  const nlohmann::json& o = j.at("observables").at(0);
  EXPECT_EQ(o.at("source").get<std::string>(), "replicates + default error");
  EXPECT_NEAR(o.at("noise_sd").get<double>(), 0.5, 1e-9);
  const double measurement = 0.02 * o.at("median").get<double>();
  EXPECT_NEAR(o.at("sd").get<double>(), std::sqrt(0.25 + measurement * measurement), 1e-9);
}

TEST(PlanCli, AParameterLeftWideIsToldWhyFromItsMainEffect) {
  TempDir dir;
  // angle = 20 + 1.0 a + 0.5 b, sd 0.3: both sensitive (ST 0.8 and 0.2), both too weak for half their width. A
  // straight response spanning R sds leaves 2 · 1.645 / R of the width (at most 0.9, a flat posterior's), so half
  // needs 6.58; a spans 3.3 (an sd at least 2.0 times smaller, 3.9 times the packings), b 1.7 (3.9 times, 16 times).
  write_study(dir / "weak", "weak", 14, [](const std::vector<double>& u) { return 20.0 + 1.0 * u[0] + 0.5 * u[1]; });
  const nlohmann::json weak = plan({(dir / "weak").string(), "--sd", "angle=0.3", "--truths", "20"});
  const std::vector<double> range = weak.at("observables").at(0).at("main_effect_range").get<std::vector<double>>();
  ASSERT_EQ(range.size(), 3u);
  EXPECT_NEAR(range[0], 1.0, 0.01);
  EXPECT_NEAR(range[1], 0.5, 0.01);
  EXPECT_NEAR(range[2], 0.0, 0.01);
  const std::vector<std::string> reasons = weak.at("wide_reasons").get<std::vector<std::string>>();
  ASSERT_EQ(reasons.size(), 2u) << weak.dump();
  EXPECT_NE(reasons[0].find("mu_pp"), std::string::npos) << reasons[0];
  EXPECT_NE(reasons[0].find("on weak:angle, spans 3.3 of that observable's sd over its range; a straight response of "
                            "that size alone would leave 0.90 of its width; 0.5 of its width needs an sd at least 2 "
                            "times smaller (about 3.9 times the packings"),
            std::string::npos)
      << reasons[0];
  EXPECT_NE(reasons[1].find("spans 1.7 of that observable's sd"), std::string::npos) << reasons[1];
  EXPECT_NE(reasons[1].find("an sd at least 3.9 times smaller (about 16 times the packings"), std::string::npos)
      << reasons[1];
  for (const std::string& r : reasons) EXPECT_EQ(r.find("the rest is"), std::string::npos) << r;
  // y = a + b in one study, sd 0.25: each spans 20 sds, yet the ridge leaves both wide; more precision is not the cure.
  write_ridge_pair(dir.path());
  const nlohmann::json sum = plan({(dir / "sum").string(), "--sd", "angle=0.25", "--truths", "20"});
  const std::vector<std::string> ridge = sum.at("wide_reasons").get<std::vector<std::string>>();
  ASSERT_EQ(ridge.size(), 2u) << sum.dump();
  for (const std::string& r : ridge) {
    EXPECT_NE(r.find("spans 20 of that observable's sd over its range; a straight response of that size alone would "
                     "leave 0.16 of its width; the rest is where the effect lies in its range (a step, a curve) or "
                     "other parameters that make the same change"),
              std::string::npos)
        << r;
    EXPECT_EQ(r.find("needs an sd"), std::string::npos) << r;
  }
  // A set that meets the goal has no reasons, and the printed plan says them.
  EXPECT_TRUE(plan({(dir / "sum").string(), (dir / "difference").string(), "--sd", "angle=0.25", "--truths", "20"})
                  .at("wide_reasons")
                  .empty());
  const CommandResult text = run_demsa({"plan", (dir / "weak").string(), "--sd", "angle=0.3", "--truths", "10",
                                        "--no-plots", "--out", (dir / "weak-text").string()});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("why they stay wide:\n  mu_pp (0."), std::string::npos) << text.out;
  ASSERT_EQ(run_demsa({"report", (dir / "weak").string()}).exit_code, 0);
  const std::string report = read_file(dir / "weak" / "report" / "report.md");
  EXPECT_NE(report.find("Why they stay wide: mu_pp (0."), std::string::npos) << report;
}

TEST(PlanCli, BadOptionsAreRefusedNamingTheValue) {
  TempDir dir;
  write_study(dir / "line", "line", 13, [](const std::vector<double>& u) { return 20.0 + 10.0 * u[0]; });
  const std::string study = (dir / "line").string();
  const auto refused = [&](const std::vector<std::string>& args, const std::string& message) {
    std::vector<std::string> all{"plan", study};
    all.insert(all.end(), args.begin(), args.end());
    const CommandResult r = run_demsa(all);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  };
  refused({"--sd", "height=1"}, "--sd 'height=1': no measured observable is named so (measured: line:angle)");
  refused({"--sd", "angle=-1"}, "--sd 'angle=-1': '-1' must be a number > 0");
  refused({"--observe", "slide_angle"}, "--observe 'slide_angle': no study measures it");
  refused({"--truths", "1"}, "--truths 1: must be in 2..1000");
  refused({"--truths", "5000"}, "--truths 5000: must be in 2..1000");
  refused({"--threads", "-1"}, "--threads -1: must be in 0..256");
  refused({study}, "are the same study");
  // issue 45: an sd whose square overflows made every posterior the prior, silently; one sd given twice kept the
  // first without a word.
  refused({"--sd", "angle=1e200"}, "--sd 'angle=1e+200': 1e+200 squared overflows a double");
  refused({"--sd", "angle=1", "--sd", "angle=2"},
          "--sd 'angle=1' and --sd 'angle=2': the same observable's sd given twice");
  refused({"--sd", "angle=1", "--sd", "line:angle=2"},
          "--sd 'angle=1' and --sd 'line:angle=2' both give the sd of "
          "line:angle");
  // --out that cannot be a folder: refused before the work, not an internal error after it.
  write_file(dir / "a-file", "x\n");
  refused({"--out", (dir / "a-file").string()}, "--out " + (dir / "a-file").string() + ": exists and is not a folder");
}

TEST(PlanCli, TwoStudiesOfOneNameAreRefusedAndEveryStudyIsHeld) {
  TempDir dir;
  write_study(dir / "a", "same", 13, [](const std::vector<double>& u) { return 20.0 + 10.0 * u[0]; });
  write_study(dir / "b", "same", 14, [](const std::vector<double>& u) { return 20.0 + 10.0 * u[1]; });
  const CommandResult r = run_demsa({"plan", (dir / "a").string(), (dir / "b").string(), "--no-plots"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("share the name 'same'"), std::string::npos) << r.err;
  // issue 45: plan held only its first study; a `demsa run` extending the second meanwhile went unnoticed.
  write_study(dir / "c", "other", 15, [](const std::vector<double>& u) { return 20.0 + 10.0 * u[1]; });
  {
    const StudyLock held(dir / "c");  // this process stands for the `demsa run` that holds it
    const CommandResult held_run = run_demsa({"plan", (dir / "a").string(), (dir / "c").string(), "--no-plots"});
    EXPECT_EQ(held_run.exit_code, 2) << held_run.err;
    EXPECT_NE(held_run.err.find((dir / "c").string() + ": another demsa (pid "), std::string::npos) << held_run.err;
  }
  // A [study] name that STUDY:NAME cannot express is refused by the study file.
  for (const char* name : {"pile:wall", "a=b"}) {
    write_file(dir / "named.toml", StudyToml{.name = name, .samples = 4}.text());
    const CommandResult named =
        run_demsa({"run", (dir / "named.toml").string(), "--dir", (dir / "n").string(), "--dry-run"});
    EXPECT_EQ(named.exit_code, 2) << named.err;
    EXPECT_NE(named.err.find("[study] name: '" + std::string(name) + "' holds"), std::string::npos) << named.err;
  }
}

}  // namespace
}  // namespace demsa::test
