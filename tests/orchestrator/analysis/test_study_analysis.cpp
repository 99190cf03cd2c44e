// The study analysis (orchestrator/analysis/study_analysis.hpp) on synthetic studies: a constant observable is an
// error of its own while the others are analysed, a metamodel whose Q² is not computable gives no index, an analysis
// in which nothing could be analysed says why, and a stop request ends it before any file is written.
#include "orchestrator/analysis/analysis_json.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/study/store.hpp"
#include "sobol/stop.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

using namespace demsa::study;
using namespace demsa::analysis;

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

/// DIR/study.toml and DIR/study.db with `samples` (20) done samples whose angle and pile height are the given
/// functions.
void write_study(const fs::path& dir, const std::function<double(double, double)>& angle,
                 const std::function<double(double, double)>& height, const std::string& analysis = "",
                 int samples = 20) {
  StudyToml toml{.name = "synthetic", .seed = 7, .samples = samples};
  if (!analysis.empty()) toml.analysis = analysis;
  SyntheticStudy study = start_synthetic_study(dir, toml.text(), 5);
  for (const SampleRow& row : study.samples) {
    const long run = study.store.add_run(row.sample, 1);
    RunOutcome outcome;
    outcome.exit_code = 0;
    study.store.record_done(
        run, outcome, {{"angle", angle(row.unit[0], row.unit[1])}, {"pile_height", height(row.unit[0], row.unit[1])}});
  }
}

const ObservableAnalysis& observable(const AnalysisSummary& s, const std::string& name) {
  for (const ObservableAnalysis& o : s.observables)
    if (o.name == name) return o;
  throw std::runtime_error("no observable " + name);
}

TEST(StudyAnalysis, ABaseThatIsNotAPowerOfTwoIsRoundedUpWithAWarningNamingTheField) {
  std::vector<std::string> warnings;
  const auto warn = [&warnings](const std::string& w) { warnings.push_back(w); };
  EXPECT_EQ(balanced_base_samples(1024, "AnalyzeOptions.base_samples", warn), 1024);
  EXPECT_EQ(balanced_base_samples(-1, "AnalyzeOptions.base_samples", warn), -1);  // the study's value
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(balanced_base_samples(10000, "AnalyzeOptions.base_samples", warn), 16384);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "AnalyzeOptions.base_samples 10000 is not a power of two: rounded up to 16384 (a scrambled Sobol' "
            "sequence is balanced only at powers of two; Saltelli 2010 takes N = 2^k)");
}

TEST(StudyAnalysis, ConstantObservableIsItsOwnErrorAndTheOthersAreAnalysed) {
  TempDir dir;
  // 0.1 + 0.2 and 0.3 differ in the last bit: a constant up to round-off, as a measurement may store it.
  write_study(
      dir.path(), [](double u1, double u2) { return 22.0 + 14.0 * u2 + 5.0 * u1 * u1; },
      [](double u1, double) { return u1 < 0.5 ? 0.1 + 0.2 : 0.3; });
  AnalyzeOptions options;
  options.dir = dir.path();
  options.bootstrap = 10;
  options.base_samples = 256;
  const AnalysisSummary summary = analyze_study(options);
  const ObservableAnalysis& height = observable(summary, "pile_height");
  EXPECT_NE(height.error.find("constant observable"), std::string::npos) << height.error;
  EXPECT_TRUE(height.models.empty());
  const ObservableAnalysis& angle = observable(summary, "angle");
  EXPECT_TRUE(angle.error.empty());
  ASSERT_FALSE(angle.models.empty());
  EXPECT_TRUE(angle.models[0].ok) << angle.models[0].error;
  EXPECT_EQ(analysis_failure(summary), "");
  // The error is in analysis.json and in the printed table.
  const AnalysisSummary back = read_analysis(dir / "analysis" / "analysis.json");
  EXPECT_EQ(observable(back, "pile_height").error, height.error);
  EXPECT_NE(s1_table_text(summary, height).find("not analysed: constant observable"), std::string::npos);
}

TEST(StudyAnalysis, IntervalSettingChoosesTheGpPosteriorInterval) {
  // [analysis] interval: the gp metamodel's indices get the GP-posterior interval (its note says so, in
  // analysis.json too); the default keeps the design bootstrap.
  const auto angle = [](double u1, double u2) { return 22.0 + 14.0 * u2 + 5.0 * std::sin(3.0 * u1); };
  const auto height = [](double u1, double u2) { return 0.01 + 0.002 * u1 + 0.001 * u2 * u2; };
  for (const bool posterior : {false, true}) {
    SCOPED_TRACE(posterior);
    TempDir dir;
    write_study(dir.path(), angle, height,
                std::string("metamodels = [\"gp\"]\n") + (posterior ? "interval = \"gp-posterior\"\n" : ""));
    AnalyzeOptions options;
    options.dir = dir.path();
    options.bootstrap = 20;
    options.base_samples = 256;
    const AnalysisSummary summary = analyze_study(options);
    const ObservableAnalysis& a = observable(summary, "angle");
    ASSERT_EQ(a.models.size(), 1u);
    ASSERT_TRUE(a.models[0].ok) << a.models[0].error;
    EXPECT_EQ(a.models[0].indices.note.find("GP-posterior interval") != std::string::npos, posterior)
        << a.models[0].indices.note;
    EXPECT_EQ(a.models[0].indices.bootstrap, 20);
    EXPECT_LT(a.models[0].indices.first[0].lower, a.models[0].indices.first[0].upper);
    const AnalysisSummary back = read_analysis(dir / "analysis" / "analysis.json");
    EXPECT_EQ(observable(back, "angle").models[0].indices.note, a.models[0].indices.note);
  }
}

