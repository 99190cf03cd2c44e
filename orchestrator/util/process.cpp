#include "orchestrator/util/process.hpp"

#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cassert>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

extern char** environ;

namespace demsa::util {

namespace fs = std::filesystem;

std::filesystem::path self_executable() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path("demsa") : exe;
}

namespace {

using Clock = std::chrono::steady_clock;

/// A file descriptor closed when it goes out of scope.
class Fd {
 public:
  Fd() = default;
  explicit Fd(int fd) : m_fd(fd) {}
  Fd(Fd&& other) noexcept : m_fd(std::exchange(other.m_fd, -1)) {}
  Fd& operator=(Fd&& other) noexcept {
    if (this != &other) {
      close();
      m_fd = std::exchange(other.m_fd, -1);
    }
    return *this;
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() { close(); }
  int get() const { return m_fd; }
  bool open() const { return m_fd >= 0; }
  void close() {
    if (m_fd >= 0) ::close(m_fd);
    m_fd = -1;
  }

 private:
  int m_fd = -1;
};

/// Both ends of a close-on-exec pipe; throws InternalError naming `program`.
std::pair<Fd, Fd> make_pipe(const std::string& program) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw InternalError(fmt::format("cannot start {}: pipe: {}", program, std::strerror(errno)));
  return {Fd(fds[0]), Fd(fds[1])};
}

Fd open_dev_null(const std::string& program) {
  const int fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw InternalError(fmt::format("cannot start {}: /dev/null: {}", program, std::strerror(errno)));
  return Fd(fd);
}

/// What a child that failed before exec reports through its close-on-exec pipe (the pipe reads end-of-file
/// when the exec succeeds: the check posix_spawn makes).
struct StartFailure {
  int stage = 0;  ///< k_stage_chdir or k_stage_exec
  int error = 0;  ///< errno
};
constexpr int k_stage_chdir = 1;
constexpr int k_stage_exec = 2;

/// Everything the child needs, prepared before fork: between fork and exec the child makes only
/// async-signal-safe calls (no allocation), since another thread may hold the allocator's lock.
struct Launch {
  std::vector<std::string> env_storage;
  std::vector<char*> argv;
  std::vector<char*> envp;  ///< empty: demsa's environment
  std::string cwd;
  int in = -1;
  int out = -1;
  int err = -1;
  bool new_group = false;
};

Launch prepare(const std::vector<std::string>& argv, const fs::path& cwd, const Environment& env) {
  assert(!argv.empty());
  Launch launch;
  for (const std::string& arg : argv) launch.argv.push_back(const_cast<char*>(arg.c_str()));
  launch.argv.push_back(nullptr);
  if (!env.empty()) {
    for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
      const std::string entry(*e);
      const std::string name = entry.substr(0, entry.find('='));
      const bool replaced =
          std::any_of(env.begin(), env.end(), [&](const auto& variable) { return variable.first == name; });
      if (!replaced) launch.env_storage.push_back(entry);
    }
    for (const auto& [name, value] : env) launch.env_storage.push_back(name + "=" + value);
    for (std::string& entry : launch.env_storage) launch.envp.push_back(entry.data());
    launch.envp.push_back(nullptr);
  }
  launch.cwd = cwd.string();
  return launch;
}

/// A close-on-exec copy of `fd` above 2, made in the child before the dup2()s onto 0, 1 and 2: when demsa was
/// started with a standard descriptor closed, one source may be another's target and would be clobbered.
int lift(int fd) { return ::fcntl(fd, F_DUPFD_CLOEXEC, 3); }

[[noreturn]] void child_fail(int report, int stage, int exit_code) {
  const StartFailure failure{stage, errno};
  [[maybe_unused]] const ssize_t n = ::write(report, &failure, sizeof failure);
  ::_exit(exit_code);
}

