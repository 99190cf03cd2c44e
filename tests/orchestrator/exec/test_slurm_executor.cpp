// The SLURM executor against fake sbatch/squeue/scancel (tests/data/slurm/): the edge cases a real cluster
// rarely shows on demand. The test plays the cluster: it writes each job's squeue answer and the sentinels.
#include "orchestrator/exec/slurm/executor.hpp"

#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <signal.h>
#include <stdlib.h>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <thread>

namespace demsa {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::exec;
namespace {
namespace fs = std::filesystem;
using std::chrono::milliseconds;
using test::read_file;
using test::TempDir;
using test::write_file;

class FakeSlurm : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(m_dir / "fake");
    ::setenv("FAKE_SLURM_DIR", (m_dir / "fake").c_str(), 1);
    m_study = m_dir / "study with spaces";
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
    o.squeue_outage_limit = milliseconds(600);
    o.cancel_wait = milliseconds(2000);
    o.job_name = "demsa-test";
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

  /// A demsa that reserves the ids of `tasks`, submits them and dies before it stores the real ids: the
  /// provisional ids it reserved.
  std::vector<std::string> submit_then_die(const std::vector<CaseTask>& tasks) const {
    SlurmExecutor first(options(), m_study);
    std::vector<std::string> reserved = first.reserve_ids(tasks);
    first.submit(tasks);
    return reserved;
  }

  fs::path fake() const { return m_dir / "fake"; }
  void set_squeue(const std::string& job, const std::string& lines) const {
    write_file(fake() / "jobs" / job / "squeue", lines);
  }
  void write_sentinel(const std::string& job, int task, const std::string& text) const {
    write_file(sentinel_path(m_study / "slurm", job, task), text);
  }
  int squeue_calls() const {
    if (!fs::exists(fake() / "squeue_calls")) return 0;
    const std::string text = read_file(fake() / "squeue_calls");
    return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  }

