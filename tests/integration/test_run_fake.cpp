// `demsa run` / `status` / `analyze` end to end against a fake LIGGGHTS (tests/integration/fake_liggghts): every
// failure class, retries, the timeout, SIGINT, and resume after SIGKILL at random moments.
#include "orchestrator/study/store.hpp"

#include "support/process.hpp"
#include "support/test_support.hpp"

#include <signal.h>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <thread>

namespace demsa {

using namespace demsa::study;
namespace {

namespace fs = std::filesystem;
using test::spawn_demsa;
using test::starts_per_sample;
using test::wait_exit;
using test::wait_until;

struct StudyText {
  std::string experiment = "pile";
  int samples = 12;
  int parallel = 2;
  double timeout = 0;
  int retries = 1;
  std::string analysis =
      "metamodels = [\"rsm2\", \"rbf-cubic\"]\nbootstrap = 0\nbase_samples = 512\nsecond_order = false\n";
  std::string extra;
};

std::string study_toml(const StudyText& s) {
  return test::StudyToml{.name = "fake-" + s.experiment,
                         .experiment = s.experiment,
                         .seed = 7,
                         .samples = s.samples,
                         .parameters =
                             "mu_pp = { low = 0.2, high = 0.8 }\nmu_r_pp = { low = 0.05, high = 0.3 }\n"
                             "e_r = { low = 0.3, high = 0.7 }\n",
                         .tables = s.experiment == "pile" ? "[pile]\nparticles = 300\n" : "",
                         .run = test::fake_liggghts_run_lines() +
                                fmt::format("parallel = {}\noversubscribe = true\ntimeout = {}\nretries = {}\n",
                                            s.parallel, s.timeout, s.retries),
                         .analysis = s.analysis,
                         .extra = s.extra}
      .text();
}

/// TMP/study.toml, the study of `s`.
void write_study(const test::TempDir& tmp, const StudyText& s) { test::write_file(tmp / "study.toml", study_toml(s)); }

/// The file's text, or "" when it does not exist (yet, or any more).
std::string read_if_exists(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Live processes whose working directory is under `dir`.
int processes_in(const fs::path& dir) {
  int count = 0;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator("/proc", ec)) {
    std::error_code link_error;
    const fs::path cwd = fs::read_symlink(entry.path() / "cwd", link_error);
    if (link_error) continue;
    const std::string stat = read_if_exists(entry.path() / "stat");
    if (stat.find(") Z") != std::string::npos) continue;
    if (cwd.string().rfind(dir.string(), 0) == 0) ++count;
  }
  return count;
}

/// The store's invariants after any sequence of runs and kills: one done run per sample, nothing after it, no
/// more fake starts than run rows, result.json belongs to the done run, integrity ok.
void expect_each_sample_done_exactly_once(const fs::path& dir, const fs::path& state, int samples) {
  const Store store = Store::open_read_only((dir / "study.db").string());
  EXPECT_EQ(store.integrity_check(), "ok");
  std::map<int, std::vector<RunRow>> runs;
  for (const RunRow& r : store.runs()) runs[r.sample].push_back(r);
  const std::map<int, int> starts = starts_per_sample(state);
  for (int k = 0; k < samples; ++k) {
    SCOPED_TRACE(fmt::format("sample {}", k));
    const std::vector<RunRow>& rows = runs[k];
    ASSERT_FALSE(rows.empty());
    int done = 0;
    for (const RunRow& r : rows) done += r.state == RunState::done;
    EXPECT_EQ(done, 1);
    EXPECT_EQ(rows.back().state, RunState::done) << "a run was started after the sample was done";
    const auto it = starts.find(k);
    EXPECT_LE(it == starts.end() ? 0 : it->second, static_cast<int>(rows.size()));
    const nlohmann::json result =
        nlohmann::json::parse(test::read_file(dir / "cases" / fmt::format("{:06d}", k) / "result.json"));
    EXPECT_EQ(result.at("run").get<long>(), rows.back().id);
    EXPECT_TRUE(store.observables().at(k).count("angle"));
  }
}

TEST(RunFake, EveryFailureClassRetriesTimeoutAndAnalysis) {
  test::TempDir tmp;
  StudyText s;
  s.samples = 14;
  s.timeout = 4.0;
  s.retries = 1;
  write_study(tmp, s);
  test::FakeLiggghtsEnvironment env(
      "1:error,2:nan,3:exit,4:signal,5:hang,6:nodump,7:truncated,8:lost,9:flaky,10:offpedestal", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--progress-interval", "1"}));
  EXPECT_EQ(run.exit_code, 1) << run.out << run.err;  // failures left
  EXPECT_NE(run.out.find("5 of 14 samples done"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("Sobol' S1 of angle"), std::string::npos) << run.out;
  EXPECT_NE(run.err.find("[demsa] done"), std::string::npos) << run.err;  // periodic lines: not a terminal

  const test::CommandResult status = test::run_demsa({"status", (tmp / "study").string(), "--json"});
  ASSERT_EQ(status.exit_code, 0) << status.err;
  const nlohmann::json j = nlohmann::json::parse(status.out);
  EXPECT_EQ(j.at("done").get<int>(), 5);
  EXPECT_EQ(j.at("failed").get<int>(), 9);
  EXPECT_EQ(j.at("running").get<int>(), 0);
  std::map<int, std::string> classes;
  for (const nlohmann::json& f : j.at("failures")) {
    classes[f.at("sample").get<int>()] = f.at("class").get<std::string>();
    EXPECT_EQ(f.at("attempt").get<int>(), 2) << "every failure was retried once";
    EXPECT_FALSE(f.at("log_tail").get<std::string>().empty());
  }
  const std::map<int, std::string> expected{{1, "liggghts-error"}, {2, "energy-blowup"},  {3, "nonzero-exit"},
                                            {4, "signal"},         {5, "timeout"},        {6, "missing-dump"},
                                            {7, "missing-dump"},   {8, "lost-particles"}, {10, "measurement"}};
  EXPECT_EQ(classes, expected);
  const std::map<int, int> starts = starts_per_sample(tmp.path());
  EXPECT_EQ(starts.at(9), 2);  // flaky: failed once, retried, done
  EXPECT_EQ(starts.at(0), 1);
  EXPECT_EQ(starts.at(5), 2);

  // The analysis left the failed samples out and wrote the paper's table.
  const nlohmann::json analysis = nlohmann::json::parse(test::read_file(tmp / "study" / "analysis" / "analysis.json"));
  EXPECT_EQ(analysis.at("samples_used").size(), 5u);
  EXPECT_EQ(analysis.at("samples_left_out").size(), 9u);
  const std::string table = test::read_file(tmp / "study" / "analysis" / "table_angle.csv");
  EXPECT_EQ(table.rfind("model,S1_mu_pp,S1_e_r,S1_mu_r_pp,residual,r2,q2\n", 0), 0u) << table;

  // Five samples are too few for a design bootstrap of the RBF (a resample keeps all five distinct points in 4% of
  // the draws): the indices are still reported, without intervals, and the analysis says why.
  const test::CommandResult boot = test::run_demsa({"analyze", (tmp / "study").string(), "--bootstrap", "30"});
  ASSERT_EQ(boot.exit_code, 0) << boot.out << boot.err;
  EXPECT_NE(boot.out.find("rbf-cubic: no interval: only "), std::string::npos) << boot.out;
  EXPECT_EQ(boot.out.find("rbf-cubic  not fitted"), std::string::npos) << boot.out;
  const nlohmann::json booted = nlohmann::json::parse(test::read_file(tmp / "study" / "analysis" / "analysis.json"));
  EXPECT_NE(booted.dump().find("design-bootstrap refits of rbf-cubic succeeded"), std::string::npos);

  // A second run retries the failed samples (same plan: they fail again) and repeats no done sample.
  const test::CommandResult again = test::run_demsa(test::run_args(tmp, {"--no-analyze", "--quiet"}));
  EXPECT_EQ(again.exit_code, 1);
  const std::map<int, int> after = starts_per_sample(tmp.path());
  EXPECT_EQ(after.at(0), 1);
  EXPECT_EQ(after.at(9), 2);
  EXPECT_EQ(after.at(1), 4);
}

TEST(RunFake, AStopThatFollowsFromTheSettingsIsNotRetried) {
  // The pile's stop at the insertion height follows from its settings: each such case ran twice. A LIGGGHTS error of
  // another kind is still retried.
  test::TempDir tmp;
  StudyText s;
  s.samples = 4;
  s.retries = 2;
  write_study(tmp, s);
  test::FakeLiggghtsEnvironment env("1:insertion,2:error", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--no-analyze", "--quiet"}));
  EXPECT_EQ(run.exit_code, 1) << run.out << run.err;
  const std::map<int, int> starts = starts_per_sample(tmp.path());
  EXPECT_EQ(starts.at(1), 1);
  EXPECT_EQ(starts.at(2), 3);
  EXPECT_EQ(starts.at(0), 1);
}

TEST(RunFake, ResumeAfterSigkillAtRandomMomentsDoesEachSampleExactlyOnce) {
  test::TempDir tmp;
  StudyText s;
  s.samples = 10;
  write_study(tmp, s);
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.4);
  const std::vector<std::string> args = test::run_args(tmp, {"--no-analyze", "--quiet"});
  test::kill_at_random_moments(args, tmp / "demsa.log", 2024, 6, 150, 1200);
  const test::CommandResult final_run = test::run_demsa(args);
  ASSERT_EQ(final_run.exit_code, 0) << final_run.out << final_run.err << test::read_file(tmp / "demsa.log");
  expect_each_sample_done_exactly_once(tmp / "study", tmp.path(), s.samples);
  // Nothing runs any more, and a further run starts nothing.
  const std::size_t starts_before = test::read_file(tmp / "starts.log").size();
  EXPECT_EQ(test::run_demsa(args).exit_code, 0);
  EXPECT_EQ(test::read_file(tmp / "starts.log").size(), starts_before);
}

TEST(RunFake, GpSettingsOfTheStudyReachAnalyzeAndCalibrate) {
  test::TempDir tmp;
  StudyText s;
  s.analysis =
      "metamodels = [\"gp\"]\nbootstrap = 0\nbase_samples = 512\nsecond_order = false\ngp_kernel = \"matern52\"\n"
      "gp_trend = \"linear\"\ngp_nugget = true\n";
  write_study(tmp, s);
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const nlohmann::json analysis = nlohmann::json::parse(test::read_file(tmp / "study" / "analysis" / "analysis.json"));
  const std::string text = analysis.dump();
  const nlohmann::json* gp = nullptr;
  for (const nlohmann::json& o : analysis.at("observables"))
    for (const nlohmann::json& m : o.at("models"))
      if (m.at("model") == "gp") gp = &m;
  ASSERT_NE(gp, nullptr) << text;
  // an estimated nugget (it is exactly 0 without gp_nugget)
  EXPECT_GT(gp->at("quality").at("parameters").at("nugget").get<double>(), 0.0) << gp->dump();
  const test::CommandResult calibrate =
      test::run_demsa({"calibrate", (tmp / "study").string(), "--target", "angle=30"});
  EXPECT_EQ(calibrate.exit_code, 0) << calibrate.out << calibrate.err;
  EXPECT_NE(calibrate.out.find("gp"), std::string::npos) << calibrate.out;
}

TEST(RunFake, SigintStopsTheCasesAndTheStudyResumes) {
  test::TempDir tmp;
  StudyText s;
  s.samples = 4;
  write_study(tmp, s);
  const std::vector<std::string> args = test::run_args(tmp, {"--no-analyze", "--quiet"});
  {
    test::FakeLiggghtsEnvironment env("", tmp.path(), 30.0);
    const pid_t pid = spawn_demsa(args, tmp / "demsa.log");
    wait_until([&] { return starts_per_sample(tmp.path()).size() >= 2; });  // 20 s: under load the two may take seconds
    ASSERT_EQ(starts_per_sample(tmp.path()).size(), 2u);                    // two cases at once
    // While it runs, status reads the store and sees the running cases.
    const test::CommandResult status = test::run_demsa({"status", (tmp / "study").string(), "--json"});
    ASSERT_EQ(status.exit_code, 0) << status.err;
    const nlohmann::json j = nlohmann::json::parse(status.out);
    EXPECT_EQ(j.at("running").get<int>(), 2);
    EXPECT_EQ(j.at("active_pid").get<long>(), static_cast<long>(pid));
    const auto start = std::chrono::steady_clock::now();
    ::kill(pid, SIGINT);
    EXPECT_EQ(wait_exit(pid), 130);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  }
  // No process is left working in a case folder of this study.
  EXPECT_EQ(processes_in(tmp / "study"), 0);
  {
    const Store store = Store::open_read_only((tmp / "study" / "study.db").string());
    EXPECT_EQ(store.counts().running, 0);
    EXPECT_EQ(store.runs_in_state(RunState::requeued).size(), 2u);
  }
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult resumed = test::run_demsa(args);
  EXPECT_EQ(resumed.exit_code, 0) << resumed.out << resumed.err;
  expect_each_sample_done_exactly_once(tmp / "study", tmp.path(), s.samples);
}

TEST(RunFake, OedometerPlateNotConvergedIsAFailureClass) {
  test::TempDir tmp;
  StudyText s;
  s.experiment = "oedometer";
  s.samples = 6;
  s.extra = "\n[oedometer]\nparticles = 200\n";
  write_study(tmp, s);
  test::FakeLiggghtsEnvironment env("2:plate", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--no-analyze", "--quiet"}));
  EXPECT_EQ(run.exit_code, 1) << run.out << run.err;
  const test::CommandResult status = test::run_demsa({"status", (tmp / "study").string(), "--json"});
  const nlohmann::json j = nlohmann::json::parse(status.out);
  EXPECT_EQ(j.at("done").get<int>(), 5);
  ASSERT_EQ(j.at("failures").size(), 1u);
  EXPECT_EQ(j.at("failures")[0].at("sample").get<int>(), 2);
  EXPECT_EQ(j.at("failures")[0].at("class").get<std::string>(), "plate-not-converged");
  const Store store = Store::open_read_only((tmp / "study" / "study.db").string());
  // A load not reached is final: the study allows a retry, and the sample ran once.
  EXPECT_EQ(store.runs_in_state(RunState::failed).size(), 1u);
  // Settlements relative to the first load: 3 loads after 100 N, growing with the load.
  const std::map<std::string, double>& values = store.observables().at(0);
  ASSERT_TRUE(values.count("settlement_3"));
  EXPECT_GT(values.at("settlement_3"), values.at("settlement_1"));
  EXPECT_GT(values.at("settlement_1"), 0.0);
}

TEST(RunFake, DryRunWritesEveryCaseAndRunsNothing) {
  test::TempDir tmp;
  StudyText s;
  s.samples = 5;
  write_study(tmp, s);
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--dry-run"}));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (int k = 0; k < 5; ++k) EXPECT_TRUE(fs::exists(tmp / "study" / "cases" / fmt::format("{:06d}", k) / "run.sh"));
  EXPECT_TRUE(fs::exists(tmp / "study" / "design.csv"));
  EXPECT_FALSE(fs::exists(tmp / "starts.log"));
}

TEST(RunFake, ChangedDesignIsRefusedUnlessNew) {
  test::TempDir tmp;
  StudyText s;
  s.samples = 4;
  write_study(tmp, s);
  ASSERT_EQ(test::run_demsa(test::run_args(tmp, {"--dry-run"})).exit_code, 0);
  // A design-relevant change is refused, naming the key.
  s.experiment = "oedometer";
  write_study(tmp, s);
  const test::CommandResult refused = test::run_demsa(test::run_args(tmp, {}));
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("design-relevant settings differ"), std::string::npos) << refused.err;
  // More samples extend the design (docs/how-to/refine.md); fewer are refused.
  s.experiment = "pile";
  s.samples = 6;
  write_study(tmp, s);
  ASSERT_EQ(test::run_demsa(test::run_args(tmp, {"--dry-run"})).exit_code, 0);
  EXPECT_TRUE(fs::exists(tmp / "study" / "cases" / "000005" / "run.sh"));
  s.samples = 4;
  write_study(tmp, s);
  const test::CommandResult shrunk = test::run_demsa(test::run_args(tmp, {"--dry-run"}));
  EXPECT_EQ(shrunk.exit_code, 2);
  EXPECT_NE(shrunk.err.find("can grow, not shrink"), std::string::npos) << shrunk.err;
  // [run] settings may change freely.
  s.samples = 6;
  s.retries = 3;
  write_study(tmp, s);
  EXPECT_EQ(test::run_demsa(test::run_args(tmp, {"--dry-run"})).exit_code, 0);
  s.samples = 3;
  write_study(tmp, s);
  const test::CommandResult renewed = test::run_demsa(test::run_args(tmp, {"--dry-run", "--new"}));
  EXPECT_EQ(renewed.exit_code, 0) << renewed.err;
  EXPECT_TRUE(fs::exists(tmp / "study" / "cases" / "000002" / "run.sh"));
  EXPECT_FALSE(fs::exists(tmp / "study" / "cases" / "000003"));
}

TEST(RunFake, StatusAndAnalyzeOnAFolderThatIsNoStudy) {
  test::TempDir tmp;
  const test::CommandResult status = test::run_demsa({"status", tmp.path().string()});
  EXPECT_EQ(status.exit_code, 2);
  EXPECT_NE(status.err.find("not a study folder"), std::string::npos);
  const test::CommandResult analyze = test::run_demsa({"analyze", tmp.path().string()});
  EXPECT_EQ(analyze.exit_code, 2);
  EXPECT_NE(analyze.err.find("not a study folder"), std::string::npos);
}

}  // namespace
}  // namespace demsa
