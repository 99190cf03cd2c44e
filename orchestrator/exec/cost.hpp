#pragma once
// What a study costs before and while it runs: the atom-steps of each case by its experiment's schedule
// (Experiment::case_cost), the CPU-seconds at a LIGGGHTS's measured rate (atom-steps per CPU-second, measured once per
// LIGGGHTS binary by a short standard run and cached, or the study's own finished cases), and the wall time with the
// executor's parallelism. docs/how-to/cost.md.
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demsa::exec {

// ---------------------------------------------------------------- the machine's rate
/// A LIGGGHTS's speed: atom-steps per CPU-second, and where the number comes from.
struct LiggghtsRate {
  double atom_steps_per_cpu_second = 0.0;
  std::string source;  ///< one line for the user: "measured now", "cached measurement of BINARY (FILE)", ...
};

/// What identifies a LIGGGHTS binary in the rate cache: its resolved path, size and modification time. A rebuilt or
/// replaced binary has another key, and its rate is measured again.
struct BinaryKey {
  std::string path;  ///< canonical path (symbolic links resolved)
  std::uintmax_t size = 0;
  std::int64_t mtime_ns = 0;
  bool operator==(const BinaryKey&) const = default;
};

/// The key of `executable` (a path, or a name on $PATH). Throws util::UserError when it does not exist.
BinaryKey binary_key(const std::string& executable);

/// The rate cache: $DEMSA_RATE_CACHE when set, else liggghts_cache_dir()/liggghts-rates.json
/// (${XDG_CACHE_HOME:-$HOME/.cache}/demsa/liggghts-rates.json). A JSON object {"rates": [{binary, size, mtime_ns,
/// atom_steps_per_cpu_second, atom_steps, cpu_seconds, measured_at}]}, one entry per binary.
std::filesystem::path rate_cache_file();

/// The input script of the standard run: 4046 spheres of 3 mm (E = 1e7 Pa, Hertz with tangential history and `cdt`
/// rolling friction, the templates' contact model) in an fcc packing of touching neighbours in a 40 mm box,
/// compacting under gravity: 1000 steps to start, then 4000 measured steps. About 3 s of CPU.
std::string rate_benchmark_input();

/// The window of plausible LIGGGHTS rates [atom-steps per CPU-second]: three decades either side of what the standard
/// run and the studies measured (3.5e6 to 6.3e6, docs/how-to/cost.md). A cached rate outside it, or an entry whose
/// fields have other types, is measured again; a standard run that measures one outside it is an error, not cached.
inline constexpr double k_min_plausible_rate = 1e3;
inline constexpr double k_max_plausible_rate = 1e10;

/// The rate of `executable` from `cache_file`, when its key is there with fields of the right types and a rate inside
/// [k_min_plausible_rate, k_max_plausible_rate]; none otherwise (a changed binary included).
std::optional<LiggghtsRate> cached_rate(const std::string& executable, const std::filesystem::path& cache_file);

/// The cached rate of `executable`, or, when there is none, the rate measured now by the standard run (in a temporary
/// folder beside the cache, one rank) and stored in `cache_file` under its key (a changed binary's entry replaced).
/// Throws util::UserError when the run fails or its log has no `Loop time` line.
LiggghtsRate machine_rate(const std::string& executable, const std::filesystem::path& cache_file);

// ---------------------------------------------------------------- a finished case
/// What a finished case cost: the sums over its log's `Loop time of X on N procs for S steps with M atoms` lines.
struct CaseActual {
  double atom_steps = 0.0;   ///< sum of S x M
  double cpu_seconds = 0.0;  ///< sum of X x N (LIGGGHTS's loop time on every rank) [s]
};

/// From CASE/log.liggghts; none when the case has no log or it has no `Loop time` line.
std::optional<CaseActual> case_actual(const std::filesystem::path& case_dir);

/// The schedule's cap of a written case (its experiment's case_cost on CASE/case.json); none when the folder has no
/// case.json or the experiment gives no estimate.
std::optional<double> case_cap_atom_steps(const study::StudyConfig& config, const std::filesystem::path& case_dir);

// ---------------------------------------------------------------- the probe
/// A short run of the study's first case before the study runs (`demsa run --dry-run --probe SECONDS`): the rate of
/// this study's own cases (its contact model, walls and particle count, which the standard run does not have), and,
/// when the case ends within the budget, its actual atom-steps against its cap. Stored in DIR/cost_probe.json.
struct ProbeResult {
  int sample = 0;
  double budget_seconds = 0.0;  ///< the wall-clock budget it was given
  bool finished = false;        ///< the case ran to its end within the budget
  double cap_atom_steps = 0.0;  ///< the case's cap when it was probed (a changed case invalidates the probe)
  double atom_steps = 0.0;      ///< of its complete LIGGGHTS runs (all of them when finished)
  double cpu_seconds = 0.0;     ///< the CPU those atom-steps took [s]
  double rate = 0.0;            ///< atom_steps / cpu_seconds
  std::string binary;           ///< the LIGGGHTS it ran (canonical path)
  std::int64_t binary_mtime_ns = 0;
  std::string measured_at;
  /// What the probe learnt of its case for the experiment's model (Experiment::probe_state: an oedometer's settled
  /// packing), null when nothing: passed to every case's case_cost.
  nlohmann::json state;
};

/// Runs the first case of the study in `dir` (design order) from a copy of its folder, DIR/.cost-probe, for at most
/// `budget_seconds` of wall time (then it is killed with what it started), and writes DIR/cost_probe.json. A case that
/// finishes gives its atom-steps over its run's CPU (wait4's rusage); a killed one its complete LIGGGHTS runs'
/// atom-steps over their loop time times the share of a core the run had (as the standard run). Throws
/// util::UserError when no LIGGGHTS run completed within the budget, or the case failed; util::StopRequested when
/// util::StopFlag was raised (Ctrl-C), after killing the run: nothing is stored then.
/// The shortest probe budget [s]: LIGGGHTS starts in a fraction of a second, and a budget below a millisecond would
/// round to no timeout at all.
inline constexpr double k_min_probe_seconds = 1.0;
ProbeResult probe_study(const study::StudyConfig& config, const std::filesystem::path& dir, double budget_seconds);
/// Throws util::UserError naming --probe when `budget_seconds` is below k_min_probe_seconds or not finite (before the
/// dry run writes anything).
void check_probe_budget(double budget_seconds);

/// DIR/cost_probe.json when it is there and still describes this study's first case and LIGGGHTS (the same cap, the
/// same binary); none otherwise.
std::optional<ProbeResult> read_probe(const study::StudyConfig& config, const std::filesystem::path& dir);

/// One line for the user: what the probe ran and measured.
std::string probe_text(const ProbeResult& probe);

// ---------------------------------------------------------------- the arithmetic
/// One case of the estimate: its cap, whether it may end early, and what it cost when it has finished.
struct CaseCostInput {
  int sample = 0;
  double cap_atom_steps = 0.0;
  bool may_end_early = false;
  std::optional<CaseActual> actual;  ///< set for a finished case
  /// The experiment's model of what it costs (CaseCost::expected_atom_steps; 0: none, the cap stands for it).
  double expected_atom_steps = 0.0;
};

struct EstimateInput {
  std::vector<CaseCostInput> cases;  ///< in the order they run
  std::optional<LiggghtsRate> rate;  ///< the machine's (a cached or new measurement); none: CPU and wall unknown
  std::string rate_failure;          ///< why there is none (the standard run failed), for rate_source
  std::optional<ProbeResult> probe;  ///< the study's probe: its rate and, when it finished, its actual / cap
  int ranks = 1;                     ///< MPI ranks per case: a case's wall time is its CPU time / ranks
  int slots = 1;                     ///< cases at once (local: [run] parallel or cores / ranks; SLURM: the throttle)
  /// The experiment's rate over the standard run's (CaseCost::rate_factor): applied to `rate`, the standard run's.
  double rate_factor = 1.0;
  std::string rate_factor_source;  ///< CaseCost::rate_factor_source
  std::string expected_source;     ///< CaseCost::expected of the cases' model, when they have one
  double expected_weight = 0.0;    ///< CaseCost::expected_weight: the model's weight in finished cases
};

struct CaseEstimate {
  int sample = 0;
  double cap_atom_steps = 0.0;
  double atom_steps = 0.0;    ///< expected: the actual of a finished case, else the cap x the study's ratio
  double cpu_seconds = 0.0;   ///< expected (actual when finished) [s]
  double wall_seconds = 0.0;  ///< cpu_seconds / ranks [s]
  std::optional<CaseActual> actual;
};

struct StudyEstimate {
  std::vector<CaseEstimate> cases;
  double atom_steps = 0.0;    ///< the whole study (finished cases at their actual cost)
  double cpu_seconds = 0.0;   ///< [s]
  double wall_seconds = 0.0;  ///< [s] every case on `slots` slots, in order, each started when a slot frees
  double remaining_atom_steps = 0.0;
  double remaining_cpu_seconds = 0.0;
  double remaining_wall_seconds = 0.0;
  int finished = 0;  ///< cases with an actual cost
  /// actual / expected over the finished cases that may end early (1 when none); expected is the experiment's model
  /// when it has one, else the cap
  double early_ratio = 1.0;
  double rate = 0.0;             ///< atom-steps per CPU-second used; 0 when none is known
  std::string rate_source;       ///< where it came from
  std::string atom_step_source;  ///< where the expected atom-steps came from
  int slots = 1;
  int ranks = 1;
  std::optional<ProbeResult> probe;  ///< the study's probe, when it has one that still holds
};

/// The estimate (docs/how-to/cost.md): a finished case counts its actual atom-steps and CPU; any other case its
/// expected atom-steps (the experiment's model, else its cap), times the ratio actual / expected of the study's
/// finished cases when it may end early and some have finished (against a model, n finished cases weigh n / (n + k),
/// the model the rest: Bühlmann, "Experience rating and credibility", ASTIN Bulletin 4 (1967) 199-207; k =
/// expected_weight), else, for a case without a model, of the probe, when it
/// ran its case to the end (one case's ratio to a model scatters more than the model errs over a study). The rate is
/// the study's own (its finished cases' atom-steps over their CPU) when it has any, else the probe's when it ran its
/// case to the end, else `input.rate` times `input.rate_factor`. The wall time schedules the cases in order on `slots`
/// slots, each case on the first slot to free (Graham's list scheduling, "Bounds on multiprocessing timing anomalies",
/// SIAM J. Appl. Math. 17 (1969) 416-429), as the local executor starts them.
StudyEstimate estimate(const EstimateInput& input);

// ---------------------------------------------------------------- a study folder
struct StudyCostOptions {
  bool measure_rate = true;  ///< run the standard run when no rate is cached (false: `demsa status`, the report)
  std::filesystem::path cache_file = rate_cache_file();
};

/// The estimate of the study in `dir` (config: its study file, LIGGGHTS resolved): every case of the store (design
/// samples then replicates) from its case folder's case.json, the finished ones from the store's case costs (or
/// their logs), the study's probe (read_probe), the rate of the study or of `config.run.liggghts` (cached or
/// measured), the executor's slots.
StudyEstimate estimate_study(const study::StudyConfig& config, const std::filesystem::path& dir,
                             const StudyCostOptions& options);

/// The estimate as JSON: {"estimate": {atom_steps, cpu_seconds, wall_seconds, remaining_*, rate, rate_source, ...,
/// "cases": [...]}}.
nlohmann::ordered_json estimate_json(const StudyEstimate& estimate);

/// The estimate as text lines for the terminal (the study's bill, the rate used and its source).
std::string estimate_text(const StudyEstimate& estimate);

/// The per-case table of predicted against actual (finished cases), Markdown, from the store's rows.
std::string predicted_vs_actual_table(const std::vector<study::CaseCostRow>& rows);

/// What the runner stores when a case is done: its cap, the prediction before it ran (from the rows of the cases
/// done before it, the study's probe and the cached machine rate, never measured here) and its actual cost from its
/// log. None when the case has no log with a `Loop time` line or no estimate.
std::optional<study::CaseCostRow> case_cost_row(const study::StudyConfig& config, const std::filesystem::path& dir,
                                                const std::filesystem::path& case_dir, long run, int sample,
                                                const std::vector<study::CaseCostRow>& before);

/// What `demsa --version` says of LIGGGHTS: the one found (PATH, DEMSA_LIGGGHTS) and the build of
/// scripts/build-liggghts.sh, each with its version, rolling models and measured speed, and which a study runs.
std::string liggghts_text();

}  // namespace demsa::exec
