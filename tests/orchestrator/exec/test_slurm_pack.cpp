// SLURM pack mode without a cluster: the sbatch arguments of one allocation, SLURM times, the driver script run by
// bash with the fake srun of tests/data/slurm (it runs each job step here), and the executor following a pack
// allocation through the fake sbatch/squeue/scancel, the test playing the cluster.
#include "orchestrator/exec/slurm/executor.hpp"
#include "orchestrator/experiments/registry.hpp"

#include "orchestrator/study/config.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace demsa {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::experiments;
using namespace demsa::exec;
namespace {
namespace fs = std::filesystem;
using std::chrono::milliseconds;
using test::read_file;
using test::TempDir;
using test::write_file;

void write_run_sh(const fs::path& folder, const std::string& body) {
  write_file(folder / "run.sh", "#!/bin/bash\n" + body);
  fs::permissions(folder / "run.sh", fs::perms::owner_all, fs::perm_options::add);
}

SlurmSubmission pack_submission(const fs::path& work, int cases) {
  SlurmSubmission s;
  for (int i = 0; i < cases; ++i)
    s.case_folders.push_back(work.parent_path() / "cases" / ("case " + std::to_string(i)));
  s.work_dir = work;
  s.job_name = "demsa-x";
  s.settings.mode = SlurmMode::pack;
  return s;
}

// ---------------------------------------------------------------------------------------------- sbatch arguments

TEST(SlurmPack, SbatchArgumentsAskForOneAllocation) {
  SlurmSubmission s = pack_submission("/study dir/100%/slurm", 5);
  s.ranks = 3;
  s.comment = "demsa:6553f100-0000abcd";
  s.settings.partition = "short";
  s.settings.account = "proj1";
  s.settings.time_limit = "00:10:00";
  s.settings.throttle = 2;
  s.settings.sbatch_options = {"--mem-per-cpu=2G", "--time=12:00:00"};
  // 5 cases, 2 at a time: 3 waves of at most 10 min, plus a minute each
  const std::vector<std::string> expected{"--parsable",
                                          "--job-name=demsa-x",
                                          "--ntasks=2",
                                          "--cpus-per-task=3",
                                          "--chdir=/study dir/100%/slurm",
                                          "--output=/study dir/100%%/slurm/logs/%j.out",
                                          "--comment=demsa:6553f100-0000abcd",
                                          "--time=0-00:33:00",
                                          "--partition=short",
                                          "--account=proj1",
                                          "--mem-per-cpu=2G",
                                          "--time=12:00:00"};
  EXPECT_EQ(sbatch_arguments(s), expected);
  EXPECT_EQ(pack_allocation_seconds(s), 3 * 660);

  // throttle 0: every case at once, one wave; no time limit: no --time
  s.settings.throttle = 0;
  EXPECT_EQ(pack_parallel(s), 5);
  EXPECT_EQ(pack_allocation_seconds(s), 660);
  s.settings.throttle = 9;  // never more than the cases
  EXPECT_EQ(pack_parallel(s), 5);
  s.settings.time_limit = "";
  s.settings.sbatch_options.clear();
  s.comment.clear();
  const auto args = sbatch_arguments(s);
  EXPECT_EQ(std::count_if(args.begin(), args.end(), [](const std::string& a) { return a.rfind("--time", 0) == 0; }), 0);
  EXPECT_EQ(std::count_if(args.begin(), args.end(), [](const std::string& a) { return a.rfind("--array", 0) == 0; }),
            0);
  EXPECT_NE(std::find(args.begin(), args.end(), "--ntasks=5"), args.end());

  // a long study: the allocation asks for days
  s.case_folders.resize(100);
  s.settings.throttle = 10;
  s.settings.time_limit = "1-00:00:00";
  EXPECT_EQ(format_slurm_time(pack_allocation_seconds(s)), "10-00:10:00");
  s.settings.time_limit = "soon";
  EXPECT_THROW(pack_allocation_seconds(s), std::invalid_argument);
}

TEST(SlurmPack, ArrayArgumentsAreUnchanged) {
  SlurmSubmission s = pack_submission("/w", 3);
  s.settings.mode = SlurmMode::array;
  s.settings.throttle = 2;
  s.settings.time_limit = "00:30:00";
  const std::vector<std::string> expected{"--parsable",     "--array=0-2%2", "--job-name=demsa-x",
                                          "--ntasks=1",     "--chdir=/w",    "--output=/w/logs/%A_%a.out",
                                          "--time=00:30:00"};
  EXPECT_EQ(sbatch_arguments(s), expected);
}

TEST(SlurmPack, SlurmTimes) {
  EXPECT_EQ(parse_slurm_time("90"), 5400);
  EXPECT_EQ(parse_slurm_time("2:30"), 150);
  EXPECT_EQ(parse_slurm_time("01:02:03"), 3723);
  EXPECT_EQ(parse_slurm_time("2-3"), 2 * 86400 + 3 * 3600);
  EXPECT_EQ(parse_slurm_time("2-03:04"), 2 * 86400 + 3 * 3600 + 4 * 60);
  EXPECT_EQ(parse_slurm_time("2-03:04:05"), 2 * 86400 + 3 * 3600 + 4 * 60 + 5);
  EXPECT_EQ(parse_slurm_time(" 00:10:00 "), 600);
  for (const std::string none : {"", "0", "UNLIMITED", "INFINITE"}) EXPECT_EQ(parse_slurm_time(none), 0) << none;
  for (const std::string bad : {"soon", "1:2:3:4", "1-2:3:4:5", "-5", "1:-2", "1h", "1:", ":5", "1--2", "99999999999"})
    EXPECT_FALSE(parse_slurm_time(bad).has_value()) << bad;
  EXPECT_EQ(format_slurm_time(1), "0-00:01:00");
  EXPECT_EQ(format_slurm_time(3600), "0-01:00:00");
  EXPECT_EQ(format_slurm_time(3601), "0-01:01:00");
  EXPECT_EQ(format_slurm_time(86400 * 3 + 120), "3-00:02:00");
}

TEST(SlurmPack, SqueueLineOfAJobThatIsNotAnArray) {
  // `squeue -h -r -t all -j 12 -O ArrayTaskID:16,State:24,exit_code:16` for a job without --array
  const std::string text = "N/A             FAILED                  256             \n";
  const auto job = parse_squeue_job(text);
  ASSERT_TRUE(job.has_value());
  EXPECT_EQ(job->state, "FAILED");
  EXPECT_EQ(job->wait_status, 256);
  EXPECT_TRUE(parse_squeue(text).empty());
  EXPECT_FALSE(parse_squeue_job("0 RUNNING 0\n1 PENDING 0\n").has_value());
}

TEST(SlurmPack, TimeoutSentinel) {
  const auto s = parse_sentinel("timeout host=n3 start=10 end=70.5\n0m0.000s 0m0.000s\n0m59.000s 0m1.000s\n");
  ASSERT_TRUE(s.has_value());
  EXPECT_TRUE(s->timed_out);
  EXPECT_FALSE(s->signalled);
  EXPECT_EQ(s->host, "n3");
  EXPECT_DOUBLE_EQ(s->wall_seconds, 60.5);
  EXPECT_DOUBLE_EQ(s->cpu_seconds, 60.0);
}

// ---------------------------------------------------------------------------------------------- the driver script

/// Runs a pack driver as the batch shell of allocation 77 would run: bash, SLURM_JOB_ID set, the fake srun first on
/// PATH. Each case's run.sh appends "start TIME" and "end TIME" lines to `stamps` (shared by all cases).
class PackScript : public ::testing::Test {
 protected:
  void SetUp() override {
    m_work = m_dir / "my study's dir/slurm";
    fs::create_directories(sentinel_dir(m_work));
    fs::create_directories(m_dir / "fake");
  }
  fs::path case_folder(int i) const { return m_work.parent_path() / "cases" / ("case " + std::to_string(i) + " $x"); }
  SlurmSubmission submission(int cases) const {
    SlurmSubmission s = pack_submission(m_work, cases);
    s.case_folders.clear();
    for (int i = 0; i < cases; ++i) s.case_folders.push_back(case_folder(i));
    return s;
  }
  /// run.sh of case i: marks its start and end in the stamps file, sleeps `seconds`, exits `status`.
  void write_case(int i, double seconds, int status) const {
    fs::create_directories(case_folder(i));
    write_run_sh(case_folder(i), "echo \"start $(date +%s.%N)\" >> " + util::shell_quote(stamps().string()) +
                                     "\necho \"case " + std::to_string(i) + " in $(basename \"$PWD\")\"\nsleep " +
                                     std::to_string(seconds) + "\necho \"end $(date +%s.%N)\" >> " +
                                     util::shell_quote(stamps().string()) + "\nexit " + std::to_string(status) + "\n");
  }
  fs::path stamps() const { return m_dir / "stamps"; }
  std::vector<std::string> environment() const {
    const char* path = std::getenv("PATH");
    return {"env", "SLURM_JOB_ID=77", "FAKE_SLURM_DIR=" + (m_dir / "fake").string(),
            "PATH=" + test::data_path("slurm").string() + ":" + (path != nullptr ? path : "")};
  }
  test::CommandResult run(const SlurmSubmission& s) const {
    write_file(m_work / "pack.sh", render_pack_script(s));
    std::vector<std::string> argv = environment();
    argv.push_back("bash");
    argv.push_back((m_work / "pack.sh").string());
    return test::run_command(argv);
  }
  /// The most cases that ran at once, from the stamps.
  int most_at_once() const {
    std::vector<std::pair<double, int>> events;
    std::istringstream lines(read_file(stamps()));
    std::string kind;
    double time = 0;
    while (lines >> kind >> time) events.emplace_back(time, kind == "start" ? 1 : -1);
    std::sort(events.begin(), events.end());
    int now = 0;
    int most = 0;
    for (const auto& [t, d] : events) most = std::max(most, now += d);
    return most;
  }

