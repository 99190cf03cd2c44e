// `demsa run --submit-only`, `demsa status` collecting a SLURM study, and SIGINT on a SLURM study, against the fake
// sbatch/squeue/scancel of tests/data/slurm and the fake LIGGGHTS of tests/integration/fake_liggghts. The test
// plays the cluster: it runs a task by starting the batch script sbatch received with the SLURM array variables
// set (the task runs the case's run.sh and writes its sentinel, as on a node), and writes squeue's answer.
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/signals.hpp"

#include "support/process.hpp"
#include "support/test_support.hpp"

#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace demsa {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::exec;
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using test::read_file;
using test::spawn_demsa;
using test::wait_exit;
using test::wait_until;
using test::write_file;

std::string study_toml(const std::string& executor, int samples) {
  return test::StudyToml{.name = "fake-slurm",
                         .seed = 5,
                         .samples = samples,
                         .parameters = "mu_pp = { low = 0.2, high = 0.8 }\ne_r = { low = 0.3, high = 0.7 }\n",
                         .tables = "[pile]\nparticles = 300\n",
                         .run = fmt::format("executor = \"{}\"\n", executor) + test::fake_liggghts_run_lines() +
                                "parallel = 2\noversubscribe = true\nretries = 0\n",
                         .analysis = "",
                         .extra = "\n[run.slurm]\ntime_limit = \"00:10:00\"\npoll_interval = 0.05\n"}
      .text();
}

