#pragma once
// `demsa calibrate DIR [DIR ...] --method bayes`: the posterior of the contact parameters given measured values
// with their uncertainty, on the metamodels of one or several studies (different experiments: a pile and an
// oedometer study that share parameter names).
//
//   1. prior: uniform on each parameter's design scale (log where the study's range is log) over the intersection of
//      the studies' ranges of that parameter (an empty intersection, or log in one study and linear in another, is
//      a UserError naming the parameter and both studies);
//   2. per target observable and study: the candidate metamodel with the best leave-one-out Q² (as the point
//      calibration); the likelihood is Gaussian with variance σ² (measurement) + the metamodel's variance (GP:
//      predictive; RSM/RBF: mean squared leave-one-out residual), sobol/posterior.hpp;
//   3. the affine-invariant ensemble sampler (sobol/ensemble_sampler.hpp), seeded, with τ, split R̂ and ESS; a chain
//      that has not converged fails the check (an "UNCONVERGED: ..." problem), its results written all the same;
//   4. DIR/calibration/ (or --out): posterior_samples.csv, posterior.json; with verify K, the real cases at the MAP
//      and at K posterior draws (run_point, handed in by the CLI), each kept as verify/<point>/<study>.json so that
//      a rerun measures only what is missing.
#include "orchestrator/analysis/measured_target.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/observables.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace demsa::analysis {

struct PosteriorOptions {
  std::vector<std::filesystem::path> dirs;  ///< study folders (at least one); the first holds the output
  std::filesystem::path out;                ///< output folder; empty: dirs[0]/calibration
  /// The measured values, each matched to the one study that measures its observable (or that its `study` names);
  /// sd 0: the metamodel's error alone.
  std::vector<MeasuredTarget> targets;
  /// Weight W >= 0 of a target by its label ("NAME" or "STUDY:NAME", MeasuredTarget::label): tempers its likelihood
  /// term. A target without one has weight 1.
  std::map<std::string, double> weights;
  std::string model;  ///< one metamodel for every target; empty: the best Q² per observable
  int walkers = 0;    ///< 0: the sampler's default (max(32, 4d))
  /// Kept steps per walker; 0 (the default): automatic, 3000 and then, while the chain is not converged (shorter
  /// than 50 τ, or split R̂ >= 1.05), continue it with max(60 τ, twice as many) steps (and a burn-in of at least
  /// 5 τ), at most k_auto_max_runs runs within k_max_auto_draws values in memory.
  int steps = 0;
  int burn_in = 1000;                 ///< discarded steps per walker (automatic steps may raise it)
  std::optional<std::uint64_t> seed;  ///< empty: the first study's seed
  int verify = -1;                    ///< -1: no verification; K >= 0: the MAP and K posterior draws
  std::function<study::PointRun(const study::StudyConfig& config, const std::filesystem::path& folder,
                                const std::vector<double>& unit)>
      run_point;
  /// Throws util::UserError naming the field ("PosteriorOptions.walkers") and the value.
  void validate() const;
};

/// Automatic steps: the first run's length, the most runs, and the most draw values (steps × walkers × (d + 1))
/// held in memory (200 MB).
inline constexpr int k_auto_first_steps = 3000;
inline constexpr int k_auto_max_runs = 3;
inline constexpr double k_max_auto_draws = 2.5e7;
/// The sampler's walkers start at the points of highest posterior density among this many uniform draws from the
/// prior box.
inline constexpr int k_start_points = 16384;

/// The checks of a posterior against its measurements (docs/reference/checks.md). A target fails when its measured
/// value lies in a tail of the posterior predictive holding less than k_predictive_tail (two-sided); a parameter is "at
/// bound" when more than k_bound_share of its draws lie in the outer k_bound_band of its prior range at one end.
inline constexpr double k_predictive_tail = 1e-3;
inline constexpr double k_bound_band = 0.02;
inline constexpr double k_bound_share = 0.5;
/// The verdict of a chain that has not converged (sobol::diagnose: fewer steps than 50 τ, or a split R̂ >= 1.05): it
/// opens the problem calibrate_posterior adds to PosteriorOutcome::problems, so the check fails (`demsa calibrate`
/// exits 1), as an unconverged truth fails the plan's (experiment_plan.hpp).
inline const std::string k_unconverged = "UNCONVERGED";
/// The printed posterior lists the pairs of parameters with |correlation| at least this (posterior.json all).
inline constexpr double k_print_correlation = 0.3;