  TempDir m_dir;
  fs::path m_work;
};

TEST_F(PackScript, RunsAtMostParallelCasesAtOnceAndWritesEachSentinel) {
  for (int i = 0; i < 5; ++i) write_case(i, 1.0, i == 3 ? 3 : 0);
  SlurmSubmission s = submission(5);
  s.settings.throttle = 2;
  s.settings.time_limit = "00:10:00";
  s.settings.prologue = "export DEMSA_TEST_PROLOGUE=loaded";
  const auto r = run(s);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  for (int i = 0; i < 5; ++i) {
    const auto sentinel = read_sentinel(sentinel_path(m_work, "77", i));
    ASSERT_TRUE(sentinel.has_value()) << i;
    EXPECT_EQ(sentinel->exit_code, i == 3 ? 3 : 0) << i;
    EXPECT_FALSE(sentinel->signalled || sentinel->timed_out) << i;
    EXPECT_EQ(sentinel->host, "fake-node");
    EXPECT_GE(sentinel->wall_seconds, 1.0);
    EXPECT_EQ(read_file(case_folder(i) / "run.out"), fmt::format("case {} in case {} $x\n", i, i));
    EXPECT_FALSE(fs::exists(launch_failure_path(m_work, "77", i)));
  }
  EXPECT_EQ(most_at_once(), 2);
}

TEST_F(PackScript, OneRunShPerCaseWhateverTheRanks) {
  // srun starts `ranks` tasks; only task 0 runs run.sh (mpirun inside it starts the ranks)
  write_case(0, 0, 0);
  write_case(1, 0, 0);
  SlurmSubmission s = submission(2);
  s.ranks = 3;
  s.settings.throttle = 1;
  const auto r = run(s);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const std::string text = read_file(stamps());
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 4) << text;  // start + end of each of the 2 cases
  EXPECT_EQ(read_sentinel(sentinel_path(m_work, "77", 1))->exit_code, 0);
}

