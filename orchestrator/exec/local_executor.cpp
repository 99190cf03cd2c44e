#include "orchestrator/exec/local_executor.hpp"

#include "orchestrator/util/errors.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/core.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace demsa::exec {

using namespace demsa::util;
using namespace demsa::study;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// Fields of /proc/PID/stat we use.
struct ProcStat {
  bool ok = false;
  char state = '?';
  long pgrp = 0;
  unsigned long long start_ticks = 0;
};

ProcStat read_proc_stat(long pid) {
  ProcStat stat;
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  std::string text;
  if (!in || !std::getline(in, text)) return stat;
  // The command name (field 2) is in parentheses and may contain spaces: parse after the last ')'.
  const auto close = text.rfind(')');
  if (close == std::string::npos) return stat;
  std::istringstream rest(text.substr(close + 1));
  std::string field;
  std::vector<std::string> fields;  // fields[0] is field 3 (state)
  while (rest >> field) fields.push_back(field);
  if (fields.size() < 20) return stat;
  stat.state = fields[0].empty() ? '?' : fields[0][0];
  stat.pgrp = std::stol(fields[2]);            // field 5
  stat.start_ticks = std::stoull(fields[19]);  // field 22
  stat.ok = true;
  return stat;
}

/// Live (non-zombie) processes of process group `pgid` started at or after `start_ticks`.
std::vector<long> group_members(long pgid, unsigned long long start_ticks) {
  std::vector<long> members;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || !std::all_of(name.begin(), name.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
    const long pid = std::stol(name);
    const ProcStat stat = read_proc_stat(pid);
    if (stat.ok && stat.pgrp == pgid && stat.state != 'Z' && stat.start_ticks >= start_ticks) members.push_back(pid);
  }
  return members;
}

double seconds(const struct timeval& tv) { return static_cast<double>(tv.tv_sec) + 1e-6 * tv.tv_usec; }

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "localhost";
  return name;
}

}  // namespace

struct LocalExecutor::Child {
  CaseTask task;
  pid_t pid = 0;  ///< also the process group id
  Clock::time_point started;
  Clock::time_point term_sent;  ///< when SIGTERM went out (timeout or cancel)
  bool timed_out = false;
  bool cancelled = false;
  bool kill_sent = false;
};

void LocalExecutorOptions::validate() const {
  if (parallel < 1) throw std::invalid_argument(fmt::format("parallel = {}: must be >= 1", parallel));
  if (!(timeout >= 0)) throw std::invalid_argument(fmt::format("timeout = {}: must be >= 0", timeout));
  if (!(grace >= 0)) throw std::invalid_argument(fmt::format("grace = {}: must be >= 0", grace));
}

int machine_cores() { return std::max(1u, std::thread::hardware_concurrency()); }

int local_parallel(const RunSettings& run, int cores) {
  const int ranks = std::max(1, run.ranks);
  const int parallel = run.parallel > 0 ? run.parallel : std::max(1, cores / ranks);
  if (!run.oversubscribe && parallel * ranks > cores)
    throw UserError(
        fmt::format("[run] parallel = {} cases x ranks = {} needs {} cores, this machine has {}; lower them or set "
                    "oversubscribe = true",
                    parallel, ranks, parallel * ranks, cores));
  return parallel;
}

std::unique_ptr<Executor> make_local_executor(const RunSettings& run, const fs::path& /*study_dir*/) {
  LocalExecutorOptions options;
  options.parallel = local_parallel(run, machine_cores());
  options.timeout = run.timeout;
  return std::make_unique<LocalExecutor>(options);
}

LocalExecutor::LocalExecutor(LocalExecutorOptions options) : m_options(options), m_host(host_name()) {
  m_options.validate();
}

LocalExecutor::~LocalExecutor() {
  if (!m_children.empty()) cancel_all();
}

int LocalExecutor::free_slots() const { return std::max(0, m_options.parallel - static_cast<int>(m_children.size())); }

int LocalExecutor::in_flight() const { return static_cast<int>(m_children.size() + m_ready.size()); }

std::vector<std::string> LocalExecutor::submit(const std::vector<CaseTask>& tasks) {
  if (static_cast<int>(tasks.size()) > free_slots())
    throw std::logic_error(fmt::format("LocalExecutor::submit: {} tasks, {} free slots", tasks.size(), free_slots()));
  std::vector<std::string> ids;
  for (const CaseTask& task : tasks) {
    const fs::path out = task.folder / k_run_output_file;
    const std::string folder = task.folder.string();
    const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error(fmt::format("{}: cannot open: {}", out.string(), std::strerror(errno)));
    const int null_fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
    const pid_t pid = ::fork();
    if (pid < 0) {
      ::close(fd);
      if (null_fd >= 0) ::close(null_fd);
      throw std::runtime_error(fmt::format("fork failed: {}", std::strerror(errno)));
    }
    if (pid == 0) {
      // Child: only async-signal-safe calls until exec.
      ::setpgid(0, 0);
      sigset_t all;
      sigemptyset(&all);
      sigprocmask(SIG_SETMASK, &all, nullptr);
      for (int s : {SIGINT, SIGTERM, SIGPIPE, SIGCHLD, SIGHUP, SIGQUIT}) ::signal(s, SIG_DFL);
      if (::chdir(folder.c_str()) != 0) ::_exit(126);
      if (null_fd >= 0) ::dup2(null_fd, 0);
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      char arg0[] = "./run.sh";
      char* argv[] = {arg0, nullptr};
      ::execv(arg0, argv);
      static const char message[] = "demsa: cannot execute ./run.sh\n";
      [[maybe_unused]] const ssize_t n = ::write(2, message, sizeof message - 1);
      ::_exit(127);
    }
    ::setpgid(pid, pid);  // also here: no race with the first kill(-pid)
    ::close(fd);
    if (null_fd >= 0) ::close(null_fd);
    auto child = std::make_unique<Child>();
    child->task = task;
    child->pid = pid;
    child->started = Clock::now();
    const ProcStat stat = read_proc_stat(pid);
    ids.push_back(fmt::format("{}:{}", pid, stat.ok ? stat.start_ticks : 0ULL));
    m_children.push_back(std::move(child));
  }
  return ids;
}

