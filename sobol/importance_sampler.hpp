#pragma once
// Adaptive importance sampling of a posterior on a box: population Monte Carlo (Cappé, Guillin, Marin & Robert 2004,
// "Population Monte Carlo", J. Comput. Graph. Stat. 13(4), §2-3) with one Gaussian refitted each round to the
// weighted draws of the round before, mixed with the uniform box as a defensive component (Hesterberg 1995,
// "Weighted average importance sampling and defensive mixture distributions", Technometrics 37(2)): the weights
// stay below density / (share · box density), so a Gaussian that misses the tails shows as a low effective sample
// size rather than as an interval too narrow. Each round is judged by Kish's effective sample size (Σw)² / Σw².
//
// It answers where a posterior is narrow in a few directions and flat in the others (a calibration that pins two of
// seven parameters): there the ensemble sampler's walkers mix slowly along the flat directions (autocorrelation
// times of hundreds of steps), while independent draws from a proposal fitted to the posterior need no chain.
//
// Typical use:
//   ImportanceResult r = adaptive_importance_sample(log_density, lower, upper, prior_points, prior_log_density, o);
//   if (r.converged) { auto [q05, q95] = r.interval(j); }   // else: sample the posterior another way
#include "sobol/ensemble_sampler.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <utility>
#include <vector>

namespace demsa::sobol {

struct ImportanceOptions {
  int draws = 16384;       ///< draws per round, >= 100
  int rounds = 8;          ///< at most this many rounds, >= 1
  double min_ess = 400;    ///< a round whose effective sample size reaches this ends the sampling, > 0
  double defensive = 0.1;  ///< the uniform box's share of the proposal, in (0, 1)
  double inflation = 1.5;  ///< the Gaussian's sd over the weighted draws' sd, >= 1
  std::uint64_t seed = 1;
  /// Throws InputError naming the field, the value and the rule.
  void validate() const;
};

/// Plain data: the draws of the last rounds kept and their weights.
struct ImportanceResult {
  Eigen::MatrixXd points;   ///< draws × d
  Eigen::VectorXd weights;  ///< summing to 1; 0 outside the box and where the density is zero
  double ess = 0.0;         ///< Kish's effective sample size of the draws kept
  int rounds = 0;           ///< rounds drawn
  int evaluations = 0;      ///< log-density evaluations (points)
  bool converged = false;   ///< ess >= ImportanceOptions::min_ess
  /// The weighted `low` and `high` quantiles of parameter j: the first draws, in the order of coordinate j, where the
  /// cumulative weight reaches each. NaN, NaN when no draw was kept.
  std::pair<double, double> interval(int j, double low = 0.05, double high = 0.95) const;
};

/// The row indices of `points` in increasing order of column j (the walk order of weighted_interval).
std::vector<Eigen::Index> rows_by_column(const Eigen::MatrixXd& points, int j);

/// The weighted `low` and `high` quantiles of column j of `points`, walking its rows in `order` (sorted by column j):
/// the first rows where the cumulative weight reaches low · total and high · total (`total`: the weights' sum). The
/// last row's value when rounding leaves the sum short of high · total; NaN, NaN for an empty order.
std::pair<double, double> weighted_interval(const Eigen::MatrixXd& points, int j,
                                            const std::vector<Eigen::Index>& order, const Eigen::VectorXd& weights,
                                            double total, double low = 0.05, double high = 0.95);

/// Samples the density on the box [lower, upper] (zero outside). The first Gaussian is fitted to `points` weighted
/// by exp(`log_density_at_points`) (draws of the uniform prior, e.g., with their log-density), with a variance of at
/// least a quarter of their spacing squared in each direction so that a posterior narrower than their spacing is
/// still reached; each later round refits to the round before. Stops once the last rounds pooled (each draw weighted
/// by the density over its own round's proposal) reach options.min_ess, keeping the fewest last rounds that do, or
/// after options.rounds (then the last round, not converged). Deterministic for a seed. InputError: bad options, shapes
/// that do not match, or no point of finite density to start from.
ImportanceResult adaptive_importance_sample(const BatchLogDensity& log_density, const std::vector<double>& lower,
                                            const std::vector<double>& upper, const Eigen::MatrixXd& points,
                                            const Eigen::VectorXd& log_density_at_points,
                                            const ImportanceOptions& options);

}  // namespace demsa::sobol
