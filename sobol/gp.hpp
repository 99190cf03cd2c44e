#pragma once
// Gaussian-process (Kriging) regression (Rasmussen & Williams 2006, §2.7 for the explicit trend; Santner, Williams,
// Notz 2003, §3.3 for the concentrated likelihood): y(x) = f(x)ᵀβ + Z(x), Z a zero-mean GP with variance σ² and an
// anisotropic stationary correlation (squared exponential or Matérn 5/2) with one length scale per input, plus an
// optional nugget τ (correlation matrix R + τI) for noisy simulators. β by generalised least squares, σ² profiled
// out, length scales (and τ) by maximising the concentrated log-likelihood with NLopt (bounded, in log space, from
// several starts). Leave-one-out residuals at fixed hyperparameters in closed form (Dubrule 1983):
// e = Q y / diag(Q), Q = R⁻¹ - R⁻¹F (FᵀR⁻¹F)⁻¹ FᵀR⁻¹.
#include "sobol/metamodel.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace demsa::sobol {

class GaussianProcess final : public Metamodel {
 public:
  explicit GaussianProcess(const GpOptions& options = {});

  MetamodelKind kind() const override { return MetamodelKind::gp; }
  /// Needs at least d + trend terms + 2 samples (d + 3 with a constant trend: the hyperparameters it estimates and one
  /// more) and no duplicated points unless a nugget is estimated.
  void fit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) override;
  /// Fits with fixed hyperparameters (length scales, nugget ratio) instead of a likelihood search.
  void fit_with(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& lengths, double nugget);
  /// A model saved to a file: fit_with(x, y, lengths, nugget) (deterministic: the same Cholesky factor, LOO
  /// residuals and summary), then predicts with the saved trend coefficients β, weights α = R⁻¹(y - Fβ) and
  /// process variance σ². Throws InputError for wrong sizes or a σ² that is not positive.
  void restore(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& lengths, double nugget,
               const Eigen::VectorXd& beta, const Eigen::VectorXd& alpha, double process_variance);
  Eigen::VectorXd predict(const Eigen::MatrixXd& x) const override;
  /// predict() with the distances to the training points taken as exact differences and the sum k(x)ᵀα accumulated
  /// in long double: the weights α of a smooth kernel are large and cancel (cond(R) ~ 1e12), and the rounding of a
  /// double sum moved predictions by ~1e-9 relative. For `demsa predict`; the analysis, which predicts millions of
  /// points, keeps predict().
  Eigen::VectorXd predict_precise(const Eigen::MatrixXd& x) const;
  /// Predictive standard deviation (without the trend-estimation term) at the rows of x.
  Eigen::VectorXd predict_sd(const Eigen::MatrixXd& x) const;
  /// `count` joint draws (columns) of the latent function (without the noise of the nugget) at the rows of x from
  /// the model's posterior at its fitted hyperparameters, β with a flat prior (universal Kriging), by Matheron's
  /// rule: draw = predict(x) + Z(x) - K(Z(X) + ε), Z a prior draw, ε the noise at the training points, K the
  /// Kriging predictor (Chilès & Delfiner 2012, "Geostatistics", §7.3.1, conditioning by Kriging; Wilson et al.
  /// 2020, "Efficiently sampling functions from Gaussian process posteriors", ICML, eq. 8). Z is drawn in weight
  /// space from `features` random Fourier features of the kernel, shared by the draws (Rahimi & Recht 2007,
  /// "Random features for large-scale kernel machines", NeurIPS): the draws are functions, evaluated at any number
  /// of points in O(points × features) without a Cholesky factor of the points' covariance. Their mean is predict(x)
  /// exactly; their covariance is the posterior one up to the features' approximation of the kernel (relative
  /// error about 1/√features in the prior, less near the data). Deterministic in `seed`; the same seed gives the
  /// same functions, so calls on different x are consistent.
  Eigen::MatrixXd posterior_draws(const Eigen::MatrixXd& x, int count, std::uint64_t seed, int features = 1000) const;
  /// Posterior variance of the latent function at the rows of x, with the trend-estimation term (universal Kriging,
  /// Santner, Williams & Notz 2003 eq. 3.4.4), the variance posterior_draws() samples.
  Eigen::VectorXd latent_variance(const Eigen::MatrixXd& x) const;
  Eigen::VectorXd loo_residuals() const override { return m_loo; }
  MetamodelSummary summary() const override;
  std::unique_ptr<Metamodel> refit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) const override;
  bool interpolates() const override { return !m_options.nugget; }

  const GpOptions& options() const { return m_options; }
  const Eigen::VectorXd& lengths() const { return m_lengths; }          ///< θ_k
  double nugget() const { return m_nugget; }                            ///< τ (0 without nugget)
  double process_variance() const { return m_sigma2; }                  ///< σ²
  double log_likelihood() const { return m_log_likelihood; }            ///< concentrated, at the optimum
  const Eigen::VectorXd& trend_coefficients() const { return m_beta; }  ///< β, on trend_basis (1, x_1..x_d)
  const Eigen::VectorXd& weights() const { return m_alpha; }            ///< α = R⁻¹ (y - Fβ), in the units of y
  /// Added to the diagonal of every correlation matrix (relative to the unit variance) for a stable Cholesky factor.
  static double jitter();

  /// Concentrated log-likelihood of (x, y) for given hyperparameters (-inf when R is not positive definite).
  /// Exposed for tests and benchmarks.
  double concentrated_log_likelihood(const Eigen::VectorXd& lengths, double nugget) const;

 private:
  Eigen::MatrixXd trend_basis(const Eigen::MatrixXd& x) const;
  void finish_fit(const Eigen::VectorXd& lengths, double nugget);

  GpOptions m_options;
  Eigen::VectorXd m_lengths;
  double m_nugget = 0.0;
  double m_sigma2 = 0.0;
  double m_log_likelihood = 0.0;
  Eigen::VectorXd m_beta;
  Eigen::VectorXd m_alpha;  ///< R⁻¹ (y - Fβ)
  Eigen::LLT<Eigen::MatrixXd> m_llt;
  Eigen::VectorXd m_loo;
  int m_starts_done = 0;
  int m_evaluations = 0;
};

}  // namespace demsa::sobol
