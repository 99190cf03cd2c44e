#pragma once
// The interface every executor implements (ARCHITECTURE.md "exec/"): it runs case folders, each runnable by hand with
// `./run.sh`, and reports how each one ended. It knows nothing of the store, of designs or of observables: the
// study runner (runner.hpp) decides what to submit, classifies the outcome (failure.hpp), measures and
// commits.
//
// Life of a case in an executor:
//   reserve_ids({task}) -> provisional id (the runner stores it before anything starts)
//   submit({task}) -> job id (kept by the runner in the store, runs.job_id, in place of the provisional one)
//   poll(...)      -> the task comes back exactly once, as a FinishedCase
//   cancel_all()   -> every task still running comes back from poll() with `cancelled` set
// After a restart of demsa, the runner hands the job ids of submitted-but-not-collected tasks to adopt(); the
// executor either follows them again (SLURM: the jobs kept running) or ends what is left of them and reports
// them as `lost` (local: their parent died, their exit status is gone). Either way they come back from poll().
// A task whose stored id is still the provisional one (demsa died inside submit(), after the job may have been
// created) is looked up by it (SLURM: the submission's token in the job's comment); the real id found that way
// comes back from take_learned_ids(), and the runner stores it.
//
// Conventions for every executor:
//   - the case is started as `./run.sh` with the case folder as working directory;
//   - its standard output and error go, combined, to `run.out` in the case folder (study::k_run_output_file);
//   - an executor never deletes or rewrites files in the case folder other than run.out.
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/folder.hpp"

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace demsa::exec {

/// One attempt at one case.
struct CaseTask {
  int sample = -1;               ///< sample index in the design (0-based)
  int attempt = 1;               ///< 1 for the first attempt, 2 for the first retry, ...
  std::filesystem::path folder;  ///< absolute path of the case folder holding run.sh
};

/// How a case's process ended, as far as the executor can tell. Exactly one of: exited (exit_code >= 0),
/// killed by a signal (signal > 0), timed_out, cancelled, lost.
struct CaseExit {
  int exit_code = -1;         ///< exit status of run.sh when it exited normally; -1 otherwise
  int signal = 0;             ///< signal that killed run.sh (not by the executor); 0 if none
  bool timed_out = false;     ///< killed by the executor after study::RunSettings::timeout (or SLURM TIMEOUT)
  bool cancelled = false;     ///< stopped by cancel_all(): not the case's fault, run it again later
  bool lost = false;          ///< adopted after a restart but its outcome is unknown: run it again
  double wall_seconds = 0.0;  ///< from start to end (0 when unknown)
  double cpu_seconds = 0.0;   ///< user + system time of run.sh and all its descendants (0 when unknown)
  std::string host;           ///< host the case ran on ("" when unknown)
  std::string detail;         ///< free text from the executor (e.g. SLURM state), may be empty
};

/// A task that ended, with how it ended.
struct FinishedCase {
  CaseTask task;
  CaseExit exit;
};

/// A task that an earlier demsa process submitted and never collected, with the job id submit() returned then.
struct SubmittedCase {
  CaseTask task;
  std::string job_id;
};

/// Runs case folders. Not thread-safe: one study runner drives one executor from one thread.
class Executor {
 public:
  virtual ~Executor() = default;

  /// "local", "slurm".
  virtual std::string name() const = 0;

  /// How many more tasks submit() accepts right now (local: free slots; SLURM: a large number). The runner never
  /// submits more than this.
  virtual int free_slots() const = 0;

  /// Ids by which the tasks of the next submit(tasks) call (same tasks, same order) can be found again if demsa
  /// dies while submit() runs, after the executor has started them but before their real ids are stored. The
  /// runner records them in the store before it calls submit(). One per task; "" when the executor needs none
  /// (local: a process that started is found by its process group, and one that did not start leaves nothing).
  /// SLURM: "pending:TOKEN:INDEX", TOKEN marking the array job (sbatch --comment), INDEX the task in it.
  virtual std::vector<std::string> reserve_ids(const std::vector<CaseTask>& tasks) {
    return std::vector<std::string>(tasks.size());
  }

  /// Starts the tasks (at most free_slots()). Returns one job id per task, in the same order: an id the executor
  /// can find the task again by after a restart of demsa (local: "pgid:start-ticks"; SLURM: "jobid_taskid").
  /// Throws std::runtime_error if the tasks could not be started at all (e.g. sbatch failed); then none started.
  virtual std::vector<std::string> submit(const std::vector<CaseTask>& tasks) = 0;

  /// Takes over tasks submitted by an earlier demsa process. They come back from later poll() calls. A task whose
  /// id is a provisional one (reserve_ids) is looked up by it: found, it is followed and its real id comes back
  /// from take_learned_ids(); surely not started (or long ended), it comes back `lost`; while the lookup itself
  /// fails, it stays in flight.
  virtual void adopt(const std::vector<SubmittedCase>& tasks) = 0;

  /// The real ids found since the last call for adopted tasks that had a provisional id, each once. Default: none.
  virtual std::vector<SubmittedCase> take_learned_ids() { return {}; }

  /// Waits up to `wait` for tasks to end (returns at once when something already ended) and returns every task
  /// that ended since the last call, each exactly once. Enforces timeouts.
  virtual std::vector<FinishedCase> poll(std::chrono::milliseconds wait) = 0;

  /// Tasks submitted or adopted and not yet returned by poll().
  virtual int in_flight() const = 0;

  /// Stops every task in flight (local: SIGTERM to each process group, SIGKILL after a grace period; SLURM:
  /// scancel) and waits for them to end. They come back from the next poll() with `cancelled` set. (SLURM: an
  /// adopted task with a provisional id that squeue cannot be asked about stays in flight: it cannot be found to
  /// be cancelled, and it must not be submitted again.)
  virtual void cancel_all() = 0;
};

/// The executor the study's [run] settings ask for. `study_dir` is the study folder (SLURM keeps its batch
/// scripts there). Throws util::UserError for an executor that cannot be used here.
std::unique_ptr<Executor> make_executor(const study::RunSettings& run, const std::filesystem::path& study_dir);

/// The local executor (local_executor.hpp); every executor factory takes these same arguments.
std::unique_ptr<Executor> make_local_executor(const study::RunSettings& run, const std::filesystem::path& study_dir);

}  // namespace demsa::exec
