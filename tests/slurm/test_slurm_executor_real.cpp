// The SLURM executor against a real local SLURM (scripts/start-local-slurm.sh; started here when none is
// running, and stopped again afterwards). Cases are tiny run.sh scripts, so this checks SLURM's side: the batch
// script, squeue's real output, sentinels, scancel of running and pending tasks, adopt after a "restart".
#include "orchestrator/exec/slurm/executor.hpp"

#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <chrono>
#include <filesystem>

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

class RealSlurm : public ::testing::Test {
 public:
  static void SetUpTestSuite() {
    const auto info = test::run_command({"sinfo", "-h", "-o", "%T"});
    if (info.exit_code == 0 && !info.out.empty()) return;  // a SLURM is already up: use it, leave it running
    ASSERT_EQ(::geteuid(), 0u) << "no SLURM is running and starting one needs root";
    const auto r = test::run_command({std::string(DEMSA_SOURCE_DIR) + "/scripts/start-local-slurm.sh"});
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    s_started = true;
  }
  static void TearDownTestSuite() {
    if (s_started) test::run_command({std::string(DEMSA_SOURCE_DIR) + "/scripts/stop-local-slurm.sh"});
    s_started = false;
  }

 protected:
  SlurmExecutorOptions options() const {
    SlurmExecutorOptions o;
    o.query_interval = milliseconds(300);
    o.sentinel_interval = milliseconds(100);
    o.sentinel_grace = milliseconds(5000);
    o.cancel_wait = milliseconds(30000);
    o.job_name = "demsa-real-test";
    o.settings.time_limit = "00:05:00";
    return o;
  }
  CaseTask make_case(int sample, const std::string& body) const {
    CaseTask t;
    t.sample = sample;
    t.folder = m_dir / "study dir" / "cases" / ("case " + std::to_string(sample));
    write_file(t.folder / "run.sh", "#!/bin/bash\n" + body);
    fs::permissions(t.folder / "run.sh", fs::perms::owner_all, fs::perm_options::add);
    return t;
  }
  static const FinishedCase* find(const std::vector<FinishedCase>& done, int sample) {
    for (const auto& f : done)
      if (f.task.sample == sample) return &f;
    return nullptr;
  }
  static std::vector<FinishedCase> collect(Executor& e, size_t n, milliseconds limit = milliseconds(90000)) {
    std::vector<FinishedCase> done;
    const auto end = std::chrono::steady_clock::now() + limit;
    while (done.size() < n && std::chrono::steady_clock::now() < end) {
      auto got = e.poll(milliseconds(500));
      done.insert(done.end(), got.begin(), got.end());
    }
    return done;
  }

  TempDir m_dir;
  static bool s_started;
};
bool RealSlurm::s_started = false;

TEST_F(RealSlurm, ExitStatusesOutputAndTiming) {
  SlurmExecutor executor(options(), m_dir / "study dir");
  const auto ids = executor.submit(
      {make_case(0, "echo hello from $PWD; sleep 1; exit 0\n"), make_case(1, "echo failing >&2; exit 3\n")});
  ASSERT_EQ(ids.size(), 2u);
  EXPECT_EQ(ids[0].substr(ids[0].find('_')), "_0");
  const auto done = collect(executor, 2);
  ASSERT_EQ(done.size(), 2u);
  const auto* ok = find(done, 0);
  ASSERT_NE(ok, nullptr);
  EXPECT_EQ(ok->exit.exit_code, 0) << ok->exit.detail;
  EXPECT_EQ(ok->exit.host, "localhost");
  EXPECT_GE(ok->exit.wall_seconds, 1.0);
  EXPECT_LT(ok->exit.wall_seconds, 30.0);
  EXPECT_EQ(read_file(ok->task.folder / "run.out"), "hello from " + ok->task.folder.string() + "\n");
  const auto* bad = find(done, 1);
  ASSERT_NE(bad, nullptr);
  EXPECT_EQ(bad->exit.exit_code, 3) << bad->exit.detail;
  EXPECT_EQ(read_file(bad->task.folder / "run.out"), "failing\n");
  EXPECT_EQ(executor.in_flight(), 0);
}