TEST(StudyAnalysis, NothingAnalysedNamesEveryObservable) {
  TempDir dir;
  write_study(
      dir.path(), [](double, double) { return 30.0; }, [](double, double) { return 0.02; });
  AnalyzeOptions options;
  options.dir = dir.path();
  options.bootstrap = 0;
  options.base_samples = 64;
  const AnalysisSummary summary = analyze_study(options);
  const std::string failure = analysis_failure(summary);
  EXPECT_NE(failure.find("no observable could be analysed"), std::string::npos) << failure;
  EXPECT_NE(failure.find("angle: constant observable: every one of its 20 samples is 30"), std::string::npos)
      << failure;
  EXPECT_NE(failure.find("pile_height: constant observable"), std::string::npos) << failure;
}

TEST(StudyAnalysis, MetamodelWhoseQ2IsNotComputableRanksNoParameter) {
  // rsm2 in two inputs has 6 terms: on 6 samples it passes through every one, each leave-one-out residual is 0/0
  // and Q² is NaN. Its S1 used to be printed (and written) as any other row's, with exit 0.
  TempDir dir;
  write_study(
      dir.path(), [](double u1, double u2) { return 22.0 + 14.0 * u2 + 5.0 * u1 * u1; },
      [](double u1, double u2) { return 0.02 + 0.01 * u1 + 0.004 * u2 * u2; },
      "metamodels = [\"rsm2\", \"rbf-cubic\"]\n", 6);
  AnalyzeOptions options;
  options.dir = dir.path();
  options.bootstrap = 0;
  options.base_samples = 256;
  const AnalysisSummary summary = analyze_study(options);
  const ObservableAnalysis& angle = observable(summary, "angle");
  ASSERT_EQ(angle.models.size(), 2u);
  const ModelAnalysis& rsm2 = angle.models[0];
  ASSERT_EQ(rsm2.model, "rsm2");
  EXPECT_TRUE(std::isnan(rsm2.quality.q2));
  EXPECT_FALSE(rsm2.ok);
  EXPECT_TRUE(rsm2.fitted);
  EXPECT_TRUE(rsm2.indices.first.empty());
  EXPECT_NE(rsm2.error.find("Q² not computable: leave-one-out Q² is not finite on 6 samples: as many as its terms"),
            std::string::npos)
      << rsm2.error;
  EXPECT_TRUE(angle.models[1].ok) << angle.models[1].error;
  EXPECT_EQ(analysis_failure(summary), "");
  // The printed row gives the reason, not numbers.
  const std::string table = s1_table_text(summary, angle);
  const std::size_t row = table.find("\nrsm2 ");
  ASSERT_NE(row, std::string::npos) << table;
  const std::string rsm2_row = table.substr(row + 1, table.find('\n', row + 1) - row - 1);
  EXPECT_NE(rsm2_row.find("Q² not computable"), std::string::npos) << table;
  EXPECT_EQ(rsm2_row.find("nan"), std::string::npos) << table;
  // The files say the same: no rsm2 row or index, its quality (Q² null) and the reason kept.
  const fs::path out = dir / "analysis";
  EXPECT_EQ(read_file(out / "table_angle.csv").find("rsm2"), std::string::npos) << read_file(out / "table_angle.csv");
  EXPECT_EQ(read_file(out / "sobol_rsm2.csv").find("angle"), std::string::npos) << read_file(out / "sobol_rsm2.csv");
  const nlohmann::json metamodels = nlohmann::json::parse(read_file(out / "metamodels.json"));
  EXPECT_TRUE(metamodels["angle"]["rsm2"]["q2"].is_null()) << metamodels.dump(2);
  EXPECT_EQ(metamodels["angle"]["rsm2"]["error"], rsm2.error);
  const AnalysisSummary back = read_analysis(out / "analysis.json");
  const ModelAnalysis& rsm2_back = observable(back, "angle").models[0];
  EXPECT_FALSE(rsm2_back.ok);
  EXPECT_TRUE(rsm2_back.fitted);
  EXPECT_EQ(rsm2_back.error, rsm2.error);
  EXPECT_DOUBLE_EQ(rsm2_back.quality.r2, rsm2.quality.r2);

  // Alone, it leaves nothing analysed: the analysis fails naming it.
  options.metamodels = {"rsm2"};
  const std::string failure = analysis_failure(analyze_study(options));
  EXPECT_NE(failure.find("angle ~ rsm2: Q² not computable"), std::string::npos) << failure;
}

TEST(StudyAnalysis, StopRequestEndsItBeforeAnyFileIsWritten) {
  TempDir dir;
  write_study(
      dir.path(), [](double u1, double u2) { return 22.0 + 14.0 * u2 + 5.0 * u1 * u1; },
      [](double u1, double u2) { return 0.02 + 0.01 * u1 + 0.004 * u2; });
  AnalyzeOptions options;
  options.dir = dir.path();
  options.bootstrap = 100000;  // hours without the stop
  options.base_samples = 1024;
  options.metamodels = {"rbf-cubic"};
  int polls = 0;
  options.should_stop = [&polls] { return ++polls > 50; };
  EXPECT_THROW(analyze_study(options), sobol::Stopped);
  EXPECT_GT(polls, 50);
  EXPECT_FALSE(fs::exists(dir / "analysis"));
}

}  // namespace
}  // namespace demsa::test