  TempDir m_dir;
  fs::path m_study;
};

const FinishedCase* find_sample(const std::vector<FinishedCase>& done, int sample) {
  for (const auto& f : done)
    if (f.task.sample == sample) return &f;
  return nullptr;
}

// Polls until `count` tasks came back or `limit` passes.
std::vector<FinishedCase> collect(SlurmExecutor& executor, size_t count, milliseconds limit = milliseconds(5000)) {
  std::vector<FinishedCase> done;
  const auto end = std::chrono::steady_clock::now() + limit;
  while (done.size() < count && std::chrono::steady_clock::now() < end) {
    auto got = executor.poll(milliseconds(100));
    done.insert(done.end(), got.begin(), got.end());
  }
  return done;
}

TEST_F(FakeSlurm, SubmitsOneArrayAndCollectsSentinels) {
  auto o = options();
  o.ranks = 2;
  o.settings.partition = "short";
  o.settings.throttle = 2;
  SlurmExecutor executor(o, m_study);
  const auto ids = executor.submit(make_tasks(3));
  EXPECT_EQ(ids, (std::vector<std::string>{"100_0", "100_1", "100_2"}));
  EXPECT_EQ(executor.in_flight(), 3);

  const std::string args = read_file(fake() / "jobs/100/args");
  EXPECT_NE(args.find("--array=0-2%2\n"), std::string::npos) << args;
  EXPECT_NE(args.find("--ntasks=2\n"), std::string::npos);
  EXPECT_NE(args.find("--partition=short\n"), std::string::npos);
  EXPECT_NE(args.find("--job-name=demsa-test\n"), std::string::npos);
  const std::string script = read_file(fake() / "jobs/100/script");
  EXPECT_NE(script.find("'" + (m_study / "cases/000001").string() + "'"), std::string::npos) << script;

  set_squeue("100", "0 RUNNING 0\n1 RUNNING 0\n2 PENDING 0\n");
  EXPECT_TRUE(executor.poll(milliseconds(50)).empty());
  write_sentinel("100", 0, "exit 0 host=n1 start=10 end=14.5\n0m0.000s 0m0.000s\n0m3.000s 0m0.500s\n");
  write_sentinel("100", 1, "exit 2 host=n2 start=10 end=11\n");
  const auto done = collect(executor, 2);
  ASSERT_EQ(done.size(), 2u);
  const auto* first = find_sample(done, 0);
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(first->exit.exit_code, 0);
  EXPECT_EQ(first->exit.host, "n1");
  EXPECT_DOUBLE_EQ(first->exit.wall_seconds, 4.5);
  EXPECT_DOUBLE_EQ(first->exit.cpu_seconds, 3.5);
  const auto* second = find_sample(done, 1);
  ASSERT_NE(second, nullptr);
  EXPECT_EQ(second->exit.exit_code, 2);
  EXPECT_FALSE(second->exit.cancelled || second->exit.lost || second->exit.timed_out);
  EXPECT_EQ(executor.in_flight(), 1);

  write_sentinel("100", 2, "exit 0 host=n1 start=1 end=2\n");
  const auto last = collect(executor, 1);
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(last[0].task.sample, 2);
  EXPECT_EQ(executor.in_flight(), 0);
  EXPECT_TRUE(executor.poll(milliseconds(10)).empty());  // each task comes back exactly once
}

TEST_F(FakeSlurm, TaskVanishingWhilePendingIsLost) {
  SlurmExecutor executor(options(), m_study);
  executor.submit(make_tasks(2));
  set_squeue("100", "0 PENDING 0\n1 PENDING 0\n");
  EXPECT_TRUE(executor.poll(milliseconds(100)).empty());
  // `scancel 100_1` on a pending task removes it completely: no squeue record, no sentinel
  set_squeue("100", "0 PENDING 0\n");
  const auto done = collect(executor, 1);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].task.sample, 1);
  EXPECT_TRUE(done[0].exit.lost);
  EXPECT_EQ(done[0].exit.exit_code, -1);
  EXPECT_NE(done[0].exit.detail.find("gone from squeue"), std::string::npos) << done[0].exit.detail;
  EXPECT_EQ(executor.in_flight(), 1);
}

TEST_F(FakeSlurm, FinalStateWithoutSentinelWaitsForTheGraceThenUsesSqueue) {
  auto o = options();
  o.sentinel_grace = milliseconds(400);
  SlurmExecutor executor(o, m_study);
  executor.submit(make_tasks(2));
  set_squeue("100", "0 FAILED 256\n1 COMPLETED 0\n");
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(executor.poll(milliseconds(150)).empty());  // within the grace: the sentinel may still show up
  write_sentinel("100", 1, "exit 0 host=n1 start=1 end=2\n");
  auto done = collect(executor, 2);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(done.size(), 2u);
  const auto* missing = find_sample(done, 0);
  ASSERT_NE(missing, nullptr);
  EXPECT_EQ(missing->exit.exit_code, 1);  // wait status 256 = exit 1
  EXPECT_NE(missing->exit.detail.find("no sentinel"), std::string::npos) << missing->exit.detail;
  EXPECT_GE(seconds, 0.4);
  const auto* present = find_sample(done, 1);
  ASSERT_NE(present, nullptr);
  EXPECT_EQ(present->exit.exit_code, 0);
  EXPECT_EQ(present->exit.host, "n1");
}

TEST_F(FakeSlurm, SignalInWaitStatusWithoutSentinel) {
  auto o = options();
  o.sentinel_grace = milliseconds(0);
  SlurmExecutor executor(o, m_study);
  executor.submit(make_tasks(1));
  set_squeue("100", "0 FAILED 9\n");  // killed by SIGKILL
  const auto done = collect(executor, 1);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].exit.signal, SIGKILL);
  EXPECT_EQ(done[0].exit.exit_code, -1);
}