TEST_F(PackScript, StopsACaseAtItsTimeLimit) {
  fs::create_directories(case_folder(0));
  write_run_sh(case_folder(0), "echo started > started.txt\nsleep 30\necho not reached > after.txt\n");
  write_case(1, 0, 0);
  SlurmSubmission s = submission(2);
  s.settings.throttle = 2;
  s.settings.time_limit = "0:01";  // one second
  const auto start = std::chrono::steady_clock::now();
  const auto r = run(s);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(seconds, 15.0);
  const auto stopped = read_sentinel(sentinel_path(m_work, "77", 0));
  ASSERT_TRUE(stopped.has_value());
  EXPECT_TRUE(stopped->timed_out);
  EXPECT_GE(stopped->wall_seconds, 1.0);
  EXPECT_TRUE(fs::exists(case_folder(0) / "started.txt"));
  EXPECT_FALSE(fs::exists(case_folder(0) / "after.txt"));
  const auto quick = read_sentinel(sentinel_path(m_work, "77", 1));
  ASSERT_TRUE(quick.has_value());
  EXPECT_EQ(quick->exit_code, 0);
  EXPECT_FALSE(quick->timed_out);
}

TEST_F(PackScript, TermStopsTheRunningCasesAndStartsNoMore) {
  fs::create_directories(case_folder(0));
  write_run_sh(case_folder(0), "echo started > started.txt\nsleep 60\necho not reached > after.txt\n");
  write_case(1, 0, 0);
  write_case(2, 0, 0);
  SlurmSubmission s = submission(3);
  s.settings.throttle = 1;
  write_file(m_work / "pack.sh", render_pack_script(s));
  const std::vector<std::string> env = environment();
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::setpgid(0, 0);
    for (size_t i = 1; i < env.size(); ++i) ::putenv(const_cast<char*>(env[i].c_str()));
    const std::string script = (m_work / "pack.sh").string();
    ::execlp("bash", "bash", script.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  for (int i = 0; i < 200 && !fs::exists(case_folder(0) / "started.txt"); ++i)
    std::this_thread::sleep_for(milliseconds(50));
  ASSERT_TRUE(fs::exists(case_folder(0) / "started.txt"));
  ::kill(-pid, SIGTERM);  // as SLURM does on scancel and at the allocation's end: every process of the job
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 143);
  std::this_thread::sleep_for(milliseconds(300));
  const auto stopped = read_sentinel(sentinel_path(m_work, "77", 0));
  ASSERT_TRUE(stopped.has_value());
  EXPECT_TRUE(stopped->signalled);
  EXPECT_FALSE(fs::exists(case_folder(0) / "after.txt"));
  for (int i : {1, 2}) {
    EXPECT_FALSE(fs::exists(sentinel_path(m_work, "77", i))) << i;
    EXPECT_FALSE(fs::exists(case_folder(i) / "run.out")) << i;
  }
  EXPECT_FALSE(fs::exists(launch_failure_path(m_work, "77", 0)));
  ::kill(-pid, SIGKILL);
}

