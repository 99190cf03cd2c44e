#pragma once
// The study store: one SQLite database per study (DIR/study.db, docs/explanation/method.md "A study") in WAL mode, so
// that `demsa status` reads while `demsa run` writes. It holds the samples of the design, every run attempt (state,
// attempt, exit status, failure class, wall and CPU time, host, log tail, executor job id), the measured observables,
// an event log, and the hash of the design-relevant settings.
//
// Invariants kept by the schema itself:
//   - a sample has at most one run in state `done` (a partial unique index), so a finished case can never be
//     counted twice;
//   - a run becomes `done` together with its observables in one transaction (record_done);
//   - runs.failure is the name of a FailureClass (failure_class.hpp), `none` unless the run failed (CHECK
//     constraints).
//
// Schema versions (meta row `schema_version`):
//   1  demsa up to commit 6807f91: runs.failure free text, "" for runs that did not fail, no CHECK on it.
//   2  this demsa: runs.failure a FailureClass name, `none` for runs that did not fail, checked by the schema.
// Opening read-write migrates a version-1 store to version 2 in one transaction (the runs table is rebuilt with its
// CHECK constraints, "" becomes `none`, an event `migrated` records it); a name this demsa does not know is refused
// and leaves the file as it was. Opening read-only (status, analyze, report) writes nothing: a version-1 store is
// read as it is, "" read as FailureClass::none; the next `demsa run` migrates it. A store of a newer version than
// k_store_schema_version is refused by both (util::UserError naming the file): it was written by a newer demsa.
// The CHECK constraints also stop a version-1 demsa from writing to a version-2 store (it would store "").
#include "orchestrator/study/failure_class.hpp"

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace SQLite {
class Database;
}