TEST_F(FakeSlurm, SqueueFailingKeepsTasksThenThrowsAfterTheOutageLimit) {
  SlurmExecutor executor(options(), m_study);
  executor.submit(make_tasks(2));
  write_file(fake() / "squeue_fail", "");
  EXPECT_TRUE(executor.poll(milliseconds(100)).empty());
  // sentinels are still collected while squeue fails
  write_sentinel("100", 0, "exit 0 host=n1 start=1 end=2\n");
  auto done = collect(executor, 1, milliseconds(400));
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].exit.exit_code, 0);
  // the other task has no sentinel; squeue keeps failing past squeue_outage_limit (600 ms)
  try {
    collect(executor, 1, milliseconds(3000));
    FAIL() << "poll() did not throw";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("Unable to contact slurm controller"), std::string::npos) << message;
    EXPECT_NE(message.find("stay submitted"), std::string::npos) << message;
  }
  EXPECT_EQ(executor.in_flight(), 1);
}

TEST_F(FakeSlurm, SqueueRecoveringWithinTheLimitIsHarmless) {
  SlurmExecutor executor(options(), m_study);
  executor.submit(make_tasks(1));
  write_file(fake() / "squeue_fail", "");
  EXPECT_TRUE(executor.poll(milliseconds(300)).empty());
  fs::remove(fake() / "squeue_fail");
  set_squeue("100", "0 RUNNING 0\n");
  EXPECT_TRUE(executor.poll(milliseconds(500)).empty());  // past the 600 ms from the first failure: no throw
  EXPECT_EQ(executor.in_flight(), 1);
  write_sentinel("100", 0, "exit 4 host=n1 start=1 end=2\n");
  const auto done = collect(executor, 1);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].exit.exit_code, 4);
}

TEST_F(FakeSlurm, SqueueIsNotCalledMoreOftenThanTheInterval) {
  auto o = options();
  o.query_interval = milliseconds(400);
  SlurmExecutor executor(o, m_study);
  executor.submit(make_tasks(1));
  set_squeue("100", "0 RUNNING 0\n");
  EXPECT_TRUE(executor.poll(milliseconds(1000)).empty());
  // at t = 0, 400, 800 ms (and at most one more at the edge)
  EXPECT_GE(squeue_calls(), 2);
  EXPECT_LE(squeue_calls(), 4);
}

TEST_F(FakeSlurm, SbatchFailingThrowsWithItsMessageAndStartsNothing) {
  SlurmExecutor executor(options(), m_study);
  write_file(fake() / "sbatch_fail", "sbatch: error: invalid partition specified: nope\n");
  try {
    executor.submit(make_tasks(2));
    FAIL() << "submit() did not throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("invalid partition specified: nope"), std::string::npos) << e.what();
  }
  EXPECT_EQ(executor.in_flight(), 0);
}

TEST_F(FakeSlurm, SplitsLargeSubmissionsIntoArraysOfMaxSize) {
  auto o = options();
  o.max_array_size = 2;
  SlurmExecutor executor(o, m_study);
  EXPECT_EQ(executor.free_slots(), 2);
  const auto ids = executor.submit(make_tasks(3));
  EXPECT_EQ(ids, (std::vector<std::string>{"100_0", "100_1", "101_0"}));
  EXPECT_NE(read_file(fake() / "jobs/101/args").find("--array=0-0\n"), std::string::npos);
}

TEST_F(FakeSlurm, TermSentinelWithTimeoutIsATimeoutAndWithCancelledACancellation) {
  SlurmExecutor executor(options(), m_study);
  executor.submit(make_tasks(3));
  set_squeue("100", "0 TIMEOUT 36608\n1 CANCELLED 0\n2 RUNNING 0\n");
  for (int i = 0; i < 3; ++i) write_sentinel("100", i, "signal TERM host=n1 start=1 end=5\n");
  const auto done = collect(executor, 3);
  ASSERT_EQ(done.size(), 3u);
  EXPECT_TRUE(find_sample(done, 0)->exit.timed_out);
  EXPECT_TRUE(find_sample(done, 1)->exit.cancelled);
  // TERM from elsewhere while squeue still says RUNNING: after the grace it is a signal
  EXPECT_EQ(find_sample(done, 2)->exit.signal, SIGTERM);
}

