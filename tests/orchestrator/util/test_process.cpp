// util/process: run_capture (output, status, signals, timeout, stdin, working directory, environment, paths with
// quotes and spaces, programs that cannot be started) and spawn (process group, output file, wait, rusage,
// kill_group), and the /proc process-group helpers.
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/process.hpp"

#include "support/test_support.hpp"

#include <signal.h>
#include <unistd.h>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

namespace demsa {

using namespace demsa::util;
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

/// An executable bash script at `path`.
void write_script(const fs::path& path, const std::string& body) {
  fs::create_directories(path.parent_path());
  test::write_file(path, "#!/bin/bash\n" + body + "\n");
  fs::permissions(path, fs::perms::owner_all, fs::perm_options::add);
}

/// True when `pid` is gone or a zombie nobody reaped yet.
bool gone(int pid) {
  std::error_code ec;
  const fs::path stat = fmt::format("/proc/{}/stat", pid);
  if (!fs::exists(stat, ec)) return true;
  const std::string text = test::read_file(stat);
  return text.find(") Z") != std::string::npos;
}

bool wait_gone(int pid, std::chrono::milliseconds limit = 3000ms) {
  const auto deadline = Clock::now() + limit;
  while (!gone(pid) && Clock::now() < deadline) std::this_thread::sleep_for(20ms);
  return gone(pid);
}

TEST(Process, CapturesStdoutStderrAndExitCode) {
  const CaptureResult r = run_capture({"bash", "-c", "echo out; echo err >&2; exit 3"});
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.signal, 0);
  EXPECT_FALSE(r.timed_out);
  EXPECT_TRUE(r.start_error.empty());
  EXPECT_EQ(r.out, "out\n");
  EXPECT_EQ(r.err, "err\n");
}

TEST(Process, MergesStderrInOrder) {
  CaptureOptions options;
  options.merge_stderr = true;
  const CaptureResult r = run_capture({"bash", "-c", "echo 1; echo 2 >&2; echo 3; echo 4 >&2"}, options);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out, "1\n2\n3\n4\n");
  EXPECT_EQ(r.err, "");
}

TEST(Process, LargeOutputOnBothStreamsDoesNotDeadlock) {
  // More than a pipe holds (64 KiB) on stderr before anything on stdout.
  const CaptureResult r =
      run_capture({"bash", "-c", "head -c 300000 /dev/zero | tr '\\0' e >&2; head -c 200000 /dev/zero | tr '\\0' o"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.err, std::string(300000, 'e'));
  EXPECT_EQ(r.out, std::string(200000, 'o'));
}

TEST(Process, ReportsTheSignalThatKilledTheProgram) {
  const CaptureResult r = run_capture({"bash", "-c", "kill -KILL $$"});
  EXPECT_EQ(r.signal, SIGKILL);
  EXPECT_EQ(r.exit_code, 128 + SIGKILL);
  EXPECT_FALSE(r.timed_out);
}

TEST(Process, SignalsDemsaIgnoresAreDefaultForTheProgram) {
  // An ignored signal survives exec; the program must get the default action (ends it) instead.
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  struct sigaction old {};
  ASSERT_EQ(::sigaction(SIGUSR1, &ignore, &old), 0);
  const CaptureResult r = run_capture({"bash", "-c", "kill -USR1 $$; exit 0"});
  ::sigaction(SIGUSR1, &old, nullptr);
  EXPECT_EQ(r.signal, SIGUSR1);
}

TEST(Process, TimeoutKillsTheProgramAndWhatItStarted) {
  CaptureOptions options;
  options.timeout = 500ms;
  const auto start = Clock::now();
  // The background sleep keeps stdout open: demsa must not wait for its end-of-file either.
  const CaptureResult r = run_capture({"bash", "-c", "sleep 60 & echo $!; wait"}, options);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_TRUE(r.timed_out);
  EXPECT_EQ(r.signal, SIGKILL);
  EXPECT_EQ(r.exit_code, 128 + SIGKILL);
  EXPECT_GE(seconds, 0.5);
  EXPECT_LT(seconds, 5.0);
  ASSERT_FALSE(r.out.empty());
  EXPECT_TRUE(wait_gone(std::stoi(r.out))) << "the program's child survived the timeout";
}

TEST(Process, AStopRequestKillsTheProgramAndWhatItStarted) {
  CaptureOptions options;
  const auto start = Clock::now();
  options.should_stop = [&] { return Clock::now() - start > 300ms; };
  const CaptureResult r = run_capture({"bash", "-c", "sleep 60 & echo $!; wait"}, options);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_TRUE(r.stopped);
  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(r.signal, SIGKILL);
  EXPECT_GE(seconds, 0.3);
  EXPECT_LT(seconds, 5.0);
  ASSERT_FALSE(r.out.empty());
  EXPECT_TRUE(wait_gone(std::stoi(r.out))) << "the program's child survived the stop";
}

TEST(Process, PathsAndArgumentsWithQuotesAndSpaces) {
  test::TempDir tmp;
  const fs::path dir = tmp / "it's a \"dir\" $HOME";
  const fs::path script = dir / "say it's.sh";
  write_script(script, "printf '%s|' \"$@\"; pwd");
  const std::string argument = "a 'b' \"c\" $HOME `x` ; | &";
  CaptureOptions options;
  options.cwd = dir;
  const CaptureResult r = run_capture({script.string(), argument, ""}, options);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, argument + "||" + fs::canonical(dir).string() + "\n");
  // the relative form, from its folder
  const CaptureResult relative = run_capture({"./say it's.sh", "x"}, options);
  EXPECT_EQ(relative.exit_code, 0) << relative.err;
  EXPECT_EQ(relative.out.substr(0, 2), "x|");
}