namespace demsa::study {

/// The schema version this demsa writes (see the top of this file).
inline constexpr int k_store_schema_version = 2;

/// One design point.
struct SampleRow {
  int sample = 0;
  std::vector<double> unit;      ///< in [0,1]^d
  std::vector<double> physical;  ///< scaled to the study's bounds
};

/// A replicate case (DEM noise, [design] replicates): the design point `point` again, with the particle packing
/// drawn from another assembly seed. It is a case row of its own in the samples table (so runs, observables, the
/// one-done-run index and recovery treat it as any case), with the id replicate_sample_id(point, repeat), which does
/// not depend on the design's size: a design that grows keeps its replicates. The replicates table says which rows
/// are replicates; Store::samples() leaves them out, so everything that reads the design sees the design only.
struct ReplicateRow {
  int sample = 0;                ///< its case id, replicate_sample_id(point, repeat)
  int point = 0;                 ///< the design sample it repeats
  int repeat = 1;                ///< 1 .. R − 1 (0 would be the design point's own case)
  std::uint64_t seed = 0;        ///< its assembly seed
  std::vector<double> unit;      ///< the point's, in [0,1]^d
  std::vector<double> physical;  ///< the point's physical values
};

/// First case id of the replicates: above every design sample ([design] samples <= 100000).
inline constexpr int k_replicate_sample_base = 1000000;
/// Largest repeat count ([design] replicates repeats <= 1000).
inline constexpr int k_max_replicate_repeats = 1000;
/// The case id of repeat `repeat` (1 .. R − 1) of design point `point`.
int replicate_sample_id(int point, int repeat);

/// States of a run attempt.
enum class RunState {
  submitted,  ///< handed to the executor, not collected yet
  done,       ///< measured and committed
  failed,     ///< ended with a failure class
  requeued,   ///< cancelled or lost: did not count as an attempt, the sample runs again
};
std::string to_string(RunState state);
RunState run_state_from_string(const std::string& name);

/// One attempt at one sample.
struct RunRow {
  long id = 0;
  int sample = 0;
  int attempt = 1;
  RunState state = RunState::submitted;
  std::string job_id;                         ///< executor's id (executor.hpp), "" until known
  int exit_code = -1;                         ///< -1 when not exited normally or not finished
  int signal = 0;                             ///< 0 when none
  FailureClass failure = FailureClass::none;  ///< why it failed; none unless state is failed
  std::string message;                        ///< one line about the outcome
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;
  std::string host;
  std::string log_tail;
  double submitted_at = 0.0;  ///< Unix time [s]
  double finished_at = 0.0;   ///< Unix time [s], 0 while submitted
};

/// A run about to be submitted (Store::add_runs).
struct NewRun {
  int sample = 0;
  int attempt = 1;
  std::string job_id;  ///< provisional id from exec::Executor::reserve_ids ("" when the executor needs none)
};

/// How a run ended, as the runner records it.
struct RunOutcome {
  int exit_code = -1;
  int signal = 0;
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;
  std::string host;
  FailureClass failure = FailureClass::none;  ///< none for record_done, not none for record_failed
  std::string message;
  std::string log_tail;
};

/// Counts of samples by their current state.
struct StoreCounts {
  int samples = 0;              ///< samples in the design
  int done = 0;                 ///< with a done run
  int running = 0;              ///< with a submitted run
  int failed = 0;               ///< not done, not running, last run failed
  int pending = 0;              ///< never run, or requeued
  int attempts = 0;             ///< run rows, all states
  double mean_done_wall = 0.0;  ///< mean wall time of done runs [s]
  // Replicate cases (ReplicateRow), counted apart from the design's samples above.
  int replicates = 0;          ///< replicate cases
  int replicates_done = 0;     ///< with a done run
  int replicates_running = 0;  ///< with a submitted run
  int replicates_failed = 0;   ///< last run failed
};

/// One step of `demsa refine` (cli/refine.cpp): the indices after `samples` done samples and whether the loop went
/// on. Keyed by `samples` (a restarted refine that evaluates the same samples again replaces its row).
struct RefineStep {
  int iteration = 0;     ///< 1, 2, ... in the order of the steps
  int samples = 0;       ///< done samples the metamodels were fitted to
  double target = 0.0;   ///< the target half-width W of that refine
  double time = 0.0;     ///< Unix time [s]
  std::string decision;  ///< "reached", "budget", "added N", "stopped"
  /// Largest S1 or ST interval half-width of each observable (its best metamodel by Q²); NaN without intervals.
  std::map<std::string, double> max_half_width;
  std::string indices_json;  ///< {observable: {"model", "S1": {p: [value, lower, upper]}, "ST": {...}}}
};

/// What one finished case cost against what was predicted for it (exec/cost.hpp), one row per done run: written by
/// `demsa run` when it commits the run.
struct CaseCostRow {
  long run = 0;
  int sample = 0;
  double cap_atom_steps = 0.0;         ///< the schedule's cap (Experiment::case_cost)
  double predicted_atom_steps = 0.0;   ///< the expectation before it ran (the cap x the study's ratio then)
  double predicted_cpu_seconds = 0.0;  ///< ... at the rate known then [s]; 0 when none was known
  double atom_steps = 0.0;             ///< actual: the sum of its log's `Loop time` lines, steps x atoms
  /// actual CPU [s]: the run's rusage when the executor measured one, else the sum of the loop times x procs
  double cpu_seconds = 0.0;
};

/// One finished case measured again from its files after its study changed only how cases are measured
/// (Store::record_remeasured).
struct RemeasuredCase {
  long run = 0;  ///< the sample's latest run: done, or failed in its measurement
  /// The observables measured now; nothing when the measurement failed (`message` says why).
  std::optional<std::map<std::string, double>> observables;
  std::string message;
};

struct EventRow {
  double time = 0.0;  ///< Unix time [s]
  std::string kind;
  int sample = -1;  ///< -1 when not about one sample
  std::string message;
};

class Store {
 public:
  /// Opens (creating if needed) the database at `path`, in WAL mode with a busy timeout, and creates the schema;
  /// migrates a version-1 store; throws util::UserError for a store of a newer schema version.
  explicit Store(const std::string& path);
  /// Opens an existing database read-only (for status), version 1 or 2, writing nothing; throws std::runtime_error
  /// if it does not exist, util::UserError for a store of a newer schema version or a file that is no study store.
  static Store open_read_only(const std::string& path);
  ~Store();
  Store(Store&&) noexcept;
  Store& operator=(Store&&) noexcept;

  /// The schema version of the file: k_store_schema_version, or 1 for a version-1 store opened read-only.
  int schema_version() const;