/// Fake SLURM first on PATH, its state folder, and the fake LIGGGHTS' environment; all restored at the end.
class RunnerSlurm : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* path = std::getenv("PATH");
    m_saved_path = path != nullptr ? path : "";
    ::setenv("PATH", (test::data_path("slurm").string() + ":" + m_saved_path).c_str(), 1);
    fs::create_directories(fake());
    ::setenv("FAKE_SLURM_DIR", fake().c_str(), 1);
    ::setenv("FAKE_LIGGGHTS_PLAN", "", 1);
    ::setenv("FAKE_LIGGGHTS_STATE", m_tmp.path().c_str(), 1);
    ::setenv("FAKE_LIGGGHTS_SECONDS", "0", 1);
    m_dir = m_tmp / "study dir";
    StopFlag::reset();
  }
  void TearDown() override {
    ::setenv("PATH", m_saved_path.c_str(), 1);
    for (const char* name : {"FAKE_SLURM_DIR", "FAKE_LIGGGHTS_PLAN", "FAKE_LIGGGHTS_STATE", "FAKE_LIGGGHTS_SECONDS"})
      ::unsetenv(name);
    StopFlag::reset();
  }

  fs::path fake() const { return m_tmp / "fake"; }
  fs::path study(const std::string& executor, int samples) const {
    write_file(m_tmp / "study.toml", study_toml(executor, samples));
    return m_tmp / "study.toml";
  }
  std::vector<std::string> run_args(const std::vector<std::string>& extra = {}) const {
    std::vector<std::string> args{"run",    (m_tmp / "study.toml").string(), "--dir", m_dir.string(), "--no-analyze",
                                  "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  }
  /// Runs task `task` of array job `job` as a node would: the batch script sbatch received, SLURM's variables set.
  void run_task(const std::string& job, int task, int expected_exit = 0) const {
    const test::CommandResult r =
        test::run_command({"env", "SLURM_ARRAY_JOB_ID=" + job, "SLURM_ARRAY_TASK_ID=" + std::to_string(task),
                           "SLURMD_NODENAME=node1", "bash", (fake() / "jobs" / job / "script").string()});
    ASSERT_EQ(r.exit_code, expected_exit) << r.out << r.err;
  }
  void set_squeue(const std::string& job, const std::string& lines) const {
    write_file(fake() / "jobs" / job / "squeue", lines);
  }
  std::string next_job_id() const { return read_file(fake() / "next_id"); }
  int squeue_calls() const {
    if (!fs::exists(fake() / "squeue_calls")) return 0;
    const std::string text = read_file(fake() / "squeue_calls");
    return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  }
  Store store() const { return Store::open_read_only((m_dir / "study.db").string()); }

  test::TempDir m_tmp;
  fs::path m_dir;
  std::string m_saved_path;
};

std::vector<std::string> job_ids(const Store& store, RunState state) {
  std::vector<std::string> ids;
  for (const RunRow& r : store.runs_in_state(state)) ids.push_back(r.job_id);
  std::sort(ids.begin(), ids.end());
  return ids;
}

TEST_F(RunnerSlurm, SubmitOnlyThenStatusCollectsThenRunFinishes) {
  study("slurm", 3);
  const test::CommandResult submitted = test::run_demsa(run_args({"--submit-only"}));
  ASSERT_EQ(submitted.exit_code, 0) << submitted.out << submitted.err;
  EXPECT_NE(submitted.out.find("3 case(s) submitted to SLURM now, 3 queued or running"), std::string::npos)
      << submitted.out;
  EXPECT_EQ(job_ids(store(), RunState::submitted), (std::vector<std::string>{"100_0", "100_1", "100_2"}));
  EXPECT_NE(read_file(fake() / "jobs/100/args").find("--array=0-2\n"), std::string::npos);
  EXPECT_EQ(squeue_calls(), 0) << "--submit-only must not poll";
  EXPECT_FALSE(fs::exists(fake() / "scancel_args")) << "--submit-only must not cancel";

  // Again: everything is already queued, nothing is submitted twice.
  const test::CommandResult again = test::run_demsa(run_args({"--submit-only"}));
  ASSERT_EQ(again.exit_code, 0) << again.out << again.err;
  EXPECT_NE(again.out.find("0 case(s) submitted to SLURM now, 3 queued or running"), std::string::npos) << again.out;
  EXPECT_EQ(next_job_id(), "101\n");
  EXPECT_EQ(squeue_calls(), 0);

  // Two tasks end on the cluster; status collects them, submits and cancels nothing.
  run_task("100", 0);
  run_task("100", 1);
  set_squeue("100", "0 COMPLETED 0\n1 COMPLETED 0\n2 RUNNING 0\n");
  const test::CommandResult status = test::run_demsa({"status", m_dir.string(), "--json"});
  ASSERT_EQ(status.exit_code, 0) << status.err;
  const nlohmann::json j = nlohmann::json::parse(status.out);
  EXPECT_EQ(j.at("done").get<int>(), 2) << status.out << status.err;
  EXPECT_EQ(j.at("running").get<int>(), 1);
  EXPECT_EQ(j.at("collected").get<int>(), 2);
  EXPECT_GE(squeue_calls(), 1);
  EXPECT_EQ(next_job_id(), "101\n");
  EXPECT_FALSE(fs::exists(fake() / "scancel_args"));
  for (int k : {0, 1}) {
    const nlohmann::json result =
        nlohmann::json::parse(read_file(m_dir / "cases" / fmt::format("{:06d}", k) / "result.json"));
    EXPECT_EQ(result.at("host").get<std::string>(), "node1");
    EXPECT_GT(result.at("observables").at("angle").get<double>(), 0.0);
  }
  EXPECT_EQ(job_ids(store(), RunState::submitted), (std::vector<std::string>{"100_2"}));

  // Text status: nothing left to collect, the counts as always.
  const test::CommandResult text = test::run_demsa({"status", m_dir.string()});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("samples 3: done 2, running 1, failed 0, pending 0"), std::string::npos) << text.out;

  // The last task ends; `demsa run` adopts it and finishes the study without a new submission.
  run_task("100", 2);
  set_squeue("100", "0 COMPLETED 0\n1 COMPLETED 0\n2 COMPLETED 0\n");
  const test::CommandResult run = test::run_demsa(run_args());
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("3 of 3 samples done (1 now, 0 recovered)"), std::string::npos) << run.out;
  EXPECT_EQ(next_job_id(), "101\n");
  EXPECT_EQ(store().counts().attempts, 3);
}