TEST_F(RealSlurm, CancelRunningAndPendingTasksByHand) {
  auto o = options();
  o.settings.throttle = 1;  // task 0 runs, tasks 1 and 2 wait
  SlurmExecutor executor(o, m_dir / "study dir");
  const auto ids = executor.submit(
      {make_case(0, "echo started > started; sleep 300\n"), make_case(1, "exit 0\n"), make_case(2, "exit 0\n")});
  const fs::path started = m_dir / "study dir/cases/case 0/started";
  for (int i = 0; i < 600 && !fs::exists(started); ++i) executor.poll(milliseconds(100));
  ASSERT_TRUE(fs::exists(started));
  // A pending task that is not the array's last pending one vanishes from squeue without a trace when cancelled
  // (SLURM 22.05 keeps pending tasks in one record); the running one gets SIGTERM and writes "signal TERM".
  ASSERT_EQ(test::run_command({"scancel", ids[2]}).exit_code, 0);
  ASSERT_EQ(test::run_command({"scancel", ids[0]}).exit_code, 0);
  const auto done = collect(executor, 3, milliseconds(60000));
  ASSERT_EQ(done.size(), 3u);
  const auto* running = find(done, 0);
  ASSERT_NE(running, nullptr);
  EXPECT_TRUE(running->exit.cancelled) << running->exit.detail;
  const auto* next = find(done, 1);
  ASSERT_NE(next, nullptr);
  EXPECT_EQ(next->exit.exit_code, 0) << next->exit.detail;
  const auto* pending = find(done, 2);
  ASSERT_NE(pending, nullptr);
  EXPECT_TRUE(pending->exit.lost) << pending->exit.detail;
  const auto sentinel = read_sentinel(sentinel_path(executor.work_dir(), ids[0].substr(0, ids[0].find('_')), 0));
  ASSERT_TRUE(sentinel.has_value());
  EXPECT_TRUE(sentinel->signalled);
  EXPECT_FALSE(fs::exists(sentinel_path(executor.work_dir(), ids[2].substr(0, ids[2].find('_')), 2)));
}

TEST_F(RealSlurm, CancelAllAndAdoptAfterRestart) {
  const fs::path study = m_dir / "study dir";
  std::vector<std::string> ids;
  std::vector<CaseTask> tasks{make_case(0, "sleep 2; exit 5\n"), make_case(1, "sleep 2; exit 0\n")};
  {
    SlurmExecutor first(options(), study);
    ids = first.submit(tasks);
  }  // demsa "stops" without collecting: the tasks keep running
  SlurmExecutor second(options(), study);
  second.adopt({{tasks[0], ids[0]}, {tasks[1], ids[1]}});
  const auto done = collect(second, 2);
  ASSERT_EQ(done.size(), 2u);
  EXPECT_EQ(find(done, 0)->exit.exit_code, 5);
  EXPECT_EQ(find(done, 1)->exit.exit_code, 0);

  SlurmExecutor third(options(), study);
  third.submit({make_case(2, "sleep 300\n"), make_case(3, "sleep 300\n"), make_case(4, "sleep 300\n")});
  collect(third, 1, milliseconds(3000));  // give SLURM a moment to start some of them
  const auto start = std::chrono::steady_clock::now();
  third.cancel_all();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto cancelled = third.poll(milliseconds(0));
  ASSERT_EQ(cancelled.size(), 3u);
  for (const auto& c : cancelled) EXPECT_TRUE(c.exit.cancelled) << c.exit.detail;
  EXPECT_LT(seconds, 20.0);
  EXPECT_EQ(third.in_flight(), 0);
}

TEST_F(RealSlurm, ProvisionalIdsFindTheArrayAfterACrashInsideSubmit) {
  const fs::path study = m_dir / "study dir";
  const std::vector<CaseTask> tasks{make_case(0, "sleep 1; exit 0\n"), make_case(1, "sleep 1; exit 4\n")};
  std::vector<std::string> reserved;
  std::vector<std::string> ids;
  {
    SlurmExecutor first(options(), study);
    reserved = first.reserve_ids(tasks);
    ids = first.submit(tasks);
  }  // demsa dies before it stores `ids`: only the provisional ids are in the store
  const std::string token = parse_pending_slurm_id(reserved[0]).value().token;
  const auto shown = test::run_command({"squeue", "-h", "-t", "all", "--me", "-o", "%F %k"});
  ASSERT_EQ(shown.exit_code, 0) << shown.err;
  EXPECT_NE(shown.out.find(ids[0].substr(0, ids[0].find('_')) + " demsa:" + token + "\n"), std::string::npos)
      << shown.out;

  SlurmExecutor second(options(), study);
  // a third run whose submission never reached the controller (an old token that no job carries)
  CaseTask never = make_case(2, "exit 0\n");
  second.adopt({{tasks[0], reserved[0]}, {tasks[1], reserved[1]}, {never, "pending:1-0badc0de:0"}});
  const auto done = collect(second, 3, milliseconds(25000));
  ASSERT_EQ(done.size(), 3u);
  EXPECT_EQ(find(done, 0)->exit.exit_code, 0) << find(done, 0)->exit.detail;
  EXPECT_EQ(find(done, 1)->exit.exit_code, 4) << find(done, 1)->exit.detail;
  EXPECT_TRUE(find(done, 2)->exit.lost) << find(done, 2)->exit.detail;
  const auto learned = second.take_learned_ids();
  ASSERT_EQ(learned.size(), 2u);
  EXPECT_EQ(learned[0].job_id, ids[0]);
  EXPECT_EQ(learned[1].job_id, ids[1]);
}

}  // namespace
}  // namespace demsa
