// The SLURM client without a cluster: quoting, sbatch arguments, parsing squeue and sentinels, and the batch
// script itself run by bash with the variables SLURM would set.
#include "orchestrator/exec/slurm/client.hpp"
#include "orchestrator/util/process.hpp"

#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <chrono>
#include <filesystem>
#include <thread>

namespace demsa {

using namespace demsa::study;
using namespace demsa::exec;
namespace {
namespace fs = std::filesystem;
using test::read_file;
using test::TempDir;
using test::write_file;

void write_run_sh(const fs::path& folder, const std::string& body) {
  write_file(folder / "run.sh", "#!/bin/bash\n" + body);
  fs::permissions(folder / "run.sh", fs::perms::owner_all, fs::perm_options::add);
}

TEST(SlurmClient, ShellQuoteSurvivesBash) {
  for (const std::string text : {"plain", "a b", "it's", "$HOME `x` \"q\" \\ ;|&", "", "'''"}) {
    const auto r = util::run_capture({"bash", "-c", "printf %s " + util::shell_quote(text)});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.out, text);
  }
}

TEST(SlurmClient, RunProgramCapturesOutputAndStatus) {
  const auto r = util::run_capture({"bash", "-c", "echo out; echo err >&2; exit 7"});
  EXPECT_EQ(r.exit_code, 7);
  EXPECT_EQ(r.out, "out\n");
  EXPECT_EQ(r.err, "err\n");
  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(util::run_capture({"/nonexistent/program"}).exit_code, 127);
}

TEST(SlurmClient, RunProgramKillsAHangingProgram) {
  const auto start = std::chrono::steady_clock::now();
  util::CaptureOptions options;
  options.timeout = std::chrono::milliseconds(300);
  const auto r = util::run_capture({"sleep", "30"}, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(r.timed_out);
  EXPECT_EQ(r.exit_code, 128 + SIGKILL);
  EXPECT_LT(seconds, 5.0);
}

TEST(SlurmClient, SbatchArguments) {
  SlurmSubmission s;
  s.case_folders = {"/a", "/b", "/c"};
  s.work_dir = "/study dir/100%/slurm";
  s.job_name = "demsa-x";
  s.ranks = 2;
  s.settings.partition = "short";
  s.settings.account = "proj1";
  s.settings.time_limit = "00:30:00";
  s.settings.throttle = 4;
  s.settings.sbatch_options = {"--mem=2G", "--output=/elsewhere/%A_%a.log"};
  const std::vector<std::string> expected{"--parsable",
                                          "--array=0-2%4",
                                          "--job-name=demsa-x",
                                          "--ntasks=2",
                                          "--chdir=/study dir/100%/slurm",
                                          "--output=/study dir/100%%/slurm/logs/%A_%a.out",
                                          "--time=00:30:00",
                                          "--partition=short",
                                          "--account=proj1",
                                          "--mem=2G",
                                          "--output=/elsewhere/%A_%a.log"};
  EXPECT_EQ(sbatch_arguments(s), expected);

  s.settings = SlurmSettings{};
  s.settings.time_limit.clear();
  s.case_folders = {"/a"};
  const auto plain = sbatch_arguments(s);
  EXPECT_EQ(plain.size(), 6u);
  EXPECT_EQ(plain[1], "--array=0-0");

  // the submission's mark goes after demsa's own options and before the user's
  s.comment = "demsa:6553f100-0000abcd";
  s.settings.partition = "short";
  const auto marked = sbatch_arguments(s);
  ASSERT_EQ(marked.size(), 8u);
  EXPECT_EQ(marked[6], "--comment=demsa:6553f100-0000abcd");
  EXPECT_EQ(marked[7], "--partition=short");
}

TEST(SlurmClient, ParseCommentLines) {
  // as `squeue -h -t all --me -o "%F %k"` prints it: one line per job, or per task once it has started
  const std::string text =
      "12 demsa:6553f100-0000abcd\n"
      "12 demsa:6553f100-0000abcd\n"
      "9 (null)\n"
      "13 a comment with spaces \n"
      "101 demsa:x\n"
      "99 demsa:x\n"
      "junk demsa:y\n"
      "-5 demsa:y\n"
      "\n"
      "77\n";
  const auto jobs = parse_comment_lines(text);
  ASSERT_EQ(jobs.size(), 4u);
  EXPECT_EQ(jobs.at("demsa:6553f100-0000abcd"), (std::vector<std::string>{"12"}));
  EXPECT_EQ(jobs.at("(null)"), (std::vector<std::string>{"9"}));
  EXPECT_EQ(jobs.at("a comment with spaces"), (std::vector<std::string>{"13"}));
  EXPECT_EQ(jobs.at("demsa:x"), (std::vector<std::string>{"99", "101"}));  // numeric order
  EXPECT_FALSE(jobs.count("demsa:y"));
}

TEST(SlurmClient, ParseSqueue) {
  // as `squeue -h -r -t all -j 9 -O ArrayTaskID:16,State:24,exit_code:16` prints it (exit_code: wait status)
  const std::string text =
      "0               COMPLETED               0               \n"
      "1               FAILED                  256             \n"
      "2               TIMEOUT                 36608           \n"
      "3               PENDING                 0               \n"
      "[4-7]           PENDING                 0               \n"
      "\n";
  const auto tasks = parse_squeue(text);
  ASSERT_EQ(tasks.size(), 4u);
  EXPECT_EQ(tasks.at(0).state, "COMPLETED");
  EXPECT_EQ(tasks.at(1).wait_status, 256);
  EXPECT_EQ(tasks.at(2).state, "TIMEOUT");
  EXPECT_EQ(tasks.at(2).wait_status, 36608);
  EXPECT_EQ(tasks.at(3).state, "PENDING");
  EXPECT_TRUE(is_terminal_state("OUT_OF_MEMORY"));
  EXPECT_TRUE(is_terminal_state("CANCELLED"));
  EXPECT_FALSE(is_terminal_state("COMPLETING"));
  EXPECT_FALSE(is_terminal_state("RUNNING"));
}

TEST(SlurmClient, ParseSentinel) {
  const auto s = parse_sentinel("exit 3 host=node7 start=100.25 end=112.75\n0m0.010s 0m0.020s\n1m2.500s 0m0.250s\n");
  ASSERT_TRUE(s.has_value());
  EXPECT_FALSE(s->signalled);
  EXPECT_EQ(s->exit_code, 3);
  EXPECT_EQ(s->host, "node7");
  EXPECT_DOUBLE_EQ(s->wall_seconds, 12.5);
  EXPECT_DOUBLE_EQ(s->cpu_seconds, 62.75);

  const auto t = parse_sentinel("signal TERM host=n1 start=1 end=2\n");
  ASSERT_TRUE(t.has_value());
  EXPECT_TRUE(t->signalled);
  EXPECT_DOUBLE_EQ(t->cpu_seconds, 0.0);

  EXPECT_FALSE(parse_sentinel("").has_value());
  EXPECT_FALSE(parse_sentinel("exit\n").has_value());
  EXPECT_FALSE(parse_sentinel("exit x\n").has_value());
  EXPECT_FALSE(parse_sentinel("running\n").has_value());
  EXPECT_FALSE(read_sentinel("/nonexistent/sentinel").has_value());
}

TEST(SlurmClient, ParseSbatchJobId) {
  EXPECT_EQ(parse_sbatch_job_id("1234\n"), "1234");
  EXPECT_EQ(parse_sbatch_job_id("77;cluster2\n"), "77");
  EXPECT_FALSE(parse_sbatch_job_id("").has_value());
  EXPECT_FALSE(parse_sbatch_job_id("Submitted batch job 5\n").has_value());
}

// The batch script, run by bash as SLURM would run task 1 of job 42, in folders whose names need quoting.
TEST(SlurmClient, BatchScriptRunsTheCaseAndWritesItsSentinel) {
  TempDir dir;
  const fs::path work = dir / "my study's dir/slurm";
  const fs::path case0 = dir / "my study's dir/cases/000000";
  const fs::path case1 = dir / "my study's dir/cases/000001 $x";
  fs::create_directories(case0);
  fs::create_directories(case1);
  fs::create_directories(sentinel_dir(work));
  write_run_sh(case1, "echo \"ran in $(basename \"$PWD\") with $DEMSA_TEST_PROLOGUE\"\necho oops >&2\nexit 3\n");
  SlurmSubmission s;
  s.case_folders = {case0, case1};
  s.work_dir = work;
  s.settings.prologue = "export DEMSA_TEST_PROLOGUE='module loaded'";
  write_file(work / "batch.sh", render_batch_script(s));

  const auto r = test::run_command({"env", "SLURM_ARRAY_TASK_ID=1", "SLURM_ARRAY_JOB_ID=42", "SLURMD_NODENAME=n5",
                                    "bash", (work / "batch.sh").string()});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_EQ(read_file(case1 / "run.out"), "ran in 000001 $x with module loaded\noops\n");
  const auto sentinel = read_sentinel(sentinel_path(work, "42", 1));
  ASSERT_TRUE(sentinel.has_value());
  EXPECT_FALSE(sentinel->signalled);
  EXPECT_EQ(sentinel->exit_code, 3);
  EXPECT_EQ(sentinel->host, "n5");
  EXPECT_GE(sentinel->wall_seconds, 0.0);
  EXPECT_LT(sentinel->wall_seconds, 30.0);
  EXPECT_FALSE(fs::exists(sentinel_path(work, "42", 1).string() + ".tmp"));
  EXPECT_FALSE(fs::exists(case0 / "run.out"));
}

TEST(SlurmClient, BatchScriptTermTrapWritesSignalSentinelAndStopsTheCase) {
  TempDir dir;
  const fs::path work = dir / "slurm";
  const fs::path folder = dir / "case a";
  fs::create_directories(folder);
  fs::create_directories(sentinel_dir(work));
  write_run_sh(folder, "echo started > started.txt\nsleep 60\necho not reached > after.txt\n");
  SlurmSubmission s;
  s.case_folders = {folder};
  s.work_dir = work;
  write_file(work / "batch.sh", render_batch_script(s));

  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::setpgid(0, 0);
    ::setenv("SLURM_ARRAY_TASK_ID", "0", 1);
    ::setenv("SLURM_ARRAY_JOB_ID", "9", 1);
    const std::string script = (work / "batch.sh").string();
    ::execlp("bash", "bash", script.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  for (int i = 0; i < 100 && !fs::exists(folder / "started.txt"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(fs::exists(folder / "started.txt"));
  ::kill(pid, SIGTERM);  // as SLURM does on scancel and at the time limit: the batch shell first
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 143);
  const auto sentinel = read_sentinel(sentinel_path(work, "9", 0));
  ASSERT_TRUE(sentinel.has_value());
  EXPECT_TRUE(sentinel->signalled);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_FALSE(fs::exists(folder / "after.txt"));
  ::kill(-pid, SIGKILL);  // whatever is left of the group (the sleep, if the trap missed it)
}

TEST(SlurmClient, BatchScriptWithoutCaseFolderFails) {
  TempDir dir;
  const fs::path work = dir / "slurm";
  fs::create_directories(sentinel_dir(work));
  SlurmSubmission s;
  s.case_folders = {dir / "missing"};
  s.work_dir = work;
  write_file(work / "batch.sh", render_batch_script(s));
  const auto r =
      test::run_command({"env", "SLURM_ARRAY_TASK_ID=0", "SLURM_ARRAY_JOB_ID=5", "bash", (work / "batch.sh").string()});
  EXPECT_EQ(r.exit_code, 126);
  const auto sentinel = read_sentinel(sentinel_path(work, "5", 0));
  ASSERT_TRUE(sentinel.has_value());
  EXPECT_EQ(sentinel->exit_code, 126);
}

}  // namespace
}  // namespace demsa