TEST_F(RunnerSlurm, StatusCollectsAFailedTaskAndRunRetriesIt) {
  study("slurm", 2);
  ::setenv("FAKE_LIGGGHTS_PLAN", "1:error", 1);
  ASSERT_EQ(test::run_demsa(run_args({"--submit-only"})).exit_code, 0);
  run_task("100", 0);
  run_task("100", 1, 1);  // the case's run.sh fails: the task ends with its status
  set_squeue("100", "0 COMPLETED 0\n1 FAILED 256\n");
  const test::CommandResult status = test::run_demsa({"status", m_dir.string(), "--json"});
  ASSERT_EQ(status.exit_code, 0) << status.err;
  const nlohmann::json j = nlohmann::json::parse(status.out);
  EXPECT_EQ(j.at("done").get<int>(), 1);
  EXPECT_EQ(j.at("failed").get<int>(), 1);
  ASSERT_EQ(j.at("failures").size(), 1u);
  EXPECT_EQ(j.at("failures")[0].at("class").get<std::string>(), "liggghts-error");
  EXPECT_EQ(next_job_id(), "101\n") << "status must not resubmit a failed case";

  // `demsa run --submit-only` resubmits only the failed case.
  ::setenv("FAKE_LIGGGHTS_PLAN", "", 1);
  const test::CommandResult resubmitted = test::run_demsa(run_args({"--submit-only"}));
  ASSERT_EQ(resubmitted.exit_code, 0) << resubmitted.err;
  EXPECT_NE(resubmitted.out.find("1 case(s) submitted to SLURM now"), std::string::npos) << resubmitted.out;
  EXPECT_EQ(job_ids(store(), RunState::submitted), (std::vector<std::string>{"101_0"}));
}

/// The job ids of all runs, in run order.
std::vector<std::string> all_job_ids(const Store& store) {
  std::vector<std::string> ids;
  for (const RunRow& r : store.runs()) ids.push_back(r.job_id);
  return ids;
}

bool has_event(const Store& store, const std::string& kind, const std::string& text) {
  for (const EventRow& e : store.events())
    if (e.kind == kind && e.message.find(text) != std::string::npos) return true;
  return false;
}

