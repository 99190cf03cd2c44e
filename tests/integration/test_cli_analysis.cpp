// `demsa analyze` through the real binary on synthetic studies: SIGINT and SIGTERM stop a long analysis at once
// (exit 128 + N, nothing written), a constant observable is reported while the others are analysed, a metamodel whose
// Q² is not computable says why instead of giving indices, and an analysis in which nothing could be analysed exits 2;
// a --base that is not a power of two is rounded up.
#include "orchestrator/study/store.hpp"
#include "support/process.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <csignal>
#include <functional>
#include <thread>

using namespace demsa::study;

namespace demsa::test {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

/// DIR/study.toml and DIR/study.db with 30 done samples of the given angle and pile height.
void write_study(const fs::path& dir, const std::function<double(double, double)>& angle,
                 const std::function<double(double, double)>& height) {
  const StudyToml toml{.name = "synthetic", .seed = 7, .samples = 30};
  SyntheticStudy study = start_synthetic_study(dir, toml.text(), 3);
  for (const SampleRow& row : study.samples) {
    const long run = study.store.add_run(row.sample, 1);
    RunOutcome outcome;
    outcome.exit_code = 0;
    study.store.record_done(
        run, outcome, {{"angle", angle(row.unit[0], row.unit[1])}, {"pile_height", height(row.unit[0], row.unit[1])}});
  }
}

double angle_of(double u1, double u2) { return 22.0 + 14.0 * u2 + 5.0 * u1 * u1 + std::sin(6.0 * u1 * u2); }

class AnalyzeSignal : public ::testing::TestWithParam<int> {};

TEST_P(AnalyzeSignal, StopsWithinASecondAndWritesNothing) {
  const int signal = GetParam();
  TempDir tmp;
  write_study(tmp / "study", angle_of, [](double u1, double u2) { return 0.02 + 0.01 * u1 + 0.004 * u2; });
  // base 65536 and 200 refits: about a minute and a half of work without the signal.
  const pid_t pid = spawn_demsa(
      {"analyze", (tmp / "study").string(), "--base", "65536", "--bootstrap", "200", "--models", "rbf-cubic"},
      tmp / "demsa.log");
  std::this_thread::sleep_for(1s);
  ::kill(pid, signal);
  const auto sent = std::chrono::steady_clock::now();
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  // Ended by demsa itself with 128 + N (a process killed by the signal's default action would leave its partial
  // files behind).
  ASSERT_TRUE(WIFEXITED(status)) << read_file(tmp / "demsa.log");
  EXPECT_EQ(WEXITSTATUS(status), 128 + signal) << read_file(tmp / "demsa.log");
  EXPECT_LT(seconds, 3.0);
  EXPECT_FALSE(fs::exists(tmp / "study" / "analysis")) << "a stopped analysis leaves no file";
  EXPECT_NE(read_file(tmp / "demsa.log").find("nothing written"), std::string::npos) << read_file(tmp / "demsa.log");
}

INSTANTIATE_TEST_SUITE_P(Signals, AnalyzeSignal, ::testing::Values(SIGINT, SIGTERM));

TEST(CliAnalyze, ConstantObservableIsReportedAndTheOthersAnalysed) {
  TempDir tmp;
  write_study(tmp / "study", angle_of, [](double, double) { return 0.025; });
  const CommandResult r = run_demsa({"analyze", (tmp / "study").string(), "--bootstrap", "5", "--base", "256"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("observable 'pile_height': constant observable: every one of its 30 samples is 0.025"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("not analysed: constant observable"), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(read_file(tmp / "study" / "analysis" / "analysis.json"));
  ASSERT_EQ(j["observables"].size(), 2u);
  EXPECT_FALSE(j["observables"][0].contains("error"));
  EXPECT_TRUE(j["observables"][0]["models"][0]["ok"].get<bool>());
  EXPECT_NE(j["observables"][1]["error"].get<std::string>().find("constant observable"), std::string::npos);
  EXPECT_TRUE(j["observables"][1]["models"].empty());
}

TEST(CliAnalyze, BaseThatIsNotAPowerOfTwoIsRoundedUpWithAWarning) {
  TempDir tmp;
  write_study(tmp / "study", angle_of, [](double u1, double) { return 0.02 + 0.01 * u1; });
  const CommandResult r = run_demsa({"analyze", (tmp / "study").string(), "--bootstrap", "0", "--base", "100"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("--base 100 is not a power of two: rounded up to 128"), std::string::npos) << r.err;
  const nlohmann::json j = nlohmann::json::parse(read_file(tmp / "study" / "analysis" / "analysis.json"));
  EXPECT_EQ(j["base_samples"].get<int>(), 128);
}

TEST(CliAnalyze, NothingAnalysedExits2NamingEachObservable) {
  TempDir tmp;
  write_study(
      tmp / "study", [](double, double) { return 31.5; }, [](double, double) { return 0.025; });
  const CommandResult r = run_demsa({"analyze", (tmp / "study").string(), "--bootstrap", "0", "--base", "64"});
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("demsa: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no observable could be analysed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("angle: constant observable: every one of its 30 samples is 31.5"), std::string::npos) << r.err;
  // The files record why, for the report.
  EXPECT_TRUE(fs::exists(tmp / "study" / "analysis" / "analysis.json"));
}

TEST(CliAnalyze, AMetamodelWhoseQ2IsNotComputablePrintsWhyAndAloneExits2) {
  // rsm2 in two parameters has 6 terms: on 6 samples its Q² is NaN. Its S1 row used to be printed with exit 0.
  TempDir tmp;
  SyntheticStudy study = start_synthetic_study(tmp / "study", StudyToml{.samples = 6}.text(), 3);
  record_every_sample_done(study, [](const SampleRow& row) -> std::map<std::string, double> {
    return {{"angle", angle_of(row.unit[0], row.unit[1])}, {"pile_height", 0.02 + 0.01 * row.unit[0]}};
  });
  const CommandResult r = run_demsa({"analyze", (tmp / "study").string(), "--bootstrap", "0", "--base", "64"});
  ASSERT_EQ(r.exit_code, 0) << r.err;  // rbf-cubic gave indices
  EXPECT_NE(r.out.find("rsm2       R2 1.000; Q² not computable: leave-one-out Q² is not finite on 6 samples"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("observable 'angle', metamodel rsm2: Q² not computable"), std::string::npos) << r.err;
  const CommandResult alone =
      run_demsa({"analyze", (tmp / "study").string(), "--models", "rsm2", "--bootstrap", "0", "--base", "64"});
  EXPECT_EQ(alone.exit_code, 2) << alone.out << alone.err;
  EXPECT_NE(alone.err.find("no observable could be analysed:\n  angle ~ rsm2: Q² not computable"), std::string::npos)
      << alone.err;
}

TEST(CliRun, SigintDuringTheAnalysisAtTheEndStopsIt) {
  TempDir tmp;
  const StudyToml toml{.name = "fake-pile",
                       .samples = 8,
                       .parameters = "mu_pp = { low = 0.2, high = 0.8 }\nmu_r_pp = { low = 0.05, high = 0.3 }\n",
                       .tables = "[pile]\nparticles = 300\n",
                       .run = fake_liggghts_run_lines() + "parallel = 2\noversubscribe = true\n",
                       .analysis = "metamodels = [\"rbf-cubic\"]\nbootstrap = 200\nbase_samples = 65536\n"};
  write_file(tmp / "study.toml", toml.text());
  FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const pid_t pid = spawn_demsa(run_args(tmp, {"--quiet"}), tmp / "demsa.log");
  // The cases take well under a second each; the analysis starts once the last one is committed.
  const bool all_done = wait_until(
      [&] {
        if (!fs::exists(tmp / "study" / "study.db")) return false;
        try {
          return Store::open_read_only((tmp / "study" / "study.db").string()).counts().done == 8;
        } catch (const std::exception&) {
          return false;
        }
      },
      std::chrono::seconds(60));
  ASSERT_TRUE(all_done) << read_file(tmp / "demsa.log");
  std::this_thread::sleep_for(1s);
  ::kill(pid, SIGINT);
  const auto sent = std::chrono::steady_clock::now();
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count(), 3.0);
  ASSERT_TRUE(WIFEXITED(status)) << read_file(tmp / "demsa.log");
  EXPECT_EQ(WEXITSTATUS(status), 130) << read_file(tmp / "demsa.log");
  EXPECT_FALSE(fs::exists(tmp / "study" / "analysis" / "analysis.json"));
  EXPECT_NE(read_file(tmp / "demsa.log").find("interrupted during the analysis"), std::string::npos)
      << read_file(tmp / "demsa.log");
}

}  // namespace
}  // namespace demsa::test