/// fork + exec. Returns the pid and, when the child failed before exec, why.
std::pair<pid_t, std::optional<StartFailure>> start(const Launch& launch) {
  const std::string program = launch.argv[0];
  auto [report_read, report_write] = make_pipe(program);
  const pid_t pid = ::fork();
  if (pid < 0) throw InternalError(fmt::format("cannot start {}: fork: {}", program, std::strerror(errno)));
  if (pid == 0) {
    const int report = report_write.get();
    if (launch.new_group) ::setpgid(0, 0);
    // Signal actions and mask survive exec when ignored or blocked: the program gets the defaults.
    struct sigaction default_action {};
    default_action.sa_handler = SIG_DFL;
    for (int s = 1; s < NSIG; ++s)
      if (s != SIGKILL && s != SIGSTOP) ::sigaction(s, &default_action, nullptr);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    const int in = lift(launch.in);
    const int out = lift(launch.out);
    const int err = lift(launch.err);
    if (in < 0 || out < 0 || err < 0 || ::dup2(in, 0) < 0 || ::dup2(out, 1) < 0 || ::dup2(err, 2) < 0)
      child_fail(report, k_stage_exec, 126);
    // Descriptors demsa opened without O_CLOEXEC (a library's) must not reach the program: one kept open by a
    // long mpirun would hold a file lock or a pipe of demsa's. (Kernel 5.11; where missing, nothing changes.)
    ::close_range(3, ~0U, CLOSE_RANGE_CLOEXEC);
    if (!launch.cwd.empty() && ::chdir(launch.cwd.c_str()) != 0) child_fail(report, k_stage_chdir, 126);
    if (launch.envp.empty())
      ::execvp(launch.argv[0], launch.argv.data());
    else
      ::execvpe(launch.argv[0], launch.argv.data(), launch.envp.data());
    child_fail(report, k_stage_exec, errno == ENOENT ? 127 : 126);
  }
  if (launch.new_group) ::setpgid(pid, pid);  // in the parent too: no race with a kill(-pid) right after
  report_write.close();
  StartFailure failure;
  ssize_t n = 0;
  while ((n = ::read(report_read.get(), &failure, sizeof failure)) < 0 && errno == EINTR) {
  }
  if (n == static_cast<ssize_t>(sizeof failure)) return {pid, failure};
  return {pid, std::nullopt};
}

std::string start_message(const std::string& program, const std::string& cwd, const StartFailure& failure) {
  if (failure.stage == k_stage_chdir)
    return fmt::format("cannot run {}: working directory {}: {}", program, cwd, std::strerror(failure.error));
  return fmt::format("cannot run {}: {}", program, std::strerror(failure.error));
}

double seconds(const struct timeval& tv) { return static_cast<double>(tv.tv_sec) + 1e-6 * tv.tv_usec; }

ChildExit child_exit(int status, const struct rusage& usage) {
  ChildExit ended;
  ended.cpu_seconds = seconds(usage.ru_utime) + seconds(usage.ru_stime);
  if (WIFEXITED(status)) ended.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) ended.signal = WTERMSIG(status);
  return ended;
}

/// Blocks SIGPIPE in this thread while demsa writes to a program's stdin (a program that stops reading must give
/// EPIPE, not end demsa), and discards the SIGPIPE that raised meanwhile. Pipes have no MSG_NOSIGNAL.
class SigpipeGuard {
 public:
  SigpipeGuard() {
    sigset_t pipe_set;
    sigemptyset(&pipe_set);
    sigaddset(&pipe_set, SIGPIPE);
    sigset_t pending;
    sigpending(&pending);
    m_was_pending = sigismember(&pending, SIGPIPE) == 1;
    ::pthread_sigmask(SIG_BLOCK, &pipe_set, &m_old);
  }
  ~SigpipeGuard() {
    sigset_t pipe_set;
    sigemptyset(&pipe_set);
    sigaddset(&pipe_set, SIGPIPE);
    sigset_t pending;
    sigpending(&pending);
    if (!m_was_pending && sigismember(&pending, SIGPIPE) == 1) {
      const struct timespec zero {};
      while (::sigtimedwait(&pipe_set, nullptr, &zero) < 0 && errno == EINTR) {
      }
    }
    ::pthread_sigmask(SIG_SETMASK, &m_old, nullptr);
  }
  SigpipeGuard(const SigpipeGuard&) = delete;
  SigpipeGuard& operator=(const SigpipeGuard&) = delete;

 private:
  sigset_t m_old{};
  bool m_was_pending = false;
};

/// Reads what is there into `target`; closes `fd` at end-of-file or on an error.
void drain(Fd& fd, std::string& target) {
  char buffer[16384];
  const ssize_t n = ::read(fd.get(), buffer, sizeof buffer);
  if (n > 0)
    target.append(buffer, static_cast<size_t>(n));
  else if (n == 0 || (errno != EINTR && errno != EAGAIN))
    fd.close();
}

}  // namespace

