#pragma once
// `demsa plan DIR [DIR ...]`: before any lab work, how narrowly each set of experiments would pin each parameter.
//
// A preposterior analysis on the studies' metamodels (Bayesian experimental design: Lindley 1956, "On a measure of
// the information provided by an experiment", Ann. Math. Stat. 27; Chaloner & Verdinelli 1995, "Bayesian
// experimental design: a review", Stat. Sci. 10, §2; Ryan et al. 2016, "A review of modern computational algorithms
// for Bayesian optimal experimental design", Int. Stat. Rev. 84, §3 on the nested Monte Carlo it needs):
//   1. the joint prior and one metamodel per measured observable, exactly as `demsa calibrate --method bayes` builds
//      them (joint_studies.hpp), and each observable's sd: the user's, else the study's DEM noise (pooled over its
//      replicate cases) combined with a stated default measurement error;
//   2. M truths drawn from the prior (or, with --near, from the prior restricted by rejection to where an
//      observable is predicted near a guessed value: von Neumann 1951's rejection sampling); for each, one simulated
//      measurement of every observable, m_k(u*) plus Gaussian noise of the likelihood's variance σ_k² + s_k²(u*) (so
//      that the planner's own 90 % intervals should miss the truth 10 % of the time: the coverage column checks it);
//   3. for every non-empty subset of the studies and every truth, the posterior of the subset's observables, its
//      90 % width over the prior width per parameter, and whether the truth fell outside the interval. The posterior
//      is computed by self-normalised importance sampling from one shared prior sample (Owen 2013, "Monte Carlo
//      theory, methods and examples", §9.2; its effective sample size (Σw)²/Σw², §9.3) where that sample holds at
//      least k_plan_min_ess effective points, and otherwise by the calibration's ensemble sampler
//      (sobol/ensemble_sampler.hpp, 2d + 2 walkers started at the prior sample's points of largest weight, the chain
//      lengthened until it converges; a truth whose chain does not converge fails the plan's check);
//   4. the averages over the truths, the cost of one more study of each subset (median CPU per done case × design
//      samples, per study), and a recommendation: the cheapest subset that brings every parameter with a total
//      index ST >= k_plan_sensitive for some measured observable to <= `goal` of its prior width, or else the subset
//      of the smallest largest width among those parameters.
#include "orchestrator/analysis/joint_studies.hpp"
#include "orchestrator/analysis/measured_target.hpp"
#include "orchestrator/study/config.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demsa::analysis {

/// At most this many studies (2^6 - 1 = 63 subsets).
inline constexpr int k_plan_max_studies = 6;
/// The default measurement error of an observable without --sd: this share of its median magnitude over the study.
inline constexpr double k_plan_measurement_share = 0.02;
/// A parameter counts for the recommendation when some measured observable has a total index at least this.
inline constexpr double k_plan_sensitive = 0.1;
/// The shared prior sample of the importance sampler, and the effective sample size below which the ensemble sampler
/// is used instead.
inline constexpr int k_plan_prior_points = 16384;
inline constexpr double k_plan_min_ess = 400.0;
/// Where the prior sample carries too little of a truth's posterior: adaptive importance sampling, at most
/// k_plan_importance_rounds rounds of k_plan_importance_draws draws, the last rounds pooled until their effective
/// sample size reaches k_plan_min_ess (sobol/importance_sampler.hpp). A fitted proposal keeps about half its draws
/// effective, so one round of 4096 usually suffices; pooling covers the rest.
inline constexpr int k_plan_importance_draws = 4096;
inline constexpr int k_plan_importance_rounds = 8;
/// The ensemble sampler's chain where adaptive importance sampling falls short too: k_plan_walkers_per_parameter · d +
/// 2 walkers started at the prior points of largest weight, k_plan_burn_in + k_plan_steps steps, the kept steps doubled
/// until the chain converges or reaches k_plan_max_steps (a truth whose chain does not converge fails the plan's
/// check).
inline constexpr int k_plan_walkers_per_parameter = 2;
inline constexpr int k_plan_burn_in = 300;
inline constexpr int k_plan_steps = 600;
inline constexpr int k_plan_max_steps = 19200;

/// The total sd of one measured observable, in the units demsa stores it (`demsa plan --sd`).
struct ObservableSd {
  QualifiedName observable;
  double sd = 0.0;  ///< > 0
};

struct PlanOptions {
  std::vector<std::filesystem::path> dirs;  ///< 1..k_plan_max_studies study folders
  std::filesystem::path out;                ///< empty: dirs[0]/plan
  /// The total sd of a measured observable (DEM noise and measurement together), overriding the default.
  std::vector<ObservableSd> sds;
  /// The observables measured; empty: each experiment's laboratory observables.
  std::vector<QualifiedName> observe;
  /// A guess of what the lab will measure (sd > 0). The truths are then drawn from the prior restricted to where the
  /// metamodel predicts the observable near the value (accepted with probability exp(-(m(u) - V)² / (2 sd²))), so
  /// that the widths are those expected around that value rather than over the whole prior.
  std::vector<MeasuredTarget> near;
  int truths = 50;                    ///< M, 2..1000
  double goal = 0.5;                  ///< the width the recommendation asks of every sensitive parameter, in (0, 1)
  std::string model;                  ///< one metamodel for every observable; empty: the best Q² per observable
  std::optional<std::uint64_t> seed;  ///< empty: the first study's seed
  /// Truths' posteriors computed side by side, 0..256; 0: one per core. The outcome does not depend on it.
  int threads = 0;
  /// Throws util::UserError naming the field ("PlanOptions.sds") and the value.
  void validate() const;
};