TEST_F(FakeSlurm, ClusterStatesWithoutSentinel) {
  SlurmExecutor executor(options(), m_study);
  executor.submit(make_tasks(4));
  set_squeue("100", "0 NODE_FAIL 0\n1 OUT_OF_MEMORY 0\n2 TIMEOUT 0\n3 PREEMPTED 0\n");
  const auto done = collect(executor, 4);
  ASSERT_EQ(done.size(), 4u);
  EXPECT_TRUE(find_sample(done, 0)->exit.lost);
  EXPECT_EQ(find_sample(done, 1)->exit.signal, SIGKILL);
  EXPECT_TRUE(find_sample(done, 2)->exit.timed_out);
  EXPECT_TRUE(find_sample(done, 3)->exit.lost);
}

TEST_F(FakeSlurm, CancelAllScancelsAndReturnsTasksAsCancelled) {
  SlurmExecutor executor(options(), m_study);
  executor.submit(make_tasks(3));
  set_squeue("100", "0 COMPLETED 0\n1 RUNNING 0\n2 PENDING 0\n");
  write_sentinel("100", 0, "exit 0 host=n1 start=1 end=2\n");
  const auto first = collect(executor, 1);
  ASSERT_EQ(first.size(), 1u);
  // the running task's trap writes its sentinel when it gets SIGTERM
  write_sentinel("100", 1, "signal TERM host=n1 start=1 end=3\n");
  executor.cancel_all();
  EXPECT_EQ(read_file(fake() / "scancel_args"), "100\n");
  EXPECT_EQ(executor.in_flight(), 2);
  const auto done = executor.poll(milliseconds(0));
  ASSERT_EQ(done.size(), 2u);
  EXPECT_TRUE(find_sample(done, 1)->exit.cancelled);
  EXPECT_TRUE(find_sample(done, 2)->exit.cancelled);
  EXPECT_EQ(executor.in_flight(), 0);
}

TEST_F(FakeSlurm, AdoptFollowsEarlierTasksAndReportsBadIdsLost) {
  SlurmExecutor executor(options(), m_study);
  const auto tasks = make_tasks(2);
  fs::create_directories(fake() / "jobs/57");
  set_squeue("57", "3 RUNNING 0\n");
  executor.adopt({{tasks[0], "57_3"}, {tasks[1], "not-a-slurm-id"}});
  EXPECT_EQ(executor.in_flight(), 2);
  auto done = executor.poll(milliseconds(50));
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].task.sample, 1);
  EXPECT_TRUE(done[0].exit.lost);
  write_sentinel("57", 3, "exit 0 host=n3 start=1 end=2\n");
  done = collect(executor, 1);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].task.sample, 0);
  EXPECT_EQ(done[0].exit.exit_code, 0);
}

TEST_F(FakeSlurm, AdoptedJobForgottenByTheControllerUsesSentinels) {
  SlurmExecutor executor(options(), m_study);
  const auto tasks = make_tasks(2);
  // job 58 is unknown to the controller (squeue: "Invalid job id specified"): one task left a sentinel
  write_sentinel("58", 0, "exit 0 host=n3 start=1 end=2\n");
  executor.adopt({{tasks[0], "58_0"}, {tasks[1], "58_1"}});
  const auto done = collect(executor, 2);
  ASSERT_EQ(done.size(), 2u);
  EXPECT_EQ(find_sample(done, 0)->exit.exit_code, 0);
  EXPECT_TRUE(find_sample(done, 1)->exit.lost);
}

TEST_F(FakeSlurm, StaleSentinelOfAnEarlierClusterIsIgnored) {
  // a SLURM whose state was wiped gives out job id 100 again: an old sentinel 100_0 must not count
  write_sentinel("100", 0, "exit 0 host=old start=1 end=2\n");
  const fs::path old = sentinel_path(m_study / "slurm", "100", 0);
  fs::last_write_time(old, fs::file_time_type::clock::now() - std::chrono::hours(1));
  SlurmExecutor executor(options(), m_study);
  executor.submit(make_tasks(1));
  set_squeue("100", "0 RUNNING 0\n");
  EXPECT_TRUE(executor.poll(milliseconds(100)).empty());
  EXPECT_FALSE(fs::exists(old));
}

