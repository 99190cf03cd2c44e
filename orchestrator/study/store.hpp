#pragma once
// The study store: one SQLite database per study (DIR/study.db, README "A study") in WAL mode, so that `demsa status`
// reads while `demsa run` writes. It holds the samples of the design, every run attempt (state, attempt, exit
// status, failure class, wall and CPU time, host, log tail, executor job id), the measured observables, an event
// log, and the hash of the design-relevant settings.
//
// Invariants kept by the schema itself:
//   - a sample has at most one run in state `done` (a partial unique index), so a finished case can never be
//     counted twice;
//   - a run becomes `done` together with its observables in one transaction (record_done).
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

/// One design point.
struct SampleRow {
  int sample = 0;
  std::vector<double> unit;      ///< in [0,1]^d
  std::vector<double> physical;  ///< scaled to the study's bounds
};

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
  std::string job_id;   ///< executor's id (executor.hpp), "" until known
  int exit_code = -1;   ///< -1 when not exited normally or not finished
  int signal = 0;       ///< 0 when none
  std::string failure;  ///< failure class name (failure.hpp) for failed runs, else ""
  std::string message;  ///< one line about the outcome
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
  std::string failure;  ///< failure class name; "" for done
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
};

struct EventRow {
  double time = 0.0;  ///< Unix time [s]
  std::string kind;
  int sample = -1;  ///< -1 when not about one sample
  std::string message;
};

class Store {
 public:
  /// Opens (creating if needed) the database at `path`, in WAL mode with a busy timeout, and creates the schema.
  explicit Store(const std::string& path);
  /// Opens an existing database read-only (for status); throws std::runtime_error if it does not exist.
  static Store open_read_only(const std::string& path);
  ~Store();
  Store(Store&&) noexcept;
  Store& operator=(Store&&) noexcept;

  /// The design hash recorded by initialize(), or nothing for a new store.
  std::optional<std::string> design_hash() const;
  /// Records the design hash, the study name and the samples, in one transaction. Only on a new store.
  void initialize(const std::string& design_hash, const std::string& study_name, const std::vector<SampleRow>& samples);
  std::string study_name() const;

  std::vector<SampleRow> samples() const;

  /// A new run row in state submitted (job id filled later by set_job_id). Returns its id.
  long add_run(int sample, int attempt);
  /// New run rows in state submitted, each with its (provisional) job id, in one transaction: either all of them
  /// are in the store or none. Returns their ids, in the same order.
  std::vector<long> add_runs(const std::vector<NewRun>& runs);
  void set_job_id(long run, const std::string& job_id);
  /// Sets the job ids of several runs (run id, job id) in one transaction.
  void set_job_ids(const std::vector<std::pair<long, std::string>>& ids);
  /// Marks a run done and stores its observables, in one transaction. Throws if the sample already has a done run.
  void record_done(long run, const RunOutcome& outcome, const std::map<std::string, double>& observables);
  void record_failed(long run, const RunOutcome& outcome);
  void record_requeued(long run, const std::string& message);

  std::vector<RunRow> runs() const;
  std::vector<RunRow> runs_in_state(RunState state) const;
  std::optional<RunRow> run(long id) const;

  /// observables[sample][name] of the done samples.
  std::map<int, std::map<std::string, double>> observables() const;

  StoreCounts counts() const;

  void add_event(const std::string& kind, const std::string& message, int sample = -1);
  std::vector<EventRow> events() const;

  /// Result of `PRAGMA integrity_check` ("ok" when the file is sound).
  std::string integrity_check() const;

 private:
  explicit Store(std::unique_ptr<SQLite::Database> db);
  std::unique_ptr<SQLite::Database> m_db;
};

/// Current Unix time [s].
double unix_now();

}  // namespace demsa::study
