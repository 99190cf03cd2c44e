#pragma once
// `demsa refine` (docs/how-to/refine.md): how sure the Sobol' indices of a study are, where the next cases go, and the
// loop that runs, analyses and grows the study until they are sure enough.
//
//   - refine_study: run what is left (handed in: the command line runs exec::run_study, so that analysis never runs
//     LIGGGHTS), fit the study's metamodels, compute the indices with their intervals, and stop once every S1 and ST
//     interval half-width is at most the target W (for every observable) or the study holds the most samples
//     allowed; otherwise add a batch of samples where the metamodels are least sure and go round again. Resumable
//     and kill -9 safe as `demsa run` is: a batch's samples enter the store in one transaction before any of them
//     runs, and a step's history row is keyed by its number of done samples, so a restarted refine runs what its
//     predecessor added and records each step once.
//   - check_refinement: for every observable, the metamodel with the largest Q² that gave indices with intervals
//     (fit.hpp's ranking), and the largest half-width (upper − lower)/2 of its S1 and ST intervals (those of
//     `[analysis] interval`: the design bootstrap or the GP posterior, sobol/metamodel_sobol.hpp). The loop stops
//     once every observable's is at most the target W.
//   - choose_refinement_points: a Gaussian process (the study's [analysis] GP settings) fitted to each analysable
//     observable, and a batch chosen by the largest summed integrated-variance reduction (ALC: Cohn 1996; Gramacy &
//     Lee 2009) among space-filling candidates kept apart from every sample of the store (sobol::select_by_variance,
//     sobol/augment.hpp). The Sobol' indices are variance ratios of the response integrated over the cube: they
//     are surer where the metamodel's integrated variance is small (directly so for the GP-posterior interval,
//     which draws from that variance). The candidates' correlations use each GP's fitted length scales (ARD), so
//     the points spread along the inputs the response varies fastest in. When no observable admits a GP (too few
//     samples), the batch is a maximin Latin-hypercube extension of the samples instead (sobol::extend_lhs).
#include "orchestrator/analysis/analysis_json.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace demsa::analysis {

/// How sure the indices of one analysis are.
struct RefinementCheck {
  /// Per observable: the largest S1/ST interval half-width of its best metamodel; NaN when no metamodel gave
  /// intervals (a constant observable, too few samples, bootstrap 0).
  std::map<std::string, double> max_half_width;
  std::map<std::string, std::string> model;  ///< the metamodel judged, per observable ("" when none)
  /// {observable: {"model", "max_half_width", "S1": {parameter: [value, lower, upper]}, "ST": {...}}}
  std::string indices_json;
  /// Every observable has a finite half-width at most `target`.
  bool reached(double target) const;
  /// The largest half-width over the observables (NaN when one has none).
  double worst() const;
};

RefinementCheck check_refinement(const AnalysisSummary& summary);

/// `batch` new samples (indices continue the store's) in the study's bounds, chosen as described at the top of this
/// file; deterministic in `seed`.
std::vector<study::SampleRow> choose_refinement_points(const study::StudyConfig& config, const study::Store& store,
                                                       int batch, std::uint64_t seed);

/// DIR/analysis/refine.csv: one row per step (iteration, samples, decision, target, max_half_width_<observable>).
std::string refine_history_csv(const std::vector<study::RefineStep>& steps);
/// DIR/analysis/refine.json: the steps with their indices.
std::string refine_history_json(const std::vector<study::RefineStep>& steps);

/// A half-width as the refine step prints and notes it: 4 decimals, or "none" when there is no interval.
std::string half_width_text(double width);

/// What running the study's cases came to in one round of refine_study.
struct RefineRun {
  bool interrupted = false;  ///< the runs stopped on a signal
  int done = 0;              ///< design and refinement samples done
  int samples = 0;           ///< design and refinement samples in the store
};

struct RefineOptions {
  std::filesystem::path dir;  ///< study folder (its frozen study file and store)
  double target = 0.0;        ///< largest admissible S1 or ST interval half-width W, > 0
  long batch = 4;             ///< samples added per step, >= 1
  long max_samples = 0;       ///< most samples the study may hold; 0: twice the design samples
  /// Runs what is left of the study (every sample of the store without a done run); required.
  std::function<RefineRun()> run_cases;
  std::function<bool()> should_stop;               ///< polled between the steps and in the analysis (empty: never)
  std::function<void(long max_samples)> on_start;  ///< before the first round, with the budget resolved
  std::function<void(const study::RefineStep&)> on_step;  ///< each step once recorded
};

/// How refine_study ended.
enum class RefineEnd {
  reached,              ///< every half-width is at most the target
  budget,               ///< the most samples allowed are spent
  stopped_in_runs,      ///< should_stop (or a signal) stopped the runs
  stopped_in_analysis,  ///< should_stop stopped an analysis of a step
  stopped,              ///< should_stop between steps, or in the closing analysis
};

struct RefineSummary {
  RefineEnd end = RefineEnd::stopped;
  long max_samples = 0;      ///< the budget resolved
  int done = 0;              ///< samples done at the last step
  double worst = 0.0;        ///< the largest half-width at the last step (NaN when one has none)
  AnalysisSummary analysis;  ///< the last analysis (reached, budget)
};

/// The refine loop (top of this file); writes DIR/analysis/ (the analysis, refine.csv and refine.json) and
/// DIR/design.csv at every step and records each step in the store. Throws util::UserError when fewer than two samples
/// are done.
RefineSummary refine_study(const RefineOptions& options);

/// What `demsa refine` prints of each step: "refine: step   3     24 samples  max half-width:  angle 0.041  -> ...".
/// "refine DIR: target half-width W, batches of B, at most M samples": the loop about to start (`on_start`).
std::string refine_start_text(const RefineOptions& options, long max_samples);

std::string refine_step_text(const study::RefineStep& step);
/// What it prints at the end: how to resume an interrupted refinement, or the analysis's tables and whether the target
/// half-width was reached or the budget spent (nothing for RefineEnd::stopped).
std::string refine_end_text(const RefineSummary& refined, const RefineOptions& options);

}  // namespace demsa::analysis