// The token of a provisional id "pending:TOKEN:INDEX".
std::string token_of(const std::string& id) {
  const auto pending = parse_pending_slurm_id(id);
  EXPECT_TRUE(pending.has_value()) << id;
  return pending ? pending->token : std::string{};
}

TEST_F(FakeSlurm, ReservedIdsMarkTheArraysSubmittedNext) {
  auto o = options();
  o.max_array_size = 2;
  SlurmExecutor executor(o, m_study);
  const auto tasks = make_tasks(3);
  const auto reserved = executor.reserve_ids(tasks);
  ASSERT_EQ(reserved.size(), 3u);
  const std::string first = token_of(reserved[0]);
  const std::string second = token_of(reserved[2]);
  EXPECT_EQ(reserved[0], "pending:" + first + ":0");
  EXPECT_EQ(reserved[1], "pending:" + first + ":1");
  EXPECT_EQ(reserved[2], "pending:" + second + ":0");
  EXPECT_NE(first, second);
  EXPECT_FALSE(fs::exists(fake() / "next_id")) << "reserving ids submits nothing";

  EXPECT_EQ(executor.submit(tasks), (std::vector<std::string>{"100_0", "100_1", "101_0"}));
  EXPECT_NE(read_file(fake() / "jobs/100/args").find("--comment=demsa:" + first + "\n"), std::string::npos);
  EXPECT_NE(read_file(fake() / "jobs/101/args").find("--comment=demsa:" + second + "\n"), std::string::npos);

  // A submit() of other tasks than those reserved gets a token of its own.
  executor.submit(make_tasks(1));
  const std::string args = read_file(fake() / "jobs/102/args");
  EXPECT_NE(args.find("--comment=demsa:"), std::string::npos) << args;
  EXPECT_EQ(args.find(first), std::string::npos) << args;
}

TEST_F(FakeSlurm, AdoptedProvisionalIdsFindTheArrayByItsToken) {
  const auto tasks = make_tasks(2);
  const std::vector<std::string> reserved = submit_then_die(tasks);  // before it stores 100_0 and 100_1
  SlurmExecutor executor(options(), m_study);
  executor.adopt({{tasks[0], reserved[0]}, {tasks[1], reserved[1]}});
  EXPECT_EQ(executor.in_flight(), 2);
  set_squeue("100", "0 RUNNING 0\n1 PENDING 0\n");
  EXPECT_TRUE(executor.poll(milliseconds(100)).empty());
  const auto learned = executor.take_learned_ids();
  ASSERT_EQ(learned.size(), 2u);
  EXPECT_EQ(learned[0].task.sample, 0);
  EXPECT_EQ(learned[0].job_id, "100_0");
  EXPECT_EQ(learned[1].task.sample, 1);
  EXPECT_EQ(learned[1].job_id, "100_1");
  EXPECT_TRUE(executor.take_learned_ids().empty()) << "each id is handed out once";

  write_sentinel("100", 1, "exit 3 host=n2 start=1 end=2\n");
  write_sentinel("100", 0, "exit 0 host=n1 start=1 end=2\n");
  const auto done = collect(executor, 2);
  ASSERT_EQ(done.size(), 2u);
  EXPECT_EQ(find_sample(done, 0)->exit.exit_code, 0);
  EXPECT_EQ(find_sample(done, 1)->exit.exit_code, 3);
  EXPECT_EQ(read_file(fake() / "next_id"), "101\n") << "nothing was submitted again";
}