TEST_F(PackScript, SrunThatCannotStartTheStepLeavesALaunchFailure) {
  write_case(0, 0, 0);
  write_file(m_dir / "fake/srun_fail", "");
  const auto r = run(submission(1));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("srun ended with status 1 before case 0"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(sentinel_path(m_work, "77", 0)));
  const auto failed = read_sentinel(launch_failure_path(m_work, "77", 0));
  ASSERT_TRUE(failed.has_value());
  EXPECT_EQ(failed->exit_code, 1);
  EXPECT_FALSE(fs::exists(case_folder(0) / "run.out"));
}

TEST_F(PackScript, MissingCaseFolderFailsThatCaseOnly) {
  write_case(1, 0, 0);
  const auto r = run(submission(2));  // case 0's folder does not exist
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_sentinel(sentinel_path(m_work, "77", 0))->exit_code, 126);
  EXPECT_EQ(read_sentinel(sentinel_path(m_work, "77", 1))->exit_code, 0);
}

// ---------------------------------------------------------------------------------------------- the executor

class FakePack : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(m_dir / "fake");
    ::setenv("FAKE_SLURM_DIR", (m_dir / "fake").c_str(), 1);
    m_study = m_dir / "study dir";
    fs::create_directories(m_study);
  }
  void TearDown() override { ::unsetenv("FAKE_SLURM_DIR"); }

  SlurmExecutorOptions options() const {
    SlurmExecutorOptions o;
    o.commands.sbatch = test::data_path("slurm/sbatch").string();
    o.commands.squeue = test::data_path("slurm/squeue").string();
    o.commands.scancel = test::data_path("slurm/scancel").string();
    o.commands.timeout = milliseconds(10000);
    o.query_interval = milliseconds(20);
    o.sentinel_interval = milliseconds(10);
    o.sentinel_grace = milliseconds(300);
    o.cancel_wait = milliseconds(2000);
    o.job_name = "demsa-test";
    o.settings.mode = SlurmMode::pack;
    o.settings.throttle = 2;
    o.settings.time_limit = "00:10:00";
    return o;
  }
  std::vector<CaseTask> make_tasks(int n) const {
    std::vector<CaseTask> tasks;
    for (int i = 0; i < n; ++i) {
      CaseTask t;
      t.sample = i;
      t.folder = m_study / "cases" / ("00000" + std::to_string(i));
      fs::create_directories(t.folder);
      tasks.push_back(t);
    }
    return tasks;
  }
  fs::path fake() const { return m_dir / "fake"; }
  void set_squeue(const std::string& job, const std::string& lines) const {
    write_file(fake() / "jobs" / job / "squeue", lines);
  }
  void write_sentinel(const std::string& job, int index, const std::string& text) const {
    write_file(sentinel_path(m_study / "slurm", job, index), text);
  }
  static std::vector<FinishedCase> collect(SlurmExecutor& e, size_t n, milliseconds limit = milliseconds(5000)) {
    std::vector<FinishedCase> done;
    const auto end = std::chrono::steady_clock::now() + limit;
    while (done.size() < n && std::chrono::steady_clock::now() < end) {
      auto got = e.poll(milliseconds(50));
      done.insert(done.end(), got.begin(), got.end());
    }
    return done;
  }
  static const FinishedCase* find(const std::vector<FinishedCase>& done, int sample) {
    for (const auto& f : done)
      if (f.task.sample == sample) return &f;
    return nullptr;
  }

  TempDir m_dir;
  fs::path m_study;
};