// ---------------------------------------------------------------------------------------------- run_capture

CaptureResult run_capture(const std::vector<std::string>& argv, const CaptureOptions& options) {
  assert(!argv.empty());
  const std::string& program = argv[0];
  const Clock::time_point started = Clock::now();
  std::optional<SigpipeGuard> sigpipe;
  if (options.input) sigpipe.emplace();

  auto [out_read, out_write] = make_pipe(program);
  Fd err_read;
  Fd err_write;
  if (!options.merge_stderr) std::tie(err_read, err_write) = make_pipe(program);
  Fd in_read;
  Fd in_write;
  if (options.input)
    std::tie(in_read, in_write) = make_pipe(program);
  else
    in_read = open_dev_null(program);

  Launch launch = prepare(argv, options.cwd, options.env);
  launch.in = in_read.get();
  launch.out = out_write.get();
  launch.err = options.merge_stderr ? out_write.get() : err_write.get();
  launch.new_group = options.new_process_group;
  const auto [pid, failure] = start(launch);
  in_read.close();
  out_write.close();
  err_write.close();

  CaptureResult result;
  if (in_write.open()) ::fcntl(in_write.get(), F_SETFL, O_NONBLOCK);
  size_t written = 0;
  static const std::string no_input;
  const std::string& input = options.input ? *options.input : no_input;
  if (in_write.open() && input.empty()) in_write.close();
  const bool limited = options.timeout.count() > 0;
  const Clock::time_point deadline = Clock::now() + options.timeout;
  // One poll over stdin, stdout and stderr at once (ninja's SubprocessSet::DoWork): a program that writes much
  // before it reads its input, or fills stderr while demsa waits on stdout, cannot dead-lock with demsa.
  while (out_read.open() || err_read.open() || in_write.open()) {
    int wait_ms = -1;
    if (options.should_stop && options.should_stop()) {
      result.stopped = true;
      ::kill(options.new_process_group ? -pid : pid, SIGKILL);
      break;
    }
    if (limited) {
      // Rounded up: a truncated 0.4 ms left would kill the program before its time is up.
      const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) {
        result.timed_out = true;
        ::kill(options.new_process_group ? -pid : pid, SIGKILL);
        break;
      }
      wait_ms = static_cast<int>(std::min<long long>(left, 1000));
    }
    if (options.should_stop) wait_ms = wait_ms < 0 ? 200 : std::min(wait_ms, 200);
    pollfd fds[3] = {{out_read.get(), POLLIN, 0}, {err_read.get(), POLLIN, 0}, {in_write.get(), POLLOUT, 0}};
    if (::poll(fds, 3, wait_ms) < 0) {
      if (errno == EINTR) continue;
      throw InternalError(fmt::format("running {}: poll: {}", program, std::strerror(errno)));
    }
    if (out_read.open() && fds[0].revents != 0) drain(out_read, result.out);
    if (err_read.open() && fds[1].revents != 0) drain(err_read, result.err);
    if (in_write.open() && fds[2].revents != 0) {
      const ssize_t n = ::write(in_write.get(), input.data() + written, input.size() - written);
      if (n > 0) written += static_cast<size_t>(n);
      // EPIPE: the program does not read (all of) its input; that is its business
      if ((n < 0 && errno != EINTR && errno != EAGAIN) || written == input.size()) in_write.close();
    }
  }
  out_read.close();
  err_read.close();
  in_write.close();

  int status = 0;
  struct rusage usage {};
  while (::wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  result.cpu_seconds = seconds(usage.ru_utime) + seconds(usage.ru_stime);
  result.wall_seconds = std::chrono::duration<double>(Clock::now() - started).count();
  if (WIFEXITED(status)) {
    result.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    result.signal = WTERMSIG(status);
    result.exit_code = 128 + result.signal;
  }
  if (failure) {
    result.start_error = start_message(program, launch.cwd, *failure);
    (options.merge_stderr ? result.out : result.err) += "demsa: " + result.start_error + "\n";
  }
  return result;
}

// ---------------------------------------------------------------------------------------------- spawn

