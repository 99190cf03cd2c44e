#pragma once
// Starting other programs: the one place where demsa forks, execs, makes pipes and waits (after ccache's
// util/exec.hpp and ninja's subprocess.h). Programs are started from an argv, never through a shell: argv[0] is
// looked up on demsa's PATH when it holds no '/', and every argument reaches the program exactly as given, so
// spaces, quotes and '$' in paths need no care.
//
// Every program starts with the default action for every signal and none blocked (demsa's Ctrl-C handler and
// any signal demsa ignores are not passed on), with stdin from /dev/null unless text is given, and with no
// descriptor of demsa's but 0, 1 and 2 as set up here (every other one is closed on exec).
//
// A program that cannot be started in the child (not found, not executable, no such working directory) is a
// result, as in a shell: exit status 127 when it was not found, 126 otherwise, with the reason as a message
// ("demsa: cannot run PROG: No such file or directory") on its stderr. When demsa itself cannot start it (no
// fork, no pipe), util::InternalError is thrown naming the program.
#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace demsa::util {

/// Absolute path of the running demsa (/proc/self/exe); "demsa" when it cannot be read.
std::filesystem::path self_executable();

/// Variables set (or replaced) in the environment of a program, on top of demsa's own.
using Environment = std::vector<std::pair<std::string, std::string>>;

// ------------------------------------------------------------------------ run to completion, output captured

struct CaptureOptions {
  std::optional<std::string> input;      ///< written to the program's stdin, which is then closed; nullopt: /dev/null
  bool merge_stderr = false;             ///< stderr into `out` too, in order (`err` stays empty)
  std::filesystem::path cwd;             ///< working directory of the program; empty: demsa's
  Environment env;                       ///< set for the program only
  std::chrono::milliseconds timeout{0};  ///< killed (SIGKILL) after this long; 0: no limit
  /// Polled at least every 200 ms while the program runs: once it returns true the program is killed (SIGKILL, with
  /// its process group) and the result says `stopped` (demsa's Ctrl-C, which a new process group does not pass on).
  std::function<bool()> should_stop;
  /// In a process group of its own: a Ctrl-C at the terminal reaches demsa only (which decides what to do, e.g.
  /// not leave an sbatch half-way), and a timeout kills what the program started too.
  bool new_process_group = true;
};

struct CaptureResult {
  /// As a shell's `$?`: the exit status; 128 + N when killed by signal N; 127 when the program was not found and
  /// 126 when it could not be started otherwise (see start_error).
  int exit_code = -1;
  int signal = 0;             ///< the signal that ended it; 0 when it exited
  bool timed_out = false;     ///< killed because options.timeout passed (then signal = SIGKILL)
  bool stopped = false;       ///< killed because options.should_stop returned true (then signal = SIGKILL)
  std::string start_error;    ///< why it could not be started ("cannot run PROG: ..."); empty when it ran
  std::string out;            ///< standard output (and standard error when merged)
  std::string err;            ///< standard error (empty when merged)
  double cpu_seconds = 0.0;   ///< user + system time of it and of the descendants it waited for (wait4's rusage)
  double wall_seconds = 0.0;  ///< from its start to its end (a monotonic clock)
};

/// Runs argv (at least the program) to its end and captures its output. Throws util::InternalError naming the
/// program when it cannot be started (fork, pipe).
CaptureResult run_capture(const std::vector<std::string>& argv, const CaptureOptions& options = {});

// ------------------------------------------------------------------------ started, left running, waited for later

struct SpawnOptions {
  std::filesystem::path output;  ///< stdout and stderr go to this file, created or truncated; required
  std::filesystem::path cwd;     ///< working directory of the program; empty: demsa's
  Environment env;               ///< set for the program only
};

/// How a spawned program ended.
struct ChildExit {
  int exit_code = -1;        ///< exit status when it exited (127 / 126 when it could not be started); else -1
  int signal = 0;            ///< the signal that ended it; 0 when it exited
  double cpu_seconds = 0.0;  ///< user + system time of it and of the descendants it waited for (wait4's rusage)
  std::string error;         ///< when it could not be waited for (wait4 failed): why; then the rest is unknown
};

/// A program started by spawn(), the leader of a process group of its own (pgid = pid), so that one signal
/// reaches it and everything it started (mpirun and its ranks). Move-only; the owner waits for it: a Child
/// destroyed before it was reaped leaves a zombie until demsa exits.
class Child {
 public:
  Child(int pid, unsigned long long start_ticks) : m_pid(pid), m_start_ticks(start_ticks) {}
  Child(Child&&) noexcept = default;
  Child& operator=(Child&&) noexcept = default;
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  int pid() const { return m_pid; }  ///< also its process group id
  /// Its start time in clock ticks since boot (/proc/PID/stat field 22); with the pid, names the group across a
  /// restart of demsa (see terminate_group). 0 when it could not be read.
  unsigned long long start_ticks() const { return m_start_ticks; }

  /// How it ended, reaping it (wait4, WNOHANG); nullopt while it runs. Once reaped, returns the same again.
  std::optional<ChildExit> try_wait();
  /// Blocks until it ends.
  ChildExit wait();
  /// Sends `signal` to its whole process group, also after the leader was reaped (ranks that outlive run.sh).
  void kill_group(int signal) const;

 private:
  int m_pid = 0;
  unsigned long long m_start_ticks = 0;
  std::optional<ChildExit> m_exit;
};

/// Starts argv in a process group of its own (setpgid), stdin from /dev/null, stdout and stderr to
/// options.output. Returns once the program runs (or has failed to start: then it exits 127 / 126 and the
/// reason is in the output file). Throws util::IoError when the output file cannot be opened and
/// util::InternalError naming the program when it cannot be started (fork, pipe).
Child spawn(const std::vector<std::string>& argv, const SpawnOptions& options);

// ------------------------------------------------------------------------ process groups (/proc)

/// Start time of process `pid` in clock ticks since boot (/proc/PID/stat field 22); nullopt when there is none.
std::optional<unsigned long long> process_start_ticks(int pid);

/// Live (not zombie) processes of process group `pgid` started at or after `since_ticks`, from /proc. With the
/// start time of the group's leader this tells a group demsa started from an unrelated one that got the same id.
std::vector<int> group_members(int pgid, unsigned long long since_ticks = 0);

/// Ends process group `pgid` if it still has members started at or after `since_ticks`: SIGTERM, then SIGKILL
/// to those left after `grace`. Never signals group 1 or demsa's own group. Returns true if it signalled.
bool terminate_group(int pgid, unsigned long long since_ticks, std::chrono::duration<double> grace);

}  // namespace demsa::util