TEST_F(FakeSlurm, ProvisionalIdNotInSqueueIsLostOnlyOnceAnSbatchCannotStillSubmitIt) {
  auto o = options();
  o.commands.timeout = milliseconds(1500);
  SlurmExecutor executor(o, m_study);
  const auto tasks = make_tasks(2);
  // an old token (made at Unix time 1) and one made now, neither in squeue
  const std::string fresh = make_submission_token(static_cast<double>(std::time(nullptr)));
  executor.adopt({{tasks[0], "pending:1-0badc0de:4"}, {tasks[1], "pending:" + fresh + ":0"}});
  const auto start = std::chrono::steady_clock::now();
  auto done = collect(executor, 1, milliseconds(400));
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].task.sample, 0);
  EXPECT_TRUE(done[0].exit.lost);
  EXPECT_NE(done[0].exit.detail.find("no job with comment 'demsa:1-0badc0de'"), std::string::npos)
      << done[0].exit.detail;
  // the fresh one: an sbatch of the killed demsa may still be running for up to the command timeout
  done = collect(executor, 1, milliseconds(5000));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].task.sample, 1);
  EXPECT_TRUE(done[0].exit.lost);
  EXPECT_GE(seconds, 0.5);
  EXPECT_LT(seconds, 4.0);
  EXPECT_TRUE(executor.take_learned_ids().empty());
  EXPECT_FALSE(fs::exists(fake() / "next_id"));
}

TEST_F(FakeSlurm, ProvisionalIdWhileSqueueFailsStaysInFlight) {
  const auto tasks = make_tasks(1);
  const std::vector<std::string> reserved = submit_then_die(tasks);
  write_file(fake() / "squeue_fail", "");
  SlurmExecutor executor(options(), m_study);
  executor.adopt({{tasks[0], reserved[0]}});
  EXPECT_TRUE(executor.poll(milliseconds(300)).empty());
  EXPECT_EQ(executor.in_flight(), 1);
  // cancel_all() cannot find its job: the task stays in flight (never reported cancelled, so never resubmitted)
  executor.cancel_all();
  EXPECT_FALSE(fs::exists(fake() / "scancel_args"));
  EXPECT_EQ(executor.in_flight(), 1);
  try {
    collect(executor, 1, milliseconds(3000));
    FAIL() << "poll() did not throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("Unable to contact slurm controller"), std::string::npos) << e.what();
  }
  EXPECT_EQ(executor.in_flight(), 1);
  EXPECT_TRUE(executor.take_learned_ids().empty());

  // the controller answers again: found, and cancel_all() now cancels it
  fs::remove(fake() / "squeue_fail");
  set_squeue("100", "0 RUNNING 0\n");
  executor.cancel_all();
  EXPECT_EQ(read_file(fake() / "scancel_args"), "100\n");
  const auto learned = executor.take_learned_ids();
  ASSERT_EQ(learned.size(), 1u);
  EXPECT_EQ(learned[0].job_id, "100_0");
  const auto done = executor.poll(milliseconds(0));
  ASSERT_EQ(done.size(), 1u);
  EXPECT_TRUE(done[0].exit.cancelled);
  EXPECT_EQ(read_file(fake() / "next_id"), "101\n");
}

TEST(SlurmExecutor, ProvisionalIdsAndTokens) {
  const auto id = parse_pending_slurm_id("pending:6562f0a1-9c3b07de:12");
  ASSERT_TRUE(id.has_value());
  EXPECT_EQ(id->token, "6562f0a1-9c3b07de");
  EXPECT_EQ(id->index, 12);
  for (const char* bad : {"", "100_1", "pending:", "pending::3", "pending:abc:", "pending:abc:x", "pgid:1:2"})
    EXPECT_FALSE(parse_pending_slurm_id(bad).has_value()) << bad;

  const std::string token = make_submission_token(1700000000.7);
  EXPECT_EQ(token.substr(0, 9), "6553f100-");  // 1700000000 = 0x6553f100
  EXPECT_EQ(token.size(), 17u);
  EXPECT_EQ(submission_token_time(token), 1700000000.0);
  EXPECT_NE(make_submission_token(1700000000.0), make_submission_token(1700000000.0));
  EXPECT_FALSE(submission_token_time("nodash").has_value());
  EXPECT_FALSE(submission_token_time("xyz-1").has_value());
  EXPECT_EQ(submission_comment(token), "demsa:" + token);
  EXPECT_EQ(parse_pending_slurm_id("pending:" + token + ":0")->token, token);
}