TEST(Process, StdinTextReachesTheProgram) {
  CaptureOptions options;
  options.input = "line 1\nline 'two'\n";
  const CaptureResult r = run_capture({"cat"}, options);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out, *options.input);
  // more than a pipe holds, echoed back while it is written
  options.input = std::string(1 << 20, 'x');
  const CaptureResult big = run_capture({"cat"}, options);
  EXPECT_EQ(big.out.size(), options.input->size());
  EXPECT_EQ(big.out, *options.input);
}

TEST(Process, AProgramThatDoesNotReadItsInputDoesNotEndDemsa) {
  CaptureOptions options;
  options.input = std::string(1 << 20, 'x');
  const CaptureResult r = run_capture({"bash", "-c", "exit 4"}, options);  // SIGPIPE must not reach this test
  EXPECT_EQ(r.exit_code, 4);
}

TEST(Process, StdinIsDevNullByDefault) {
  const CaptureResult r = run_capture({"cat"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out, "");
}

TEST(Process, EnvironmentIsAddedForTheProgramOnly) {
  CaptureOptions options;
  options.env = {{"DEMSA_TEST_VARIABLE", "a 'b' c"}, {"HOME", "/elsewhere"}};
  const CaptureResult r =
      run_capture({"bash", "-c", "printf '%s|%s|%s' \"$DEMSA_TEST_VARIABLE\" \"$HOME\" \"${PATH:+path}\""}, options);
  EXPECT_EQ(r.out, "a 'b' c|/elsewhere|path");
  EXPECT_EQ(std::getenv("DEMSA_TEST_VARIABLE"), nullptr);
}

TEST(Process, AMissingProgramExits127WithAMessage) {
  const CaptureResult r = run_capture({"demsa-no-such-program", "-h"});
  EXPECT_EQ(r.exit_code, 127);
  EXPECT_EQ(r.signal, 0);
  EXPECT_NE(r.start_error.find("demsa-no-such-program"), std::string::npos) << r.start_error;
  EXPECT_NE(r.err.find("cannot run demsa-no-such-program"), std::string::npos) << r.err;
  EXPECT_EQ(run_capture({"/nonexistent/program"}).exit_code, 127);

  test::TempDir tmp;
  test::write_file(tmp / "not-executable", "#!/bin/bash\necho no\n");
  const CaptureResult denied = run_capture({(tmp / "not-executable").string()});
  EXPECT_EQ(denied.exit_code, 126);
  EXPECT_FALSE(denied.start_error.empty());

  CaptureOptions options;
  options.cwd = tmp / "no such folder";
  const CaptureResult no_cwd = run_capture({"true"}, options);
  EXPECT_EQ(no_cwd.exit_code, 126);
  EXPECT_NE(no_cwd.start_error.find("no such folder"), std::string::npos) << no_cwd.start_error;
}

TEST(Process, SpawnRunsInItsOwnGroupWithOutputToAFile) {
  test::TempDir tmp;
  const fs::path dir = tmp / "it's a dir";
  // field 5 of /proc/PID/stat: the process group
  write_script(dir / "run.sh", "echo out; echo err >&2; read -r -a stat < /proc/$$/stat; echo ${stat[4]}; exit 5");
  SpawnOptions options;
  options.output = dir / "run.out";
  options.cwd = dir;
  Child child = spawn({"./run.sh"}, options);
  EXPECT_GT(child.pid(), 0);
  EXPECT_GT(child.start_ticks(), 0u);
  const ChildExit ended = child.wait();
  EXPECT_EQ(ended.exit_code, 5);
  EXPECT_EQ(ended.signal, 0);
  EXPECT_TRUE(ended.error.empty());
  EXPECT_EQ(test::read_file(dir / "run.out"), fmt::format("out\nerr\n{}\n", child.pid()));
  // reaped once; asked again, the same answer
  ASSERT_TRUE(child.try_wait().has_value());
  EXPECT_EQ(child.try_wait()->exit_code, 5);
}

TEST(Process, SpawnCountsCpuTimeOfWaitedForDescendants) {
  test::TempDir tmp;
  write_script(tmp / "busy.sh", "bash -c 'for ((i = 0; i < 200000; i++)); do :; done'");
  SpawnOptions options;
  options.output = tmp / "busy.out";
  Child child = spawn({(tmp / "busy.sh").string()}, options);
  std::optional<ChildExit> ended;
  const auto deadline = Clock::now() + 20s;
  while (!(ended = child.try_wait()) && Clock::now() < deadline) std::this_thread::sleep_for(10ms);
  ASSERT_TRUE(ended.has_value());
  EXPECT_EQ(ended->exit_code, 0);
  EXPECT_GT(ended->cpu_seconds, 0.05);
}

TEST(Process, KillGroupReachesWhatTheChildStarted) {
  test::TempDir tmp;
  write_script(tmp / "hang.sh", "sleep 60 & echo $! > child.pid; wait");
  SpawnOptions options;
  options.output = tmp / "hang.out";
  options.cwd = tmp.path();
  Child child = spawn({"./hang.sh"}, options);
  for (int i = 0; i < 250 && !(fs::exists(tmp / "child.pid") && fs::file_size(tmp / "child.pid") > 0); ++i)
    std::this_thread::sleep_for(20ms);
  const int grandchild = std::stoi(test::read_file(tmp / "child.pid"));
  EXPECT_FALSE(child.try_wait().has_value());
  const std::vector<int> members = group_members(child.pid(), child.start_ticks());
  EXPECT_EQ(members.size(), 2u);
  child.kill_group(SIGTERM);
  const ChildExit ended = child.wait();
  EXPECT_EQ(ended.signal, SIGTERM);
  EXPECT_EQ(ended.exit_code, -1);
  EXPECT_TRUE(wait_gone(grandchild));
}

TEST(Process, SpawnOfAMissingProgramExits127AndSaysWhyInTheOutput) {
  test::TempDir tmp;
  SpawnOptions options;
  options.output = tmp / "run.out";
  options.cwd = tmp.path();
  Child child = spawn({"./run.sh"}, options);
  EXPECT_EQ(child.wait().exit_code, 127);
  EXPECT_NE(test::read_file(tmp / "run.out").find("demsa: cannot run ./run.sh"), std::string::npos);
  options.output = tmp / "no such folder" / "run.out";
  EXPECT_THROW(spawn({"true"}, options), IoError);
}

TEST(Process, TerminateGroupChecksTheStartTime) {
  test::TempDir tmp;
  write_script(tmp / "stubborn.sh", "trap '' TERM; sleep 60 & echo started > ready; wait; sleep 60");
  SpawnOptions options;
  options.output = tmp / "stubborn.out";
  options.cwd = tmp.path();
  Child child = spawn({"./stubborn.sh"}, options);
  for (int i = 0; i < 250 && !(fs::exists(tmp / "ready") && fs::file_size(tmp / "ready") > 0); ++i)
    std::this_thread::sleep_for(20ms);  // its TERM trap is set
  const auto start = process_start_ticks(child.pid());
  ASSERT_TRUE(start.has_value());
  EXPECT_EQ(*start, child.start_ticks());
  // a group of that id started later is someone else's: left alone
  EXPECT_FALSE(terminate_group(child.pid(), *start + 1000000, 100ms));
  EXPECT_FALSE(child.try_wait().has_value());
  EXPECT_FALSE(terminate_group(::getpgrp(), 0, 100ms));  // never demsa's own group
  // TERM is ignored by the script: KILL after the grace
  EXPECT_TRUE(terminate_group(child.pid(), *start, 300ms));
  EXPECT_EQ(child.wait().signal, SIGKILL);
  for (int i = 0; i < 100 && !group_members(child.pid(), *start).empty(); ++i) std::this_thread::sleep_for(20ms);
  EXPECT_TRUE(group_members(child.pid(), *start).empty());
  EXPECT_FALSE(process_start_ticks(child.pid()).has_value());
}

}  // namespace
}  // namespace demsa