TEST_F(FakePack, OneAllocationAtATimeAndEachCaseOnce) {
  SlurmExecutor executor(options(), m_study);
  EXPECT_GT(executor.free_slots(), 1000);
  const auto tasks = make_tasks(3);
  const auto reserved = executor.reserve_ids(tasks);
  const auto ids = executor.submit(tasks);
  EXPECT_EQ(ids, (std::vector<std::string>{"100_0", "100_1", "100_2"}));
  const std::string args = read_file(fake() / "jobs/100/args");
  EXPECT_EQ(args.find("--array"), std::string::npos) << args;
  EXPECT_NE(args.find("--ntasks=2\n--cpus-per-task=1\n"), std::string::npos) << args;
  EXPECT_NE(args.find("--time=0-00:22:00\n"), std::string::npos) << args;
  EXPECT_NE(args.find("--comment=demsa:" + parse_pending_slurm_id(reserved[0])->token + "\n"), std::string::npos);
  const std::string script = read_file(fake() / "jobs/100/script");
  EXPECT_NE(script.find("srun --exclusive"), std::string::npos);
  EXPECT_NE(script.find("'" + (m_study / "cases/000002").string() + "'"), std::string::npos) << script;
  EXPECT_TRUE(fs::exists(m_study / "slurm/logs"));
  EXPECT_EQ(executor.free_slots(), 0) << "no second allocation while the first one is in flight";

  set_squeue("100", "N/A RUNNING 0\n");
  EXPECT_TRUE(executor.poll(milliseconds(50)).empty());
  write_sentinel("100", 0, "exit 0 host=n1 start=10 end=14.5\n0m0.000s 0m0.000s\n0m3.000s 0m0.500s\n");
  write_sentinel("100", 1, "timeout host=n1 start=10 end=610\n");
  auto done = collect(executor, 2);
  ASSERT_EQ(done.size(), 2u);
  EXPECT_EQ(find(done, 0)->exit.exit_code, 0);
  EXPECT_DOUBLE_EQ(find(done, 0)->exit.cpu_seconds, 3.5);
  EXPECT_TRUE(find(done, 1)->exit.timed_out) << find(done, 1)->exit.detail;
  EXPECT_EQ(executor.free_slots(), 0);

  // the driver died (exit 1) without running case 2: after the grace period, a failure with its status
  set_squeue("100", "N/A FAILED 256\n");
  EXPECT_TRUE(executor.poll(milliseconds(100)).empty()) << "a late sentinel has the grace period to show up";
  done = collect(executor, 1);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].exit.exit_code, 1) << done[0].exit.detail;
  EXPECT_NE(done[0].exit.detail.find("without the case's sentinel"), std::string::npos) << done[0].exit.detail;
  EXPECT_EQ(executor.in_flight(), 0);
  EXPECT_GT(executor.free_slots(), 0);
  EXPECT_TRUE(executor.poll(milliseconds(10)).empty());
}