Child spawn(const std::vector<std::string>& argv, const SpawnOptions& options) {
  assert(!argv.empty());
  const std::string& program = argv[0];
  Fd output(::open(options.output.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
  if (!output.open()) throw IoError(fmt::format("{}: cannot open: {}", options.output.string(), std::strerror(errno)));
  const Fd null = open_dev_null(program);
  Launch launch = prepare(argv, options.cwd, options.env);
  launch.in = null.get();
  launch.out = output.get();
  launch.err = output.get();
  launch.new_group = true;
  const auto [pid, failure] = start(launch);
  if (failure) {
    // the child has exited 127 / 126; its output file says why, as a shell would
    const std::string message = "demsa: " + start_message(program, launch.cwd, *failure) + "\n";
    [[maybe_unused]] const ssize_t n = ::write(output.get(), message.data(), message.size());
  }
  return Child(pid, process_start_ticks(pid).value_or(0));
}

std::optional<ChildExit> Child::try_wait() {
  if (m_exit) return m_exit;
  int status = 0;
  struct rusage usage {};
  const pid_t got = ::wait4(m_pid, &status, WNOHANG, &usage);
  if (got == 0 || (got < 0 && errno == EINTR)) return std::nullopt;
  if (got == m_pid) {
    m_exit = child_exit(status, usage);
  } else {
    m_exit = ChildExit{};
    m_exit->error = fmt::format("wait4 failed: {}", std::strerror(errno));
  }
  return m_exit;
}

ChildExit Child::wait() {
  if (m_exit) return *m_exit;
  int status = 0;
  struct rusage usage {};
  pid_t got = 0;
  while ((got = ::wait4(m_pid, &status, 0, &usage)) < 0 && errno == EINTR) {
  }
  if (got == m_pid) {
    m_exit = child_exit(status, usage);
  } else {
    m_exit = ChildExit{};
    m_exit->error = fmt::format("wait4 failed: {}", std::strerror(errno));
  }
  return *m_exit;
}

void Child::kill_group(int signal) const { ::kill(-m_pid, signal); }

// ---------------------------------------------------------------------------------------------- /proc

namespace {

/// Fields of /proc/PID/stat that demsa uses.
struct ProcStat {
  char state = '?';
  long pgrp = 0;
  unsigned long long start_ticks = 0;
};

std::optional<ProcStat> read_proc_stat(long pid) {
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  std::string text;
  if (!in || !std::getline(in, text)) return std::nullopt;
  // The command name (field 2) is in parentheses and may contain spaces and ')': parse after the last ')'.
  const auto close = text.rfind(')');
  if (close == std::string::npos) return std::nullopt;
  std::istringstream rest(text.substr(close + 1));
  std::string field;
  std::vector<std::string> fields;  // fields[0] is field 3 (state)
  while (rest >> field) fields.push_back(field);
  if (fields.size() < 20) return std::nullopt;
  ProcStat stat;
  try {
    stat.state = fields[0].empty() ? '?' : fields[0][0];
    stat.pgrp = std::stol(fields[2]);            // field 5
    stat.start_ticks = std::stoull(fields[19]);  // field 22
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return stat;
}

}  // namespace

std::optional<unsigned long long> process_start_ticks(int pid) {
  const auto stat = read_proc_stat(pid);
  if (!stat) return std::nullopt;
  return stat->start_ticks;
}

std::vector<int> group_members(int pgid, unsigned long long since_ticks) {
  std::vector<int> members;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || !std::all_of(name.begin(), name.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
    const int pid = std::stoi(name);
    const auto stat = read_proc_stat(pid);
    if (stat && stat->pgrp == pgid && stat->state != 'Z' && stat->start_ticks >= since_ticks) members.push_back(pid);
  }
  return members;
}

bool terminate_group(int pgid, unsigned long long since_ticks, std::chrono::duration<double> grace) {
  if (pgid <= 1 || pgid == ::getpgrp()) return false;
  if (group_members(pgid, since_ticks).empty()) return false;
  ::kill(-pgid, SIGTERM);
  const Clock::time_point deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(grace);
  while (Clock::now() < deadline && !group_members(pgid, since_ticks).empty())
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  if (!group_members(pgid, since_ticks).empty()) ::kill(-pgid, SIGKILL);
  return true;
}

}  // namespace demsa::util
