// The study analysis (orchestrator/analysis/study_analysis.hpp) on synthetic studies: a constant observable is an
// error of its own while the others are analysed, an analysis in which nothing could be analysed says why, and a stop
// request ends it before any file is written.
#include "orchestrator/analysis/analysis_json.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/study/store.hpp"
#include "sobol/stop.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

using namespace demsa::study;
using namespace demsa::analysis;

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

/// DIR/study.toml and DIR/study.db with 20 done samples whose angle and pile height are the given functions.
void write_study(const fs::path& dir, const std::function<double(double, double)>& angle,
                 const std::function<double(double, double)>& height, const std::string& analysis = "") {
  StudyToml toml{.name = "synthetic", .seed = 7, .samples = 20};
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