struct PosteriorParameter {
  std::string name;
  double low = 0.0, high = 1.0;                                   ///< prior range (physical)
  bool log = false;                                               ///< prior uniform in log
  double mean = 0.0, map = 0.0, q05 = 0.0, q50 = 0.0, q95 = 0.0;  ///< physical
  double width_ratio = 0.0;  ///< 90 % posterior width / prior width, on the design scale
  double tau = 0.0, rhat = 0.0, ess = 0.0;
  /// "yes" (< 0.5), "partly" (< 0.8), "no"; "at bound" when the draws pile on an end of the prior range
  std::string identified;
  std::string at_bound;      ///< "", "low" or "high": the end of the prior range the draws pile on
  double bound_share = 0.0;  ///< share of the draws in the outer k_bound_band of the range at that end
  /// Parameters a study ties to this one (`same_as`): they take its value.
  std::vector<std::string> tied;
};

struct PosteriorTarget {
  std::string name;   ///< observable
  std::string study;  ///< study it belongs to
  std::string model;  ///< metamodel used
  double q2 = 0.0;
  double value = 0.0, sd = 0.0, weight = 1.0;
  double model_sd = 0.0;                                                    ///< metamodel standard deviation at the MAP
  double predicted_map = 0.0;                                               ///< metamodel prediction at the MAP
  double predictive_q05 = 0.0, predictive_q50 = 0.0, predictive_q95 = 0.0;  ///< posterior predictive
  /// Two-sided tail probability of the measured value under the posterior predictive (Gelman et al., Bayesian Data
  /// Analysis, 3rd ed., §6.3: a posterior predictive p-value); below k_predictive_tail the target fails its check.
  double tail_probability = 1.0;
  bool contradicted = false;  ///< the check failed
  /// The observable's range over the study's done samples (what the study can produce), and their number.
  double observed_low = 0.0, observed_high = 0.0;
  int samples = 0;
};

/// One verification point: the MAP or a posterior draw, run in every study.
struct VerifyPoint {
  std::string label;             ///< "map", "draw-1", ...
  std::vector<double> physical;  ///< parameter values
  struct Measured {
    std::string target;  ///< observable
    std::string study;
    std::optional<double> value;   ///< measured (empty when the run failed)
    double predicted = 0.0;        ///< metamodel mean at the point
    double low = 0.0, high = 0.0;  ///< 90 % predictive interval at the point (mean ± 1.645 total sd)
  };
  std::vector<Measured> measured;
  std::vector<std::string> errors;  ///< "study: why" for failed runs
};

/// Plain data; written to <out>/posterior.json.
struct PosteriorOutcome {
  std::vector<std::string> studies;
  std::vector<PosteriorParameter> parameters;
  std::vector<std::vector<double>> correlation;
  std::vector<PosteriorTarget> targets;
  int walkers = 0, steps = 0, burn_in = 0, draws = 0, evaluations = 0;
  std::uint64_t seed = 0;
  double acceptance = 0.0;
  bool converged = false;
  std::string advice;
  /// Automatic steps: the steps of each run, the last kept (one entry when the first run converged); empty when
  /// --steps was given.
  std::vector<int> auto_steps;
  double seconds = 0.0;  ///< sampling wall time, every run
  std::vector<VerifyPoint> verification;
  std::filesystem::path out;
  /// Failed checks, in words (a chain that has not converged: unconverged_problem; a measured value the posterior
  /// cannot produce): `demsa calibrate` exits 1. Everything computed is written all the same, for inspection.
  std::vector<std::string> problems;
  /// Warnings that do not fail the calibration (draws piled on a bound of the prior).
  std::vector<std::string> warnings;
};

PosteriorOutcome calibrate_posterior(const PosteriorOptions& options);

std::string posterior_to_json(const PosteriorOutcome& outcome);
/// Reads <out>/posterior.json back; throws util::UserError naming the file.
PosteriorOutcome read_posterior(const std::filesystem::path& file);
/// The printed tables (parameters, targets, diagnostics, verification) and, when a check failed, its problems.
std::string posterior_text(const PosteriorOutcome& outcome);
/// The problem of an unconverged chain: "UNCONVERGED: ..." with the convergence rule and `advice`
/// (sobol::ChainDiagnostics::advice: each diagnostic that failed, its value, its threshold and what to raise).
std::string unconverged_problem(const std::string& advice);
/// What failed, for the heading of the problems ("the chain has not converged; this posterior is not an answer").
std::string posterior_check_headline(const PosteriorOutcome& outcome);

}  // namespace demsa::analysis