  /// The design hash recorded by initialize(), or nothing for a new store.
  std::optional<std::string> design_hash() const;
  /// Records the design hash, the study name and the samples, in one transaction. Only on a new store.
  void initialize(const std::string& design_hash, const std::string& study_name, const std::vector<SampleRow>& samples);
  std::string study_name() const;

  /// The design's samples (replicate cases left out), by sample.
  std::vector<SampleRow> samples() const;

  /// Samples of the study's design (the first `[design] samples` rows, grown by extensions); the others were added
  /// by `demsa refine`. Stores without the count (all samples were the design's then) give the number of samples.
  int design_samples() const;
  /// Appends samples (their indices continue the store's) in one transaction with an event of `kind`. With a
  /// `design_hash`, they are design points: the hash and the design-sample count are updated in the same
  /// transaction (an extension of the design); without one, they are refinement points.
  void add_samples(const std::vector<SampleRow>& samples, const std::string& kind, const std::string& message,
                   const std::optional<std::string>& design_hash = std::nullopt);

  /// Records (or replaces, for the same `samples`) one step of `demsa refine`.
  void record_refine_step(const RefineStep& step);
  /// The steps of `demsa refine`, by samples; empty for a store that never refined.
  std::vector<RefineStep> refine_history() const;
  /// Adds the replicate cases (their case rows and their replicates rows) in one transaction; a replicate already in
  /// the store is left as it is (so this may run on every `demsa run`). Its point must be a sample of the design.
  void add_replicates(const std::vector<ReplicateRow>& replicates);
  /// Every replicate case, by point then repeat.
  std::vector<ReplicateRow> replicates() const;

  /// A new run row in state submitted (job id filled later by set_job_id). Returns its id.
  long add_run(int sample, int attempt);
  /// New run rows in state submitted, each with its (provisional) job id, in one transaction: either all of them
  /// are in the store or none. Returns their ids, in the same order.
  std::vector<long> add_runs(const std::vector<NewRun>& runs);
  void set_job_id(long run, const std::string& job_id);
  /// Sets the job ids of several runs (run id, job id) in one transaction.
  void set_job_ids(const std::vector<std::pair<long, std::string>>& ids);
  /// Marks a run done and stores its observables, in one transaction. Throws if the sample already has a done run
  /// (std::logic_error also when outcome.failure is not none).
  void record_done(long run, const RunOutcome& outcome, const std::map<std::string, double>& observables);
  /// Marks a run failed with outcome.failure (std::logic_error when it is none).
  void record_failed(long run, const RunOutcome& outcome);
  void record_requeued(long run, const std::string& message);
  /// The cases measured again under new measurement settings, the design hash that names those settings and an event
  /// `remeasured` with `message`, in one transaction: each run's observables are replaced; a run measured now is
  /// done (failure none), one whose measurement failed now is failed in its measurement, its observables removed.
  /// std::logic_error when a run is neither done nor failed.
  void record_remeasured(const std::string& design_hash, const std::vector<RemeasuredCase>& cases,
                         const std::string& message);

  std::vector<RunRow> runs() const;
  std::vector<RunRow> runs_in_state(RunState state) const;
  std::optional<RunRow> run(long id) const;

  /// observables[sample][name] of the done samples.
  std::map<int, std::map<std::string, double>> observables() const;

  StoreCounts counts() const;

  /// Records what a done run cost (replaces the run's row).
  void record_case_cost(const CaseCostRow& row);
  /// Every recorded case cost, by run id; empty for a store without the table (an older demsa's).
  std::vector<CaseCostRow> case_costs() const;
  void add_event(const std::string& kind, const std::string& message, int sample = -1);
  std::vector<EventRow> events() const;

  /// Result of `PRAGMA integrity_check` ("ok" when the file is sound).
  std::string integrity_check() const;

 private:
  explicit Store(std::unique_ptr<SQLite::Database> db);
  /// Sets the pragmas, migrates a version-1 store and creates the tables (read-write open).
  void create_or_migrate();
  std::unique_ptr<SQLite::Database> m_db;
};

/// Current Unix time [s].
double unix_now();

}  // namespace demsa::study
