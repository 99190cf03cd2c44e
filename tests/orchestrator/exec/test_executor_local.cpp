#include "orchestrator/exec/local_executor.hpp"
#include "orchestrator/util/errors.hpp"

#include "support/test_support.hpp"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace demsa {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::exec;
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

fs::path make_case(const test::TempDir& tmp, const std::string& name, const std::string& body) {
  const fs::path folder = tmp / name;
  fs::create_directories(folder);
  test::write_file(folder / "run.sh", "#!/bin/bash\n" + body + "\n");
  fs::permissions(folder / "run.sh", fs::perms::owner_all, fs::perm_options::add);
  return folder;
}

/// The file's text, or "" when it does not exist (any more).
std::string read_if_exists(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<FinishedCase> wait_all(LocalExecutor& executor, double limit_seconds = 20) {
  std::vector<FinishedCase> all;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit_seconds);
  while (executor.in_flight() > 0 && std::chrono::steady_clock::now() < deadline)
    for (FinishedCase& f : executor.poll(100ms)) all.push_back(std::move(f));
  return all;
}

TEST(LocalExecutor, ExitStatusOutputWallCpuAndHost) {
  test::TempDir tmp;
  const fs::path ok = make_case(tmp, "ok", "echo hello; pwd");
  const fs::path bad = make_case(tmp, "bad", "echo oops >&2; exit 3");
  // A fixed amount of CPU work in a grandchild (bash -c): counted through wait4's rusage of waited-for
  // descendants, whatever the load of the machine.
  const fs::path busy = make_case(tmp, "busy", "bash -c 'for ((i = 0; i < 200000; i++)); do :; done'; exit 0");
  LocalExecutorOptions options;
  options.parallel = 3;
  LocalExecutor executor(options);
  EXPECT_EQ(executor.free_slots(), 3);
  const std::vector<std::string> ids = executor.submit({{0, 1, ok}, {1, 1, bad}, {2, 1, busy}});
  ASSERT_EQ(ids.size(), 3u);
  EXPECT_NE(ids[0].find(':'), std::string::npos);
  EXPECT_EQ(executor.free_slots(), 0);
  const std::vector<FinishedCase> done = wait_all(executor);
  ASSERT_EQ(done.size(), 3u);
  for (const FinishedCase& f : done) {
    EXPECT_FALSE(f.exit.host.empty());
    EXPECT_GT(f.exit.wall_seconds, 0.0);
    if (f.task.sample == 0) {
      EXPECT_EQ(f.exit.exit_code, 0);
      EXPECT_EQ(test::read_file(ok / "run.out"), "hello\n" + ok.string() + "\n");
    } else if (f.task.sample == 1) {
      EXPECT_EQ(f.exit.exit_code, 3);
      EXPECT_EQ(test::read_file(bad / "run.out"), "oops\n");
    } else {
      EXPECT_EQ(f.exit.exit_code, 0);
      EXPECT_GT(f.exit.cpu_seconds, 0.05);
      EXPECT_LE(f.exit.cpu_seconds, f.exit.wall_seconds + 0.05);  // one process at a time
    }
  }
  EXPECT_EQ(executor.in_flight(), 0);
}

TEST(LocalExecutor, TimeoutKillsTheWholeProcessGroup) {
  test::TempDir tmp;
  // The grandchild writes its pid; it must be gone after the timeout, not only run.sh.
  const fs::path hang = make_case(tmp, "hang", "sleep 60 & echo $! > child.pid; wait");
  LocalExecutorOptions options;
  options.timeout = 0.5;
  options.grace = 0.5;
  LocalExecutor executor(options);
  executor.submit({{0, 1, hang}});
  const std::vector<FinishedCase> done = wait_all(executor);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_TRUE(done[0].exit.timed_out);
  EXPECT_GE(done[0].exit.wall_seconds, 0.5);
  EXPECT_LT(done[0].exit.wall_seconds, 5.0);
  const pid_t child = std::stoi(test::read_file(hang / "child.pid"));
  std::this_thread::sleep_for(100ms);
  // Gone, or a zombie that nobody reaps yet (its parent run.sh was killed too).
  const std::string stat = read_if_exists(fmt::format("/proc/{}/stat", child));
  EXPECT_TRUE(stat.empty() || stat.find(") Z") != std::string::npos) << "survived the timeout: " << stat;
}