TEST(SlurmExecutor, CommentInSbatchOptionsIsRefused) {
  SlurmExecutorOptions o;
  o.settings.sbatch_options = {"--mem=1G", "--comment=mine"};
  try {
    o.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("SlurmExecutorOptions.settings.sbatch_options = \"--comment=mine\""),
              std::string::npos)
        << e.what();
  }
  const char* old = std::getenv("PATH");
  const std::string saved = old != nullptr ? old : "";
  ::setenv("PATH", (test::data_path("slurm").string() + ":" + saved).c_str(), 1);
  RunSettings run;
  run.executor = ExecutorKind::slurm;
  run.slurm.sbatch_options = {"--comment", "mine"};
  try {
    make_slurm_executor(run, "/tmp");
    FAIL();
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("[run.slurm] sbatch_options: \"--comment\""), std::string::npos) << e.what();
  }
  ::setenv("PATH", saved.c_str(), 1);
}

TEST_F(FakeSlurm, OptionsFromStudySettings) {
  RunSettings run;
  run.ranks = 3;
  run.slurm.poll_interval = 2.5;
  run.slurm.account = "a1";
  const auto o = slurm_executor_options(run, m_study);
  EXPECT_EQ(o.ranks, 3);
  EXPECT_EQ(o.query_interval, milliseconds(2500));
  EXPECT_EQ(o.sentinel_interval, milliseconds(500));
  EXPECT_EQ(o.job_name, "demsa-study_with_spaces");
  EXPECT_EQ(o.settings.account, "a1");
}

TEST(SlurmExecutorOptions, ValidateNamesTheField) {
  SlurmExecutorOptions o;
  o.ranks = 0;
  EXPECT_EQ(test::message_of<std::invalid_argument>([&] { o.validate(); }),
            "SlurmExecutorOptions.ranks = 0: must be >= 1");
  o = SlurmExecutorOptions{};
  o.settings.throttle = -1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = SlurmExecutorOptions{};
  o.query_interval = milliseconds(0);
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

TEST(SlurmExecutor, ParseTaskId) {
  EXPECT_EQ(parse_slurm_task_id("123_4"), std::make_pair(std::string("123"), 4));
  EXPECT_FALSE(parse_slurm_task_id("123").has_value());
  EXPECT_FALSE(parse_slurm_task_id("_4").has_value());
  EXPECT_FALSE(parse_slurm_task_id("12_").has_value());
  EXPECT_FALSE(parse_slurm_task_id("pgid:123").has_value());
  EXPECT_FALSE(parse_slurm_task_id("1_2_3").has_value());
}

TEST(SlurmExecutor, AskCancelOnInterrupt) {
  for (const auto& [answer, expected] : std::vector<std::pair<std::string, bool>>{
           {"y\n", true}, {" YES \n", true}, {"n\n", false}, {"\n", false}, {"", false}, {"yep\n", false}}) {
    std::istringstream in(answer);
    std::ostringstream out;
    EXPECT_EQ(ask_cancel_on_interrupt(5, in, out), expected) << answer;
    EXPECT_NE(out.str().find("5 SLURM task(s)"), std::string::npos);
  }
}

TEST(SlurmExecutor, FactoryRefusesWithoutSbatch) {
  const char* old = std::getenv("PATH");
  const std::string saved = old != nullptr ? old : "";
  ::setenv("PATH", "/nonexistent", 1);
  RunSettings run;
  run.executor = ExecutorKind::slurm;
  EXPECT_THROW(make_slurm_executor(run, "/tmp"), std::runtime_error);
  ::setenv("PATH", saved.c_str(), 1);
}

}  // namespace
}  // namespace demsa