bool end_leftover_group(const std::string& job_id, double grace) {
  const auto colon = job_id.find(':');
  if (colon == std::string::npos) return false;
  long pgid = 0;
  unsigned long long start = 0;
  try {
    pgid = std::stol(job_id.substr(0, colon));
    start = std::stoull(job_id.substr(colon + 1));
  } catch (const std::exception&) {
    return false;
  }
  if (pgid <= 1 || pgid == ::getpgrp()) return false;
  if (group_members(pgid, start).empty()) return false;
  ::kill(static_cast<pid_t>(-pgid), SIGTERM);
  const Clock::time_point deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(grace));
  while (Clock::now() < deadline && !group_members(pgid, start).empty())
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  if (!group_members(pgid, start).empty()) ::kill(static_cast<pid_t>(-pgid), SIGKILL);
  return true;
}

void LocalExecutor::adopt(const std::vector<SubmittedCase>& tasks) {
  for (const SubmittedCase& submitted : tasks) {
    const bool ended = end_leftover_group(submitted.job_id, m_options.grace);
    FinishedCase finished{submitted.task, {}};
    finished.exit.lost = true;
    finished.exit.host = m_host;
    finished.exit.detail = ended ? "left running by an earlier demsa; ended" : "not running any more";
    m_ready.push_back(std::move(finished));
  }
}

void LocalExecutor::enforce_timeouts() {
  const Clock::time_point now = Clock::now();
  for (auto& child : m_children) {
    const double age = std::chrono::duration<double>(now - child->started).count();
    if (m_options.timeout > 0 && age > m_options.timeout && !child->timed_out && !child->cancelled) {
      child->timed_out = true;
      child->term_sent = now;
      ::kill(-child->pid, SIGTERM);
    }
    if ((child->timed_out || child->cancelled) && !child->kill_sent &&
        std::chrono::duration<double>(now - child->term_sent).count() >= m_options.grace) {
      child->kill_sent = true;
      ::kill(-child->pid, SIGKILL);
    }
  }
}

void LocalExecutor::reap(std::vector<FinishedCase>& finished) {
  for (auto it = m_children.begin(); it != m_children.end();) {
    Child& child = **it;
    int status = 0;
    struct rusage usage {};
    const pid_t got = ::wait4(child.pid, &status, WNOHANG, &usage);
    if (got == 0 || (got < 0 && errno == EINTR)) {
      ++it;
      continue;
    }
    FinishedCase done{child.task, {}};
    CaseExit& exit = done.exit;
    exit.wall_seconds = std::chrono::duration<double>(Clock::now() - child.started).count();
    exit.host = m_host;
    if (got == child.pid) {
      exit.cpu_seconds = seconds(usage.ru_utime) + seconds(usage.ru_stime);
      if (WIFEXITED(status)) exit.exit_code = WEXITSTATUS(status);
      if (WIFSIGNALED(status)) exit.signal = WTERMSIG(status);
    } else {
      exit.detail = fmt::format("wait4 failed: {}", std::strerror(errno));
    }
    if (child.timed_out || child.cancelled) {
      // Whatever the group leader did, ranks that outlive it are ended too.
      ::kill(-child.pid, SIGKILL);
      exit.timed_out = child.timed_out;
      exit.cancelled = child.cancelled && !child.timed_out;
      exit.exit_code = -1;
      exit.signal = 0;
    }
    finished.push_back(std::move(done));
    it = m_children.erase(it);
  }
}

std::vector<FinishedCase> LocalExecutor::poll(std::chrono::milliseconds wait) {
  std::vector<FinishedCase> finished = std::move(m_ready);
  m_ready.clear();
  const Clock::time_point deadline = Clock::now() + wait;
  while (true) {
    enforce_timeouts();
    reap(finished);
    if (!finished.empty() || m_children.empty() || Clock::now() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return finished;
}

void LocalExecutor::cancel_all() {
  const Clock::time_point now = Clock::now();
  for (auto& child : m_children) {
    if (child->cancelled || child->timed_out) continue;
    child->cancelled = true;
    child->term_sent = now;
    ::kill(-child->pid, SIGTERM);
  }
  std::vector<FinishedCase> finished;
  while (!m_children.empty()) {
    enforce_timeouts();
    reap(finished);
    if (!m_children.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  for (FinishedCase& f : finished) m_ready.push_back(std::move(f));
}

}  // namespace demsa::exec
