#pragma once
// The local executor (ARCHITECTURE.md "exec/"): runs up to K case folders at once on this machine, each `./run.sh`
// (which runs `mpirun -np R ...`) in a process group of its own, so that a timeout, a cancel or a restart of demsa ends
// mpirun and every rank with it. Cases are started, signalled and reaped through util/process.hpp (spawn, Child).
// Wall time from a monotonic clock, CPU time from wait4()'s rusage (run.sh and all the descendants it waited for),
// host from gethostname().
//
// Job ids are "PGID:START" (START = the group leader's start time in clock ticks since boot, /proc/PID/stat
// field 22), so that a restarted demsa can tell its own leftover process group from an unrelated process that
// got the same id. Adopted tasks are ended (SIGTERM, then SIGKILL) and reported `lost`: their exit status went
// with the demsa that started them.
#include "orchestrator/exec/executor.hpp"

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace demsa::exec {

struct LocalExecutorOptions {
  int parallel = 1;       ///< cases at once (K), >= 1
  double timeout = 0.0;   ///< per case [s]; 0 = none; >= 0
  double grace = 5.0;     ///< [s] between SIGTERM and SIGKILL on timeout and cancel, >= 0
  void validate() const;  ///< throws std::invalid_argument naming the field, value and rule
};

/// Cases at once for `run` on a machine with `cores` cores: run.parallel when set, else max(1, cores / ranks).
/// Throws util::UserError when parallel × ranks > cores and run.oversubscribe is off.
int local_parallel(const study::RunSettings& run, int cores);

/// Cores of this machine (std::thread::hardware_concurrency, at least 1).
int machine_cores();

class LocalExecutor final : public Executor {
 public:
  explicit LocalExecutor(LocalExecutorOptions options);
  ~LocalExecutor() override;  ///< cancels what is still running
  LocalExecutor(const LocalExecutor&) = delete;
  LocalExecutor& operator=(const LocalExecutor&) = delete;

  std::string name() const override { return "local"; }
  int free_slots() const override;
  std::vector<std::string> submit(const std::vector<CaseTask>& tasks) override;
  void adopt(const std::vector<SubmittedCase>& tasks) override;
  std::vector<FinishedCase> poll(std::chrono::milliseconds wait) override;
  int in_flight() const override;
  void cancel_all() override;

 private:
  struct Child;
  void reap(std::vector<FinishedCase>& finished);
  void enforce_timeouts();
  LocalExecutorOptions m_options;
  std::vector<std::unique_ptr<Child>> m_children;
  std::vector<FinishedCase> m_ready;  ///< ended and not yet returned (adopted, cancelled)
  std::string m_host;
};

/// End a process group left by an earlier demsa, if `job_id` ("PGID:START") still names it: SIGTERM, then
/// SIGKILL after `grace` seconds. Returns true if something was signalled.
bool end_leftover_group(const std::string& job_id, double grace);

}  // namespace demsa::exec
