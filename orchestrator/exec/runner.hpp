#pragma once
// `demsa run`: a study from its file to committed observables (docs/explanation/method.md "A study"; ARCHITECTURE.md
// "exec/"), resumable.
//
//   design (sobol/) -> DIR/design.csv and the store's samples (first run only)
//   per sample still to do: a fresh case folder (case_writer.hpp) -> executor -> failure classification
//   -> observables measured from the dump (postprocess/) -> DIR/cases/NNNNNN/result.json written atomically
//   (temporary file, fsync, rename, fsync of the folder) -> run `done` and observables in one store transaction.
//
// With [design] replicates the store also holds the replicate cases (study::ReplicateRow: the first P design points
// again, each with another assembly seed); they are queued after the design's samples and run, fail, retry and
// recover exactly as samples do (their own case folders and run rows).
//
// The loop has the shape of ninja's build loop (src/build.h): a Plan (plan.hpp) holds what is left, the executor
// starts cases and reports those that ended (the CommandRunner), and each case that ended is finished (classified,
// measured, result.json written, committed in one transaction) before the plan is told how it went.
//
// A result counts only once that transaction is committed. After any crash (SIGKILL included), `demsa run` again:
//   - runs the store left `submitted` whose folder holds a complete result.json of that very run are committed
//     from it (the case is not run again);
//   - the other `submitted` runs are handed to the executor's adopt() (local: leftover process groups are ended)
//     and run again; SLURM: their array tasks are followed again;
//   - a batch's run rows are committed, with the ids the executor reserved for them (Executor::reserve_ids; SLURM:
//     "pending:TOKEN:INDEX", the token in the array job's comment), in one transaction before the executor
//     starts anything, and the real ids replace them once submit() returns. A crash in between leaves runs whose
//     array job adopt() finds by its token (its real id is then stored), so a case is never submitted twice;
//   - done samples are never submitted again: the store allows one done run per sample.
// SIGINT/SIGTERM (through the util::StopFlag) end the loop. The local executor's cases are cancelled and recorded
// `requeued`. SLURM tasks are cancelled (scancel) only when RunOptions::cancel_on_interrupt is set or
// RunOptions::ask_cancel says so; otherwise they keep running on the cluster, stay `submitted` in the store, and a
// later `demsa run` (adopt) or `demsa status` (collect_only) collects them.
//
// Two further modes, SLURM only:
//   - submit_only: every sample still to do is prepared and submitted; the runner returns at once, without polling
//     and without cancelling anything;
//   - collect_only (`demsa status`): the runs left `submitted` are adopted and polled once without waiting; the
//     ones that ended are measured and committed as in a full run; nothing is submitted, nothing is cancelled.
#include "orchestrator/exec/executor.hpp"
#include "orchestrator/exec/remeasure.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"

#include <csignal>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace demsa::exec {

struct RunOptions {
  std::filesystem::path study_file;   ///< the study (TOML)
  std::filesystem::path dir;          ///< study folder; empty = the study file's name without .toml
  bool dry_run = false;               ///< validate and write design + every case; run nothing
  bool new_study = false;             ///< discard an existing store, design and cases in `dir`
  bool analyze = true;                ///< run the analysis at the end (when enough samples are done)
  double progress_interval = 10.0;    ///< [s] between progress log lines when stderr is not a terminal
  bool quiet = false;                 ///< no progress output
  std::function<bool()> should_stop;  ///< polled in the loop; default: util::StopFlag::raised()
  bool submit_only = false;   ///< SLURM only: submit every case still to do and return (no polling, no cancelling)
  bool collect_only = false;  ///< SLURM only: commit what has ended, submit nothing, cancel nothing (demsa status)
  bool cancel_on_interrupt = false;  ///< SLURM: scancel the tasks in flight when stopped by a signal
  /// SLURM, when stopped with tasks in flight and cancel_on_interrupt is off: asked with the number of tasks in
  /// flight, returns true to scancel them. Empty: leave them running.
  std::function<bool(int)> ask_cancel;
  void validate() const;  ///< throws std::invalid_argument naming the field
};

