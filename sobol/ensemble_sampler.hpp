#pragma once
// Posterior sampling by the affine-invariant ensemble sampler of Goodman & Weare (2010, "Ensemble samplers with
// affine invariance", Comm. App. Math. Comp. Sci. 5(1)), with the stretch move updated in two halves as in emcee
// (Foreman-Mackey, Hogg, Lang, Goodman 2013, PASP 125, §2-3), and its convergence diagnostics:
//   - integrated autocorrelation time τ per parameter: the autocorrelation function averaged over walkers, summed
//     up to Sokal's automatic window M (the smallest M >= c τ(M), c = 5; Sokal 1997, "Monte Carlo methods in
//     statistical mechanics", §3; emcee's `integrated_time`);
//   - split R̂ per parameter, each walker a chain cut in halves (Gelman et al. 2013, "Bayesian Data Analysis", 3rd
//     ed., §11.4; Vehtari, Gelman, Simpson, Carpenter, Bürkner 2021, Bayesian Anal. 16(2), on its thresholds);
//   - effective sample size = draws / τ.
//
// Typical use:
//   EnsembleResult r = sample_ensemble(log_density, lower, upper, options);   // seeded, deterministic
//   ChainDiagnostics d = diagnose(r);  if (!d.converged) print(d.advice);
#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace demsa::sobol {

/// Log-density (up to a constant) at each row of x (m × d); -inf where the density is zero.
using BatchLogDensity = std::function<Eigen::VectorXd(const Eigen::MatrixXd& x)>;

/// The most values the kept draws may hold in memory (steps × walkers × (d + 1) doubles, the log-density included):
/// 1.5e8, 1.2 GB. EnsembleOptions::validate refuses a run that would need more, before any allocation.
inline constexpr double k_max_draw_values = 1.5e8;

struct EnsembleOptions {
  int walkers = 0;       ///< ensemble size, even and >= 2d + 2; 0: max(32, 4d) rounded up to even
  int steps = 3000;      ///< kept steps per walker (after burn-in), >= 10
  int burn_in = 1000;    ///< steps per walker discarded first, >= 0
  double stretch = 2.0;  ///< the stretch-move scale a > 1 (Goodman & Weare's a = 2)
  std::uint64_t seed = 12345;
  /// The starting ensemble (walkers × d, every row inside the box with a finite density), e.g. the last ensemble of
  /// an earlier run or points of high density found otherwise; empty: uniform draws from the box.
  Eigen::MatrixXd start;
  int walkers_for(int dimension) const;  ///< the ensemble size used for this dimension
  /// Throws InputError naming the field, value and rule; also when burn_in + steps, or the density evaluations
  /// (walkers × (burn_in + steps)), overflow an int, or the kept draws exceed k_max_draw_values.
  void validate(int dimension) const;
};

/// Plain data. Draws are ordered step-major: row s * walkers + w is walker w at kept step s.
struct EnsembleResult {
  int dimension = 0;
  int walkers = 0;
  int steps = 0;                ///< kept steps per walker
  Eigen::MatrixXd draws;        ///< (steps · walkers) × d
  Eigen::VectorXd log_density;  ///< at each draw
  Eigen::VectorXd best;         ///< the point of highest log-density visited (burn-in included)
  double best_log_density = 0.0;
  double acceptance = 0.0;  ///< fraction of accepted proposals over the kept steps
  std::uint64_t seed = 0;
  int evaluations = 0;  ///< log-density evaluations (points)
  /// Walker w's chain of parameter j (steps values).
  Eigen::VectorXd chain(int walker, int j) const;
  /// The walkers at the last kept step (walkers × d): the start of a run that continues this one.
  Eigen::MatrixXd last() const;
};

/// Initial walkers `options.start`, else uniform in the box [lower, upper] (drawn until each has a finite density;
/// InputError when 100 · walkers draws found none), then burn_in + steps stretch moves. Points outside the box have
/// density zero. A `start` of the wrong shape, outside the box or of zero density is an InputError.
EnsembleResult sample_ensemble(const BatchLogDensity& log_density, const std::vector<double>& lower,
                               const std::vector<double>& upper, const EnsembleOptions& options);

/// The `walkers` rows of `points` (n × d) of largest finite `log_density`, largest first: a starting ensemble
/// (EnsembleOptions::start) in the region of highest density among them. Started uniformly in the box, the stretch
/// move, whose steps scale with the ensemble's own spread (Goodman & Weare 2010, §3), must shrink the ensemble by
/// orders of magnitude to reach a posterior much narrower than the box, and in a chain of fixed length it may not:
/// its walkers stay apart and its widths are its starting spread. emcee's advice is to start the walkers in a small
/// region of high probability (Foreman-Mackey, Hogg, Lang, Goodman 2013, PASP 125, §4; emcee's "Fitting a model to
/// data" tutorial starts them in a small ball around the optimum); among points spread over the box, the best ones
/// also span a ridge or several modes where the density has them. InputError when fewer than `walkers` rows have a
/// finite density.
Eigen::MatrixXd highest_density_start(const Eigen::MatrixXd& points, const Eigen::VectorXd& log_density, int walkers);

/// Integrated autocorrelation time of an ensemble of chains (columns of `chains`, one walker each), emcee's
/// estimator: ACF averaged over walkers, Sokal's window with c = 5. A constant chain gives 1.
double integrated_time(const Eigen::MatrixXd& chains, double c = 5.0);

/// Split R̂ (BDA3 §11.4) of the chains (columns), each cut into a first and a second half.
double split_rhat(const Eigen::MatrixXd& chains);

struct ChainDiagnostics {
  std::vector<double> tau;   ///< integrated autocorrelation time per parameter [steps]
  std::vector<double> rhat;  ///< split R̂ per parameter
  std::vector<double> ess;   ///< effective sample size per parameter (draws / τ)
  double acceptance = 0.0;
  double max_tau = 0.0;
  double max_rhat = 0.0;
  double min_ess = 0.0;
  /// steps >= 50 max τ (emcee's rule) and every split R̂ < 1.05. The walkers of an ensemble are not independent
  /// chains, and a chain of n steps has split R̂ ≈ sqrt(1 + 2τ/n) from its own autocorrelation: Vehtari et al.'s
  /// 1.01 for independent chains would ask for ~100 τ; 1.05 still flags walkers stuck apart.
  bool converged = false;
  std::string advice;  ///< what to change when not converged ("" when converged)
};

/// The diagnostics of a run. `steps_name`/`walkers_name` are what the advice calls the two knobs ("raise the steps
/// per walker to at least 165"); a front end may name its own options instead.
ChainDiagnostics diagnose(const EnsembleResult& result, const std::string& steps_name = "the steps per walker",
                          const std::string& walkers_name = "the walkers");

}  // namespace demsa::sobol