/// One measured observable of one study.
struct PlanObservable {
  std::string study, name, model;
  double q2 = 0.0;
  double sd = 0.0;              ///< total sd used
  double noise_sd = -1.0;       ///< DEM noise sd from the study's replicates (-1: not measured)
  double measurement_sd = 0.0;  ///< the default measurement error (0 when the user gave the sd)
  std::string source;           ///< "given", "replicates + default error", "default error (no replicates)"
  double median = 0.0, low = 0.0, high = 0.0;  ///< its median and range over the study's done samples
  int samples = 0;
  std::vector<double> total_index;  ///< ST per prior parameter on the study's own ranges (NaN: not a parameter of it)
  /// Per prior parameter, max - min of its main effect E[m(u) | u_j] over the study's own range of it, in the
  /// observable's units (NaN: not a parameter of it; empty in a plan.json written before it).
  std::vector<double> main_effect_range;
};

struct PlanSubset {
  std::vector<std::string> studies;          ///< study names
  std::vector<double> width;                 ///< mean 90 % width over prior width, per parameter, over the truths
  std::vector<double> width_q10, width_q90;  ///< spread of that width over the truths
  std::vector<double> outside;               ///< share of truths outside the 90 % interval, per parameter
  double outside_all = 0.0;                  ///< the same over all parameters
  double cpu_seconds = 0.0;                  ///< one more study of each experiment of the subset (NaN: unknown)
  int adapted = 0;                           ///< truths that needed adaptive importance sampling
  int sampled = 0;                 ///< truths that needed the ensemble sampler (the rest: importance sampling)
  int unconverged = 0;             ///< of those, the truths whose chain did not converge by k_plan_max_steps
  std::string unconverged_advice;  ///< the last such chain's diagnostics (not written to plan.json)
  bool meets_goal = false;         ///< every sensitive parameter at <= goal
  double worst_sensitive = 0.0;    ///< the largest width among the sensitive parameters
};

struct PlanStudy {
  std::string name;
  std::filesystem::path dir;
  std::string experiment;
  int samples = 0;            ///< design samples
  double cpu_per_case = 0.0;  ///< median CPU seconds of its done cases (NaN: none recorded)
};

/// A straight response pins a parameter to `goal` of its width when its main effect spans at least this many sds of
/// the observable over the parameter's range: a linear-Gaussian posterior's 90 % interval is 2 · 1.645 · sd / slope.
inline double plan_needed_effect(double goal) { return 2.0 * 1.645 / goal; }
/// The 90 % width over the prior width of a posterior that the data leave flat.
inline constexpr double k_plan_flat_width = 0.9;
/// plan_wide_reason: a width this much larger than a straight response's is put down to the response's shape or to
/// other parameters; a straight response's width this much above the goal is put down to the sd.
inline constexpr double k_plan_shared_excess = 1.25;
inline constexpr double k_plan_weak_excess = 1.1;

/// Why a parameter stays wider than `goal` although it is sensitive, from the largest ratio `effect` of its main effect
/// range to an observable's sd (`observable` names it), and the width a straight response of that size would leave
/// alone (plan_needed_effect(1) / effect, at most k_plan_flat_width). Where that is above the goal, the effect is too
/// weak for the sd, and the sd it would need at least is said (other parameters' uncertainty widens it further);
/// where the width is well above it, the effect is concentrated in part of the range or shared with other
/// parameters, which more precision alone may not cure. Both can hold.
std::string plan_wide_reason(const std::string& parameter, double width, const std::string& observable, double effect,
                             double goal);

/// Plain data; written to <out>/plan.json.
struct PlanOutcome {
  std::vector<std::string> parameters;
  std::vector<PlanStudy> studies;
  std::vector<PlanObservable> observables;
  std::vector<std::string> sensitive;  ///< parameters with ST >= k_plan_sensitive for some measured observable
  std::vector<PlanSubset> subsets;     ///< every non-empty subset, in binary order (1, 2, 1+2, 3, ...)
  int recommended = -1;                ///< index into subsets
  std::string recommendation;          ///< in words
  /// When no set meets the goal: for each sensitive parameter the best set leaves wider, why, from its largest main
  /// effect over an observable's sd (plan_wide_reason).
  std::vector<std::string> wide_reasons;
  int truths = 0;
  std::vector<std::string>
      near;  ///< the `near` guesses the truths were drawn under, as MeasuredTarget::text (none: the whole prior)
  double goal = 0.5;
  std::uint64_t seed = 0;
  int prior_points = 0;
  double seconds = 0.0;  ///< wall time of the computation
  std::filesystem::path out;
  /// What makes the widths untrustworthy (an unconverged posterior); empty: the check passed. `demsa plan` exits 1
  /// when it is not empty, after writing plan.json with `checks.passed` false.
  std::vector<std::string> problems;
};

PlanOutcome plan_experiments(const PlanOptions& options);

/// How the table marks subset i: "recommended" (the recommended set, which meets the goal), "best there is" (the
/// recommended set when none meets it), "meets goal", or "".
std::string plan_mark(const PlanOutcome& outcome, std::size_t i);

std::string plan_to_json(const PlanOutcome& outcome);
/// Reads <out>/plan.json back; throws util::UserError naming the file.
PlanOutcome read_plan(const std::filesystem::path& file);
/// The printed table (subsets as rows, parameters as columns, coverage, cost) and the recommendation.
std::string plan_text(const PlanOutcome& outcome);

}  // namespace demsa::analysis