struct RunSummary {
  std::filesystem::path dir;
  int samples = 0;
  int replicates = 0;                            ///< replicate cases of the study ([design] replicates)
  int replicates_done = 0;                       ///< of them, done
  int done = 0;                                  ///< done samples (all runs of the study)
  int done_now = 0;                              ///< committed by this invocation
  int recovered = 0;                             ///< committed from result.json left by an interrupted run
  int failed = 0;                                ///< samples whose last attempt failed and that have no attempt left
  std::vector<int> failed_samples;               ///< their indices
  std::map<std::string, int> failures_by_class;  ///< failed attempts of this invocation, by class
  bool interrupted = false;                      ///< stopped by a signal or should_stop
  std::string executor;                          ///< "local", "slurm" ("" for a dry run)
  int submitted = 0;                             ///< cases submitted by this invocation
  int collected = 0;                             ///< runs that ended and were recorded by this invocation
  int left_running = 0;  ///< SLURM tasks left queued or running on the cluster (still `submitted` in the store)
  bool dry_run = false;
  double seconds = 0.0;  ///< wall time of this invocation
  /// Set when the study file changed only how cases are measured: the finished cases measured again (remeasure.hpp).
  std::optional<RemeasureSummary> remeasured;
};

/// Runs (or resumes) a study. Throws util::UserError for a bad study file, a changed design-relevant setting (unless
/// new_study), a study folder another demsa run holds, or submit_only / collect_only with the local executor.
RunSummary run_study(const RunOptions& options);

/// The study's design: the unit-cube points of config.design drawn from config.seed, with their physical values.
/// Deterministic: an optimised LHS runs a fixed number of iterations (no wall-clock limit), so `demsa run` and
/// `demsa case --sample K` draw the same points on any machine and under any load.
std::vector<study::SampleRow> draw_design(const study::StudyConfig& config);

/// The `added` design points that extend the study's samples `existing` (the store's, refinement points included),
/// of which the first `design_samples` are the design's: the next points of the sequence for a Sobol' design
/// (sobol::extend_sobol), a maximin Latin-hypercube extension of all existing points otherwise (sobol::extend_lhs).
/// Deterministic in the study's seed and the counts. Sample indices continue existing's.
std::vector<study::SampleRow> design_extension(const study::StudyConfig& config,
                                               const std::vector<study::SampleRow>& existing, int design_samples,
                                               int added);

/// `demsa extend`: the study folder whose design grows, and to how many design points.
struct ExtendOptions {
  std::filesystem::path dir;
  int samples = 0;  ///< design samples after the extension, at least the design's
};

/// What an extension did.
struct Extension {
  std::filesystem::path dir;
  int added = 0;                ///< design points added (0: the design had that many already)
  int design_samples = 0;       ///< design samples now
  std::size_t all_samples = 0;  ///< every sample of the store now (design, extensions, refinements)
};

/// Grows the design of the study in `options.dir` (its frozen study file) to `options.samples` design points, as a
/// raised `[design] samples` does in `demsa run`: the new points are added to the store in one transaction,
/// design.csv and the frozen study file follow. Nothing runs. Throws util::UserError (naming ExtendOptions.samples)
/// for a count below the design's (shrinking), a count the study file refuses, or a study another demsa holds.
Extension extend_study(const ExtendOptions& options);

/// The extension in words: what was added and the `demsa run` that runs it.
std::string extension_text(const Extension& extension);
/// The replicate cases of `config` ([design] replicates) at the first P of `samples` (the design): repeats 1 .. R − 1
/// of each, with cases::replicate_assembly_seed. Empty when the study has none. Throws util::UserError when P exceeds
/// the design.
std::vector<study::ReplicateRow> replicate_rows(const study::StudyConfig& config,
                                                const std::vector<study::SampleRow>& samples);

}  // namespace demsa::exec