TEST_F(FakePack, EndOfTheAllocation) {
  SlurmExecutor executor(options(), m_study);
  executor.submit(make_tasks(3));
  // the allocation reached its walltime: the running case was stopped, the others never started
  write_sentinel("100", 0, "exit 0 host=n1 start=1 end=2\n");
  write_sentinel("100", 1, "signal TERM host=n1 start=1 end=2\n");
  set_squeue("100", "N/A TIMEOUT 0\n");
  const auto done = collect(executor, 3);
  ASSERT_EQ(done.size(), 3u);
  EXPECT_EQ(find(done, 0)->exit.exit_code, 0);
  EXPECT_TRUE(find(done, 1)->exit.timed_out) << find(done, 1)->exit.detail;
  EXPECT_TRUE(find(done, 2)->exit.lost) << find(done, 2)->exit.detail;
  EXPECT_NE(find(done, 2)->exit.detail.find("before the case started"), std::string::npos);
}

TEST_F(FakePack, LaunchFailureCountsAfterTheGraceUnlessTheSentinelShowsUp) {
  SlurmExecutor executor(options(), m_study);
  executor.submit(make_tasks(2));
  set_squeue("100", "N/A RUNNING 0\n");
  write_file(launch_failure_path(m_study / "slurm", "100", 0), "exit 1 host=n1 start=1 end=2\n");
  write_file(launch_failure_path(m_study / "slurm", "100", 1), "exit 1 host=n1 start=1 end=2\n");
  EXPECT_TRUE(executor.poll(milliseconds(100)).empty());
  write_sentinel("100", 1, "exit 0 host=n1 start=1 end=3\n");  // the step's own sentinel, seen late
  const auto done = collect(executor, 2);
  ASSERT_EQ(done.size(), 2u);
  EXPECT_EQ(find(done, 0)->exit.exit_code, 1);
  EXPECT_NE(find(done, 0)->exit.detail.find("srun ended with status 1"), std::string::npos);
  EXPECT_EQ(find(done, 1)->exit.exit_code, 0);
  EXPECT_DOUBLE_EQ(find(done, 1)->exit.wall_seconds, 2.0);
}

TEST_F(FakePack, CancelAllCancelsTheAllocation) {
  SlurmExecutor executor(options(), m_study);
  executor.submit(make_tasks(3));
  set_squeue("100", "N/A RUNNING 0\n");
  write_sentinel("100", 0, "exit 0 host=n1 start=1 end=2\n");
  ASSERT_EQ(collect(executor, 1).size(), 1u);
  write_sentinel("100", 1, "signal TERM host=n1 start=1 end=2\n");  // what the running step writes on scancel
  executor.cancel_all();
  EXPECT_EQ(read_file(fake() / "scancel_args"), "100\n");
  const auto cancelled = executor.poll(milliseconds(0));
  ASSERT_EQ(cancelled.size(), 2u);
  for (const auto& c : cancelled) EXPECT_TRUE(c.exit.cancelled) << c.exit.detail;
  EXPECT_EQ(executor.in_flight(), 0);
}

