#pragma once
// Bayesian calibration on metamodels: the posterior of the parameters u (on the design scale, the prior's box of the
// unit cube) given measured values t_k with standard deviations σ_k,
//   log p(u | t) = const + Σ_k w_k [ -(m_k(u) - t_k)² / (2 v_k(u)) - log v_k(u) / 2 ],  v_k = σ_k² + s_k²(u),
// uniform prior on the box (Kennedy & O'Hagan 2001, "Bayesian calibration of computer models", JRSS B 63, §4: the
// emulator's own uncertainty is added to the observation variance). s_k² is the metamodel's variance: the GP's
// predictive variance at u (Rasmussen & Williams 2006, eq. 2.26), and for RSM/RBF the mean squared leave-one-out
// residual (a constant; PRESS/n). w_k = 1 is the plain likelihood; other weights temper a target's term.
// Sampled with sobol/ensemble_sampler.hpp; summarised per parameter (mean, MAP, quantiles, 90 % width over the
// prior's width, correlations).
#include "sobol/ensemble_sampler.hpp"
#include "sobol/metamodel.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace demsa::sobol {

/// Where a metamodel's input j comes from: offset + slope · u[column] (a study whose ranges differ from the prior's
/// box, on the same scale, sees the prior's coordinates through this affine map).
struct InputMap {
  int column = 0;
  double offset = 0.0;
  double slope = 1.0;
};

/// One measured value and the metamodel that predicts it.
struct GaussianTarget {
  std::string name;
  const Metamodel* model = nullptr;  ///< fitted (not owned)
  std::vector<InputMap> inputs;      ///< one per model input; empty: input j is u[j]
  double value = 0.0;                ///< t_k
  double sd = 0.0;                   ///< measurement standard deviation σ_k >= 0
  double weight = 1.0;               ///< w_k >= 0
};

/// The metamodel variance s_k² of a model that is not a GP (mean squared leave-one-out residual; NaN when the
/// residuals cannot be computed: a model fitted on as many samples as terms); for a GP the variance is predictive
/// and depends on u (0 is returned here).
double constant_model_variance(const Metamodel& model);

/// The log-posterior of the targets on the box, batched over rows of u. Validates the targets (InputError: no
/// target, an unfitted model, an input map outside the dimension, σ_k and s_k both zero, s_k unknown, σ_k² overflowing,
/// a bad weight).
class GaussianPosterior {
 public:
  GaussianPosterior(std::vector<GaussianTarget> targets, int dimension);
  int dimension() const { return m_dimension; }
  const std::vector<GaussianTarget>& targets() const { return m_targets; }
  /// Log-density (up to a constant) at the rows of u; points outside the box are the sampler's business.
  Eigen::VectorXd operator()(const Eigen::MatrixXd& u) const;
  /// Predictions (mean, rows × targets) and total predictive standard deviation sqrt(σ_k² + s_k²) at rows of u.
  void predict(const Eigen::MatrixXd& u, Eigen::MatrixXd& mean, Eigen::MatrixXd& sd) const;

 private:
  Eigen::MatrixXd model_inputs(const GaussianTarget& target, const Eigen::MatrixXd& u) const;
  std::vector<GaussianTarget> m_targets;
  std::vector<double> m_constant_variance;
  int m_dimension;
};

/// The posterior as the sampler's log-density (refers to `posterior`, which must outlive it).
BatchLogDensity posterior_function(const GaussianPosterior& posterior);

/// Summary of one parameter's posterior, in the sampler's coordinates.
struct MarginalSummary {
  double mean = 0.0;
  double map = 0.0;  ///< coordinate of the highest-density point visited
  double q05 = 0.0, q50 = 0.0, q95 = 0.0;
  double width_ratio = 0.0;  ///< (q95 - q05) / (upper - lower): about 0.9 for a parameter the data leave free
};

/// Quantile (linear interpolation between order statistics, Hyndman & Fan 1996 type 7) of v, p in [0,1].
double quantile(std::vector<double> v, double p);

/// Per-parameter summaries of the draws, and the correlation matrix of the draws.
std::vector<MarginalSummary> summarise_marginals(const EnsembleResult& result, const std::vector<double>& lower,
                                                 const std::vector<double>& upper);
Eigen::MatrixXd posterior_correlation(const Eigen::MatrixXd& draws);

}  // namespace demsa::sobol