TEST_F(RunnerSlurm, KilledAfterSbatchTheRestartAdoptsTheArrayInsteadOfSubmittingAgain) {
  study("slurm", 2);
  // demsa dies (SIGKILL) after the cluster has the array job 100, before it has read its id
  write_file(fake() / "sbatch_kill_parent", "after");
  const test::CommandResult killed = test::run_demsa(run_args({"--submit-only"}));
  ASSERT_EQ(killed.exit_code, 128 + SIGKILL) << killed.out << killed.err;
  fs::remove(fake() / "sbatch_kill_parent");
  ASSERT_EQ(next_job_id(), "101\n");

  // The runs were committed, each with the token of the array and its index, before sbatch ran.
  const std::vector<RunRow> runs = store().runs();
  ASSERT_EQ(runs.size(), 2u);
  const std::string& first = runs[0].job_id;
  ASSERT_EQ(first.rfind("pending:", 0), 0u) << first;
  const std::string token = first.substr(8, first.rfind(':') - 8);
  EXPECT_EQ(all_job_ids(store()), (std::vector<std::string>{"pending:" + token + ":0", "pending:" + token + ":1"}));
  EXPECT_NE(read_file(fake() / "jobs/100/args").find("--comment=demsa:" + token + "\n"), std::string::npos);

  // squeue fails: status and run keep the runs as they are and submit nothing
  write_file(fake() / "squeue_fail", "");
  const test::CommandResult blind = test::run_demsa({"status", m_dir.string()});
  ASSERT_EQ(blind.exit_code, 0) << blind.err;
  EXPECT_NE(blind.out.find("samples 2: done 0, running 2, failed 0, pending 0"), std::string::npos) << blind.out;
  // Standard output stays pure JSON with --json: log lines go to standard error.
  const test::CommandResult blind_json = test::run_demsa({"status", m_dir.string(), "--json"});
  ASSERT_EQ(blind_json.exit_code, 0) << blind_json.err;
  EXPECT_TRUE(nlohmann::json::accept(blind_json.out)) << blind_json.out;
  EXPECT_NE(blind_json.err.find("squeue"), std::string::npos) << blind_json.err;
  {
    RunOptions options;
    options.study_file = m_tmp / "study.toml";
    options.dir = m_dir;
    options.quiet = true;
    const int calls = squeue_calls();
    options.should_stop = [&] { return squeue_calls() >= calls + 3; };
    options.cancel_on_interrupt = true;  // even asked to cancel: a job it cannot find stays submitted
    const RunSummary summary = run_study(options);
    EXPECT_TRUE(summary.interrupted);
    EXPECT_EQ(summary.submitted, 0);
    EXPECT_EQ(summary.left_running, 2);
  }
  EXPECT_EQ(next_job_id(), "101\n");
  EXPECT_FALSE(fs::exists(fake() / "scancel_args"));
  EXPECT_EQ(all_job_ids(store()), (std::vector<std::string>{"pending:" + token + ":0", "pending:" + token + ":1"}));

  // squeue answers: status finds the array by its token and stores the real ids
  fs::remove(fake() / "squeue_fail");
  set_squeue("100", "0 RUNNING 0\n1 PENDING 0\n");
  const test::CommandResult status = test::run_demsa({"status", m_dir.string(), "--json"});
  ASSERT_EQ(status.exit_code, 0) << status.err;
  EXPECT_EQ(nlohmann::json::parse(status.out).at("running").get<int>(), 2) << status.out;
  EXPECT_EQ(all_job_ids(store()), (std::vector<std::string>{"100_0", "100_1"}));
  EXPECT_TRUE(has_event(store(), "adopted", "SLURM task 100_1"));

  // the tasks end; `demsa run` collects them without a second submission
  run_task("100", 0);
  run_task("100", 1);
  set_squeue("100", "0 COMPLETED 0\n1 COMPLETED 0\n");
  const test::CommandResult run = test::run_demsa(run_args());
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("2 of 2 samples done (2 now, 0 recovered)"), std::string::npos) << run.out;
  EXPECT_EQ(next_job_id(), "101\n");
  EXPECT_EQ(store().counts().attempts, 2);
}

TEST_F(RunnerSlurm, KilledBeforeSbatchSubmittedTheRunsAreRequeued) {
  study("slurm", 2);
  write_file(fake() / "sbatch_kill_parent", "before");
  const test::CommandResult killed = test::run_demsa(run_args({"--submit-only"}));
  ASSERT_EQ(killed.exit_code, 128 + SIGKILL) << killed.out << killed.err;
  fs::remove(fake() / "sbatch_kill_parent");
  EXPECT_FALSE(fs::exists(fake() / "next_id")) << "the controller never got the array";
  {
    // The crash was long ago (older than the sbatch time limit): back-date the tokens, as the runs' ids say.
    Store writable((m_dir / "study.db").string());
    for (const RunRow& r : writable.runs()) {
      ASSERT_EQ(r.job_id.rfind("pending:", 0), 0u) << r.job_id;
      writable.set_job_id(r.id, "pending:1" + r.job_id.substr(r.job_id.find('-')));
    }
  }
  write_file(fake() / "sbatch_pending", "");
  RunOptions options;
  options.study_file = m_tmp / "study.toml";
  options.dir = m_dir;
  options.quiet = true;
  options.should_stop = [&] { return fs::exists(fake() / "jobs/100/args"); };
  const RunSummary summary = run_study(options);
  EXPECT_TRUE(summary.interrupted);
  EXPECT_EQ(summary.submitted, 2);
  const Store s = store();
  EXPECT_EQ(s.runs_in_state(RunState::requeued).size(), 2u);
  EXPECT_EQ(job_ids(s, RunState::submitted), (std::vector<std::string>{"100_0", "100_1"}));
  EXPECT_TRUE(has_event(s, "requeued", "sbatch never submitted it"));
  EXPECT_EQ(next_job_id(), "101\n");
}