TEST(LocalExecutor, SignalDeathIsReported) {
  test::TempDir tmp;
  const fs::path killed = make_case(tmp, "killed", "kill -KILL $$");
  LocalExecutor executor(LocalExecutorOptions{});
  executor.submit({{0, 1, killed}});
  const std::vector<FinishedCase> done = wait_all(executor);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].exit.signal, SIGKILL);
  EXPECT_EQ(done[0].exit.exit_code, -1);
  EXPECT_FALSE(done[0].exit.timed_out);
}

TEST(LocalExecutor, CancelAllStopsEverythingAndReportsCancelled) {
  test::TempDir tmp;
  LocalExecutorOptions options;
  options.parallel = 2;
  options.grace = 1.0;
  LocalExecutor executor(options);
  executor.submit({{0, 1, make_case(tmp, "a", "sleep 60")},
                   {1, 1, make_case(tmp, "b", "trap '' TERM; sleep 60 & wait; sleep 60")}});
  std::this_thread::sleep_for(200ms);
  const auto start = std::chrono::steady_clock::now();
  executor.cancel_all();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  const std::vector<FinishedCase> done = executor.poll(0ms);
  ASSERT_EQ(done.size(), 2u);
  for (const FinishedCase& f : done) EXPECT_TRUE(f.exit.cancelled);
  EXPECT_EQ(executor.in_flight(), 0);
}

TEST(LocalExecutor, MissingRunScriptExits127) {
  test::TempDir tmp;
  fs::create_directories(tmp / "empty");
  LocalExecutor executor(LocalExecutorOptions{});
  executor.submit({{0, 1, tmp / "empty"}});
  const std::vector<FinishedCase> done = wait_all(executor);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].exit.exit_code, 127);
}

TEST(LocalExecutor, AdoptEndsALeftoverGroupAndReportsItLost) {
  test::TempDir tmp;
  // A process group standing for a case started by a demsa that was killed: its own group, not our child.
  const fs::path pid_file = tmp / "leftover.pid";
  const test::CommandResult started = test::run_command(
      {"bash", "-c",
       fmt::format("setsid bash -c 'echo $$ > {}; exec sleep 60' > /dev/null 2>&1 &", pid_file.string())});
  ASSERT_EQ(started.exit_code, 0);
  for (int i = 0; i < 250 && !(fs::exists(pid_file) && fs::file_size(pid_file) > 0); ++i)
    std::this_thread::sleep_for(20ms);
  const pid_t pid = std::stoi(test::read_file(pid_file));
  // Its start time in clock ticks, as the local executor records it.
  const std::string stat = test::read_file(fmt::format("/proc/{}/stat", pid));
  std::istringstream fields(stat.substr(stat.rfind(')') + 2));
  std::string field;
  for (int i = 3; i <= 22; ++i) fields >> field;
  const std::string job_id = fmt::format("{}:{}", pid, field);

  // A job id whose start time does not match (pid reused by someone else) is left alone.
  EXPECT_FALSE(end_leftover_group(fmt::format("{}:{}", pid, std::stoull(field) + 1000000), 0.1));
  EXPECT_EQ(::kill(pid, 0), 0);

  LocalExecutorOptions options;
  options.grace = 1.0;
  LocalExecutor executor(options);
  executor.adopt({{{7, 2, tmp / "case"}, job_id}});
  EXPECT_EQ(executor.in_flight(), 1);
  const std::vector<FinishedCase> done = executor.poll(0ms);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].task.sample, 7);
  EXPECT_TRUE(done[0].exit.lost);
  std::this_thread::sleep_for(100ms);
  // Gone, or a zombie waiting for init.
  const std::string after = read_if_exists(fmt::format("/proc/{}/stat", pid));
  EXPECT_TRUE(after.empty() || after.find(") Z") != std::string::npos) << after;
}

TEST(LocalExecutor, ParallelDefaultsFromCoresAndRefusesOversubscription) {
  RunSettings run;
  run.ranks = 2;
  EXPECT_EQ(local_parallel(run, 8), 4);
  EXPECT_THROW(local_parallel(run, 1), UserError);  // 2 ranks on 1 core would oversubscribe
  run.ranks = 1;
  EXPECT_EQ(local_parallel(run, 1), 1);
  run.ranks = 2;
  run.parallel = 3;
  EXPECT_THROW(local_parallel(run, 4), UserError);
  run.oversubscribe = true;
  EXPECT_EQ(local_parallel(run, 4), 3);
  LocalExecutorOptions options;
  options.parallel = 0;
  EXPECT_THROW(options.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace demsa