TEST_F(FakePack, AdoptedAfterARestartAndNothingSubmittedMeanwhile) {
  const auto tasks = make_tasks(2);
  std::vector<std::string> ids;
  {
    SlurmExecutor first(options(), m_study);
    ids = first.submit(tasks);
  }  // demsa killed: the allocation runs on
  SlurmExecutor second(options(), m_study);
  second.adopt({{tasks[0], ids[0]}, {tasks[1], ids[1]}});
  EXPECT_EQ(second.free_slots(), 0) << "the missing cases wait for the adopted allocation";
  set_squeue("100", "N/A RUNNING 0\n");
  write_sentinel("100", 0, "exit 4 host=n1 start=1 end=2\n");
  auto done = collect(second, 1);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].exit.exit_code, 4);
  // the allocation was cancelled by hand before case 1 started: it runs again
  set_squeue("100", "N/A CANCELLED 0\n");
  done = collect(second, 1);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_TRUE(done[0].exit.cancelled) << done[0].exit.detail;
  EXPECT_EQ(read_file(fake() / "next_id"), "101\n") << "nothing was submitted again";
  EXPECT_GT(second.free_slots(), 0);
}

TEST_F(FakePack, SplitsIntoAllocationsOfMaxPackSize) {
  auto o = options();
  o.max_pack_size = 2;
  SlurmExecutor executor(o, m_study);
  const auto ids = executor.submit(make_tasks(3));
  EXPECT_EQ(ids, (std::vector<std::string>{"100_0", "100_1", "101_0"}));
  EXPECT_NE(read_file(fake() / "jobs/101/args").find("--ntasks=1\n"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------- the setting

TEST(SlurmPack, ModeSettingIsAnExecutionSetting) {
  const std::string base =
      "[study]\nname = \"m\"\nexperiment = \"pile\"\n[design]\nmethod = \"lhs\"\nsamples = 8\n[parameters]\n"
      "mu_pp = { low = 0.2, high = 0.8 }\n[run]\nexecutor = \"slurm\"\n";
  const StudyConfig plain = parse_study(base, "study.toml");
  EXPECT_EQ(plain.run.slurm.mode, SlurmMode::array);
  const StudyConfig array = parse_study(base + "[run.slurm]\nmode = \"array\"\n", "study.toml");
  const StudyConfig pack = parse_study(base + "[run.slurm]\nmode = \"pack\"\n", "study.toml");
  EXPECT_EQ(pack.run.slurm.mode, SlurmMode::pack);
  // the cases do not depend on how SLURM runs them: same design hash, nothing reported changed
  EXPECT_EQ(design_hash(pack), design_hash(plain));
  EXPECT_EQ(design_hash(array), design_hash(plain));
  EXPECT_TRUE(settings_table().changed(plain, pack).empty());
  const std::string message =
      test::message_of<UserError>([&] { parse_study(base + "[run.slurm]\nmode = \"bulk\"\n", "study.toml"); });
  EXPECT_NE(message.find("study.toml:12"), std::string::npos) << message;
  EXPECT_NE(message.find("bulk"), std::string::npos) << message;
  EXPECT_NE(message.find("array, pack"), std::string::npos) << message;
}

TEST(SlurmPack, FactoryRefusesATimeLimitItCannotRead) {
  const char* old = std::getenv("PATH");
  const std::string saved = old != nullptr ? old : "";
  ::setenv("PATH", (test::data_path("slurm").string() + ":" + saved).c_str(), 1);
  RunSettings run;
  run.executor = ExecutorKind::slurm;
  run.slurm.mode = SlurmMode::pack;
  run.slurm.time_limit = "two hours";
  const std::string message = test::message_of<UserError>([&] { make_slurm_executor(run, "/tmp"); });
  EXPECT_NE(message.find("[run.slurm] time_limit = \"two hours\""), std::string::npos) << message;
  run.slurm.mode = SlurmMode::array;  // an array passes it to sbatch as it is
  EXPECT_NE(make_slurm_executor(run, "/tmp"), nullptr);
  ::setenv("PATH", saved.c_str(), 1);
  SlurmExecutorOptions o;
  o.settings.mode = SlurmMode::pack;
  o.settings.time_limit = "x";
  EXPECT_NE(test::message_of<std::invalid_argument>([&] { o.validate(); }).find("settings.time_limit = \"x\""),
            std::string::npos);
}

}  // namespace
}  // namespace demsa