TEST_F(RunnerSlurm, SubmitOnlyIsRefusedForTheLocalExecutor) {
  study("local", 2);
  const test::CommandResult r = test::run_demsa(run_args({"--submit-only"}));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("--submit-only needs [run] executor = \"slurm\""), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(m_tmp / "starts.log")) << "no case may run";
  EXPECT_FALSE(fs::exists(fake() / "next_id"));
}

TEST_F(RunnerSlurm, SigintLeavesTasksRunningUnlessCancelOnInterrupt) {
  study("slurm", 2);
  write_file(fake() / "sbatch_pending", "");
  const fs::path log = m_tmp / "demsa.log";
  {
    const pid_t pid = spawn_demsa(run_args(), log);
    ASSERT_TRUE(wait_until([&] { return squeue_calls() >= 2; })) << read_file(log);
    ::kill(pid, SIGINT);
    EXPECT_EQ(wait_exit(pid), 130) << read_file(log);
  }
  const std::string first = read_file(log);
  EXPECT_NE(first.find("2 SLURM task(s) keep running (not cancelled)"), std::string::npos) << first;
  EXPECT_FALSE(fs::exists(fake() / "scancel_args")) << "stdin is no terminal and no --cancel-on-interrupt";
  EXPECT_EQ(job_ids(store(), RunState::submitted), (std::vector<std::string>{"100_0", "100_1"}));

  // With --cancel-on-interrupt: the adopted tasks are scancelled and requeued.
  {
    const int calls = squeue_calls();
    const pid_t pid = spawn_demsa(run_args({"--cancel-on-interrupt"}), log);
    ASSERT_TRUE(wait_until([&] { return squeue_calls() >= calls + 2; })) << read_file(log);
    ::kill(pid, SIGINT);
    EXPECT_EQ(wait_exit(pid), 130) << read_file(log);
  }
  EXPECT_EQ(read_file(fake() / "scancel_args"), "100\n");
  EXPECT_TRUE(store().runs_in_state(RunState::submitted).empty());
  EXPECT_EQ(job_ids(store(), RunState::requeued), (std::vector<std::string>{"100_0", "100_1"}));
  EXPECT_EQ(next_job_id(), "101\n");
}

TEST_F(RunnerSlurm, AskOnInterruptDecidesWhetherToCancel) {
  const fs::path file = study("slurm", 2);
  write_file(fake() / "sbatch_pending", "");
  for (const bool answer : {false, true}) {
    SCOPED_TRACE(answer ? "yes" : "no");
    RunOptions options;
    options.study_file = file;
    options.dir = m_dir;
    options.quiet = true;
    const std::string job = answer ? "101" : "100";
    // Stop once the array is submitted.
    options.should_stop = [&] { return fs::exists(fake() / "jobs" / job / "args"); };
    int asked = -1;
    options.ask_cancel = [&](int in_flight) {
      asked = in_flight;
      return answer;
    };
    if (answer) {
      // the first (unanswered) round left 100_0 and 100_1 submitted: cancel them by hand so that both are resubmitted
      set_squeue("100", "0 CANCELLED 0\n1 CANCELLED 0\n");
    }
    const RunSummary summary = run_study(options);
    EXPECT_TRUE(summary.interrupted);
    EXPECT_EQ(asked, 2);
    if (!answer) {
      EXPECT_EQ(summary.left_running, 2);
      EXPECT_FALSE(fs::exists(fake() / "scancel_args"));
      EXPECT_EQ(job_ids(store(), RunState::submitted), (std::vector<std::string>{"100_0", "100_1"}));
    } else {
      EXPECT_EQ(summary.left_running, 0);
      EXPECT_EQ(read_file(fake() / "scancel_args"), "101\n");
      EXPECT_TRUE(store().runs_in_state(RunState::submitted).empty());
      EXPECT_EQ(store().runs_in_state(RunState::requeued).size(), 4u);
    }
  }
}

}  // namespace
}  // namespace demsa
