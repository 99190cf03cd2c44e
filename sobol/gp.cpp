#include "sobol/gp.hpp"

#include "sobol/random.hpp"

#include <fmt/core.h>
#include <Eigen/LU>
#include <Eigen/QR>
#include <nlopt.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace demsa::sobol {

namespace {

/// Added to the diagonal of every correlation matrix for a stable Cholesky factor (relative to the unit variance).
constexpr double k_jitter = 1e-10;

double kernel_of_r2(GpKernel kernel, double r2) {
  if (kernel == GpKernel::squared_exponential) return std::exp(-0.5 * r2);
  const double r = std::sqrt(5.0 * r2);  // Matérn 5/2 (Rasmussen & Williams 2006, eq. 4.17)
  return (1.0 + r + r * r / 3.0) * std::exp(-r);
}

/// Correlation between the rows of a and b, inputs already divided by the length scales.
Eigen::MatrixXd cross_correlation(GpKernel kernel, const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  Eigen::MatrixXd r2 = -2.0 * a * b.transpose();
  r2.colwise() += a.rowwise().squaredNorm();
  r2.rowwise() += b.rowwise().squaredNorm().transpose();
  for (Eigen::Index j = 0; j < r2.cols(); ++j)
    for (Eigen::Index i = 0; i < r2.rows(); ++i) r2(i, j) = kernel_of_r2(kernel, std::max(r2(i, j), 0.0));
  return r2;
}

Eigen::MatrixXd scaled(const Eigen::MatrixXd& x, const Eigen::VectorXd& lengths) {
  return x * lengths.cwiseInverse().asDiagonal();
}

/// Correlation matrix of the training inputs (exact differences: no cancellation on the diagonal band).
Eigen::MatrixXd training_correlation(GpKernel kernel, const Eigen::MatrixXd& xs, double nugget) {
  const Eigen::Index n = xs.rows();
  const Eigen::MatrixXd points = xs.transpose();  // one column per point: contiguous differences
  Eigen::MatrixXd r(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    r(j, j) = 1.0 + nugget + k_jitter;
    for (Eigen::Index i = j + 1; i < n; ++i)
      r(i, j) = kernel_of_r2(kernel, (points.col(i) - points.col(j)).squaredNorm());
  }
  r.triangularView<Eigen::StrictlyUpper>() = r.transpose();
  return r;
}

/// Everything the concentrated likelihood produces (Santner, Williams, Notz 2003, §3.3.2).
struct LikelihoodState {
  bool ok = false;
  double log_likelihood = -std::numeric_limits<double>::infinity();
  Eigen::LLT<Eigen::MatrixXd> llt;
  Eigen::VectorXd beta;
  Eigen::VectorXd alpha;
  double sigma2 = 0.0;
};

LikelihoodState evaluate(GpKernel kernel, const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::MatrixXd& f,
                         const Eigen::VectorXd& lengths, double nugget) {
  LikelihoodState s;
  const Eigen::Index n = x.rows();
  s.llt.compute(training_correlation(kernel, scaled(x, lengths), nugget));
  if (s.llt.info() != Eigen::Success) return s;
  const Eigen::MatrixXd rinv_f = s.llt.solve(f);
  const Eigen::VectorXd rinv_y = s.llt.solve(y);
  // β = (Fᵀ R⁻¹ F)⁻¹ Fᵀ R⁻¹ y, by a pivoting QR of the small trend system.
  const Eigen::MatrixXd ftrf = f.transpose() * rinv_f;
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(ftrf);
  if (qr.rank() < ftrf.cols()) return s;
  s.beta = qr.solve(f.transpose() * rinv_y);
  const Eigen::VectorXd resid = y - f * s.beta;
  s.alpha = s.llt.solve(resid);
  s.sigma2 = resid.dot(s.alpha) / static_cast<double>(n);
  if (!(s.sigma2 > 0.0) || !std::isfinite(s.sigma2)) return s;
  const Eigen::MatrixXd& l = s.llt.matrixLLT();
  const double log_det = 2.0 * l.diagonal().array().log().sum();
  s.log_likelihood = -0.5 * static_cast<double>(n) * std::log(s.sigma2) - 0.5 * log_det;
  s.ok = std::isfinite(s.log_likelihood);
  return s;
}

}  // namespace

GaussianProcess::GaussianProcess(const GpOptions& options) : m_options(options) { m_options.validate(); }

Eigen::MatrixXd GaussianProcess::trend_basis(const Eigen::MatrixXd& x) const {
  if (m_options.trend == GpTrend::constant) return Eigen::MatrixXd::Ones(x.rows(), 1);
  Eigen::MatrixXd f(x.rows(), x.cols() + 1);
  f.col(0).setOnes();
  f.rightCols(x.cols()) = x;
  return f;
}

double GaussianProcess::concentrated_log_likelihood(const Eigen::VectorXd& lengths, double nugget) const {
  assert(m_x.rows() > 0 && lengths.size() == m_x.cols());
  const double mean = m_y.mean();
  const double sd = std::sqrt((m_y.array() - mean).square().mean());
  const Eigen::VectorXd yn = (m_y.array() - mean) / (sd > 0.0 ? sd : 1.0);
  return evaluate(m_options.kernel, m_x, yn, trend_basis(m_x), lengths, nugget).log_likelihood;
}

void GaussianProcess::fit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  const Eigen::Index d = x.cols();
  const int trend_terms = m_options.trend == GpTrend::constant ? 1 : static_cast<int>(d) + 1;
  // Maximum likelihood estimates d length scales, the process variance and the trend coefficients from the n points
  // (Rasmussen & Williams 2006, §5.4): with fewer points than that and one more, some length scale is not
  // determined and its optimum sits at a bound, so the indices (which the length scales alone rank) would say
  // nothing. Floor: n >= d + trend terms + 2 (d + 3 with a constant trend), the same order as rbf's d + 2 and
  // rsm1's d + 1. A refit with given hyperparameters (fit_with) estimates none of them and keeps the smaller floor.
  store_training_data(x, y, static_cast<int>(d) + trend_terms + 2);
  if (!m_options.nugget) check_no_duplicates(x);
  const double mean = y.mean();
  const double sd = std::sqrt((y.array() - mean).square().mean());
  if (!(sd > 0.0)) throw InputError(fmt::format("gp: every output equals {}: nothing to model", mean));
  const Eigen::VectorXd yn = (y.array() - mean) / sd;
  const Eigen::MatrixXd f = trend_basis(x);

  // Maximise the concentrated log-likelihood over log θ (and log τ) with BOBYQA from several starts. A measured noise
  // (options.noise_share) fixes τ instead: the search is over log θ alone, at the τ of `fixed_nugget`.
  const bool measured_noise = !std::isnan(m_options.noise_share);
  const bool search_nugget = m_options.nugget && !measured_noise;
  double fixed_nugget = measured_noise ? m_options.noise_share : 0.0;
  const unsigned dim = static_cast<unsigned>(d) + (search_nugget ? 1u : 0u);
  std::vector<double> lower(dim), upper(dim);
  for (Eigen::Index k = 0; k < d; ++k) {
    lower[static_cast<std::size_t>(k)] = std::log(m_options.min_length);
    upper[static_cast<std::size_t>(k)] = std::log(m_options.max_length);
  }
  if (search_nugget) {
    lower.back() = std::log(m_options.min_nugget);
    upper.back() = std::log(m_options.max_nugget);
  }
  auto unpack_point = [&](const double* p, Eigen::VectorXd& lengths, double& nugget) {
    lengths.resize(d);
    for (Eigen::Index k = 0; k < d; ++k) lengths(k) = std::exp(p[k]);
    nugget = search_nugget ? std::exp(p[d]) : fixed_nugget;
  };
  struct Context {
    const GaussianProcess* self;
    const Eigen::MatrixXd* x;
    const Eigen::VectorXd* y;
    const Eigen::MatrixXd* f;
    decltype(unpack_point)* unpack;
    int evaluations;
  } context{this, &x, &yn, &f, &unpack_point, 0};
  auto objective = [](unsigned, const double* p, double*, void* data) -> double {
    auto* c = static_cast<Context*>(data);
    ++c->evaluations;
    Eigen::VectorXd lengths;
    double nugget = 0.0;
    (*c->unpack)(p, lengths, nugget);
    const LikelihoodState s = evaluate(c->self->m_options.kernel, *c->x, *c->y, *c->f, lengths, nugget);
    return s.ok ? -s.log_likelihood : 1e300;
  };

  Random rng(m_options.seed);
  std::vector<double> best_p;
  double best_value = std::numeric_limits<double>::infinity();
  // `starts` starts; with `from` the first start is that point (a later pass of the measured-noise iteration).
  const auto search = [&](int starts, const std::vector<double>* from) {
    for (int start = 0; start < starts; ++start) {
      std::vector<double> p(dim);
      if (start == 0 && from)
        p = *from;
      else
        for (unsigned k = 0; k < dim; ++k) {
          const bool is_nugget = search_nugget && k + 1 == dim;
          // First start: θ = 0.5 (half the cube), τ = 1e-4; then log-uniform over a plausible part of the box.
          const double lo = is_nugget ? lower[k] : std::max(lower[k], std::log(0.05));
          const double hi = is_nugget ? upper[k] : std::min(upper[k], std::log(5.0));
          p[k] = start == 0 ? (is_nugget ? std::log(1e-4) : std::log(0.5)) : lo + (hi - lo) * rng.uniform();
          p[k] = std::clamp(p[k], lower[k], upper[k]);
        }
      nlopt::opt opt(nlopt::LN_BOBYQA, dim);
      opt.set_lower_bounds(lower);
      opt.set_upper_bounds(upper);
      opt.set_min_objective(objective, &context);
      opt.set_maxeval(m_options.max_evaluations);
      opt.set_xtol_abs(1e-4);
      opt.set_ftol_abs(1e-7);
      double value = std::numeric_limits<double>::infinity();
      try {
        opt.optimize(p, value);
      } catch (const std::exception&) {
        // roundoff-limited or similar: p holds the last point NLopt kept; judge it by its value below.
        value = objective(dim, p.data(), nullptr, &context);
      }
      if (value < best_value) {
        best_value = value;
        best_p = p;
      }
    }
  };
  search(m_options.starts, nullptr);
  m_starts_done = m_options.starts;
  // Measured noise: the model's noise variance σ² τ (scaled units) must equal noise_share. τ = noise_share / σ²(θ, τ)
  // by fixed-point iteration, the length scales searched again from the last optimum at each new τ (a few passes:
  // σ² moves little with τ once θ is found).
  for (int pass = 0; measured_noise && !best_p.empty() && best_value < 1e300 && pass < 6; ++pass) {
    Eigen::VectorXd lengths;
    double nugget = 0.0;
    unpack_point(best_p.data(), lengths, nugget);
    const LikelihoodState s = evaluate(m_options.kernel, x, yn, f, lengths, nugget);
    if (!s.ok) break;
    const double next = m_options.noise_share / s.sigma2;
    if (std::abs(next - fixed_nugget) <= 1e-3 * std::max(fixed_nugget, 1e-12)) break;
    fixed_nugget = next;
    const std::vector<double> from = best_p;
    best_value = std::numeric_limits<double>::infinity();
    search(1, &from);
    ++m_starts_done;
  }
  m_evaluations = context.evaluations;
  if (best_p.empty() || !(best_value < 1e300))
    throw NumericalError(
        "gp: the correlation matrix is singular for every length scale tried (duplicated or "
        "nearly duplicated points; enable the nugget)");
  Eigen::VectorXd lengths;
  double nugget = 0.0;
  unpack_point(best_p.data(), lengths, nugget);
  // Measured noise, last step: the same fixed point with the length scales held, to round-off (evaluations only).
  for (int step = 0; measured_noise && step < 100; ++step) {
    const LikelihoodState s = evaluate(m_options.kernel, x, yn, f, lengths, nugget);
    if (!s.ok) break;
    const double next = m_options.noise_share / s.sigma2;
    const bool converged = std::abs(next - nugget) <= 1e-12 * std::max(nugget, 1e-12);
    nugget = next;
    if (converged) break;
  }
  finish_fit(lengths, nugget);
}

void GaussianProcess::fit_with(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& lengths,
                               double nugget) {
  assert(lengths.size() == x.cols());
  const int trend_terms = m_options.trend == GpTrend::constant ? 1 : static_cast<int>(x.cols()) + 1;
  store_training_data(x, y, trend_terms + 2);
  if (!m_options.nugget) check_no_duplicates(x);
  m_starts_done = 0;
  m_evaluations = 0;
  finish_fit(lengths, nugget);
}

void GaussianProcess::finish_fit(const Eigen::VectorXd& lengths, double nugget) {
  const double mean = m_y.mean();
  const double sd = std::sqrt((m_y.array() - mean).square().mean());
  if (!(sd > 0.0)) throw InputError(fmt::format("gp: every output equals {}: nothing to model", mean));
  const Eigen::VectorXd yn = (m_y.array() - mean) / sd;
  const Eigen::MatrixXd f = trend_basis(m_x);
  LikelihoodState s = evaluate(m_options.kernel, m_x, yn, f, lengths, nugget);
  if (!s.ok)
    throw NumericalError(
        "gp: the correlation matrix is not positive definite (duplicated or nearly duplicated "
        "points; enable the nugget)");
  m_lengths = lengths;
  m_nugget = nugget;
  m_log_likelihood = s.log_likelihood;
  // Back to the units of y: the model of (y - mean)/sd is scaled and shifted.
  m_beta = s.beta * sd;
  m_beta(0) += mean;
  m_alpha = s.alpha * sd;
  // Two steps of iterative refinement of the GLS solution against y itself, the bordered system
  // [R F; Fᵀ 0][α; β] = [y; 0] (Higham 2002, "Accuracy and Stability of Numerical Algorithms", §12.1). R is
  // ill-conditioned for smooth kernels, and the rounding of (y - mean)/sd alone moves the predictions: on 160 points
  // in 3-D (squared exponential, cond(R) about 1e12) they were 2.3e-9 relative from the same GP solved in long
  // double, 1.2e-9 once refined.
  // The residuals are computed in long double (mixed-precision refinement, Higham 2002 §12.1: with cond(R) u < 1 it
  // converges to the solution of the system as R holds it in double, at the residual's precision); in double they
  // left the weights ~1e-9 from that solution.
  {
    using MatrixL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
    using VectorL = Eigen::Matrix<long double, Eigen::Dynamic, 1>;
    const MatrixL r = training_correlation(m_options.kernel, scaled(m_x, lengths), nugget).cast<long double>();
    const MatrixL fl = f.cast<long double>();
    const VectorL yl = m_y.cast<long double>();
    VectorL alpha = m_alpha.cast<long double>();
    VectorL beta = m_beta.cast<long double>();
    const Eigen::MatrixXd rinv_f = s.llt.solve(f);
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(f.transpose() * rinv_f);
    for (int step = 0; step < 2; ++step) {
      const Eigen::VectorXd top = (yl - r * alpha - fl * beta).cast<double>();
      const Eigen::VectorXd bottom = (-(fl.transpose() * alpha)).cast<double>();
      const Eigen::VectorXd d_beta = qr.solve(rinv_f.transpose() * top - bottom);
      alpha += s.llt.solve(top - f * d_beta).cast<long double>();
      beta += d_beta.cast<long double>();
    }
    m_alpha = alpha.cast<double>();
    m_beta = beta.cast<double>();
  }
  m_sigma2 = (m_y - f * m_beta).dot(m_alpha) / static_cast<double>(m_y.size());
  m_llt = std::move(s.llt);
  // Closed-form LOO (Dubrule 1983): e = Q y / diag(Q), Q = R⁻¹ - R⁻¹F (FᵀR⁻¹F)⁻¹ FᵀR⁻¹; Q y = R⁻¹(y - Fβ).
  const Eigen::Index n = m_x.rows();
  const Eigen::MatrixXd rinv = m_llt.solve(Eigen::MatrixXd::Identity(n, n));
  const Eigen::MatrixXd rinv_f = rinv * f;
  const Eigen::MatrixXd ftrf = f.transpose() * rinv_f;
  const Eigen::MatrixXd correction = rinv_f * ftrf.colPivHouseholderQr().solve(rinv_f.transpose());
  m_loo.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) m_loo(i) = m_alpha(i) / (rinv(i, i) - correction(i, i));
  m_fitted = true;
}

double GaussianProcess::jitter() { return k_jitter; }

void GaussianProcess::restore(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& lengths,
                              double nugget, const Eigen::VectorXd& beta, const Eigen::VectorXd& alpha,
                              double process_variance) {
  const Eigen::Index trend_terms = m_options.trend == GpTrend::constant ? 1 : x.cols() + 1;
  if (lengths.size() != x.cols())
    throw InputError(fmt::format("gp: {} length scales for {} inputs", lengths.size(), x.cols()));
  for (Eigen::Index k = 0; k < lengths.size(); ++k)
    if (!(lengths(k) > 0.0) || !std::isfinite(lengths(k)))
      throw InputError(fmt::format("gp: length scale {} is {}: must be a positive number", k + 1, lengths(k)));
  if (!(nugget >= 0.0) || !std::isfinite(nugget))
    throw InputError(fmt::format("gp: nugget {}: must be a number >= 0", nugget));
  if (nugget > 0.0 && !m_options.nugget)
    throw InputError(fmt::format("gp: nugget {} for a model without an estimated nugget", nugget));
  if (beta.size() != trend_terms)
    throw InputError(fmt::format("gp: {} trend coefficients for a {} trend in {} inputs (needs {})", beta.size(),
                                 to_string(m_options.trend), x.cols(), trend_terms));
  if (alpha.size() != x.rows())
    throw InputError(fmt::format("gp: {} weights for {} training points", alpha.size(), x.rows()));
  if (!(process_variance > 0.0) || !std::isfinite(process_variance))
    throw InputError(fmt::format("gp: process variance {}: must be a positive number", process_variance));
  fit_with(x, y, lengths, nugget);
  m_beta = beta;
  m_alpha = alpha;
  m_sigma2 = process_variance;
}

Eigen::VectorXd GaussianProcess::predict(const Eigen::MatrixXd& x) const {
  assert(m_fitted && x.cols() == m_x.cols());
  Eigen::VectorXd out(x.rows());
  const Eigen::MatrixXd centres = scaled(m_x, m_lengths);
  const Eigen::Index block = 2048;
  for (Eigen::Index start = 0; start < x.rows(); start += block) {
    const Eigen::Index rows = std::min(block, x.rows() - start);
    const Eigen::MatrixXd xb = x.middleRows(start, rows);
    out.segment(start, rows) =
        trend_basis(xb) * m_beta + cross_correlation(m_options.kernel, scaled(xb, m_lengths), centres) * m_alpha;
  }
  return out;
}

Eigen::VectorXd GaussianProcess::predict_precise(const Eigen::MatrixXd& x) const {
  assert(m_fitted && x.cols() == m_x.cols());
  const Eigen::MatrixXd centres = scaled(m_x, m_lengths).transpose();  // one column per training point
  const Eigen::MatrixXd points = scaled(x, m_lengths).transpose();
  const Eigen::MatrixXd trend = trend_basis(x);
  Eigen::VectorXd out(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    long double sum = 0.0L;
    for (Eigen::Index k = 0; k < m_beta.size(); ++k)
      sum += static_cast<long double>(trend(i, k)) * static_cast<long double>(m_beta(k));
    for (Eigen::Index j = 0; j < centres.cols(); ++j)
      sum += static_cast<long double>(kernel_of_r2(m_options.kernel, (points.col(i) - centres.col(j)).squaredNorm())) *
             static_cast<long double>(m_alpha(j));
    out(i) = static_cast<double>(sum);
  }
  return out;
}

Eigen::VectorXd GaussianProcess::predict_sd(const Eigen::MatrixXd& x) const {
  assert(m_fitted && x.cols() == m_x.cols());
  const Eigen::MatrixXd r = cross_correlation(m_options.kernel, scaled(x, m_lengths), scaled(m_x, m_lengths));
  const Eigen::MatrixXd rinv_r = m_llt.solve(r.transpose());
  Eigen::VectorXd out(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    out(i) = std::sqrt(std::max(m_sigma2 * (1.0 + m_nugget - r.row(i).dot(rinv_r.col(i))), 0.0));
  return out;
}

Eigen::MatrixXd GaussianProcess::posterior_draws(const Eigen::MatrixXd& x, int count, std::uint64_t seed,
                                                 int features) const {
  assert(m_fitted && x.cols() == m_x.cols() && count >= 1 && features >= 1);
  const Eigen::Index d = m_x.cols();
  const Eigen::Index n = m_x.rows();
  Random rng(seed);
  // Random Fourier features (Rahimi & Recht 2007): k(h) = E[cos(ωᵀh)] for ω drawn from the kernel's spectral
  // density. Squared exponential: ω_k ~ N(0, 1/θ_k²). Matérn 5/2: a multivariate Student t with 2ν = 5 degrees of
  // freedom and scale 1/θ_k (Rasmussen & Williams 2006, eq. 4.15), ω_k = z_k / θ_k · √(5/χ²_5).
  Eigen::MatrixXd omega(d, features);
  for (int j = 0; j < features; ++j) {
    double scale = 1.0;
    if (m_options.kernel == GpKernel::matern52) {
      double chi2 = 0.0;
      for (int k = 0; k < 5; ++k) chi2 += std::pow(rng.normal(), 2);
      scale = std::sqrt(5.0 / chi2);
    }
    for (Eigen::Index k = 0; k < d; ++k) omega(k, j) = rng.normal() * scale / m_lengths(k);
  }
  // Weight space: Z(x) = Σ_j a_j cos(ω_jᵀx) + b_j sin(ω_jᵀx), a_j, b_j ~ N(0, σ²/features).
  Eigen::MatrixXd weights(2 * features, count);
  const double weight_sd = std::sqrt(m_sigma2 / features);
  for (Eigen::Index c = 0; c < count; ++c)
    for (Eigen::Index j = 0; j < 2 * features; ++j) weights(j, c) = weight_sd * rng.normal();
  const auto prior = [&](const Eigen::MatrixXd& p) {
    const Eigen::ArrayXXd phase = (p * omega).array();
    Eigen::MatrixXd phi(p.rows(), 2 * features);
    phi.leftCols(features) = phase.cos().matrix();
    phi.rightCols(features) = phase.sin().matrix();
    return Eigen::MatrixXd(phi * weights);
  };
  // The prior draws at the training points plus the noise the nugget models (variance σ² τ).
  Eigen::MatrixXd v = prior(m_x);
  const double noise_sd = std::sqrt(m_sigma2 * m_nugget);
  for (Eigen::Index c = 0; c < count; ++c)
    for (Eigen::Index i = 0; i < n; ++i) v(i, c) += noise_sd * rng.normal();
  // Universal Kriging of v (the same linear map of the data as predict()): β_v by GLS, α_v = R⁻¹(v - F β_v).
  const Eigen::MatrixXd f = trend_basis(m_x);
  const Eigen::MatrixXd rinv_f = m_llt.solve(f);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(f.transpose() * rinv_f);
  const Eigen::MatrixXd beta_v = qr.solve(rinv_f.transpose() * v);
  const Eigen::MatrixXd alpha_v = m_llt.solve(v - f * beta_v);

  Eigen::MatrixXd out(x.rows(), count);
  const Eigen::MatrixXd centres = scaled(m_x, m_lengths);
  const Eigen::Index block = 1024;
  for (Eigen::Index start = 0; start < x.rows(); start += block) {
    const Eigen::Index rows = std::min(block, x.rows() - start);
    const Eigen::MatrixXd xb = x.middleRows(start, rows);
    const Eigen::MatrixXd fb = trend_basis(xb);
    const Eigen::MatrixXd kb = cross_correlation(m_options.kernel, scaled(xb, m_lengths), centres);
    const Eigen::VectorXd mean = fb * m_beta + kb * m_alpha;
    out.middleRows(start, rows) = prior(xb) - fb * beta_v - kb * alpha_v;
    out.middleRows(start, rows).colwise() += mean;
  }
  return out;
}

Eigen::VectorXd GaussianProcess::latent_variance(const Eigen::MatrixXd& x) const {
  assert(m_fitted && x.cols() == m_x.cols());
  const Eigen::MatrixXd r = cross_correlation(m_options.kernel, scaled(x, m_lengths), scaled(m_x, m_lengths));
  const Eigen::MatrixXd rinv_r = m_llt.solve(r.transpose());
  const Eigen::MatrixXd f = trend_basis(m_x);
  const Eigen::MatrixXd rinv_f = m_llt.solve(f);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(f.transpose() * rinv_f);
  // u = f(x) - Fᵀ R⁻¹ r(x): what the trend estimate adds (Santner, Williams & Notz 2003, eq. 3.4.4).
  const Eigen::MatrixXd u = trend_basis(x).transpose() - f.transpose() * rinv_r;
  const Eigen::MatrixXd a_inv_u = qr.solve(u);
  Eigen::VectorXd out(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    out(i) = std::max(m_sigma2 * (1.0 - r.row(i).dot(rinv_r.col(i)) + u.col(i).dot(a_inv_u.col(i))), 0.0);
  return out;
}

MetamodelSummary GaussianProcess::summary() const {
  assert(m_fitted);
  // Fitted values at the training points (with a nugget they differ from y).
  MetamodelSummary s = base_summary(predict(m_x), static_cast<int>(m_beta.size()));
  for (Eigen::Index k = 0; k < m_lengths.size(); ++k)
    s.parameters.push_back({fmt::format("length_{}", k + 1), m_lengths(k)});
  s.parameters.push_back({"process_variance", m_sigma2});
  s.parameters.push_back({"nugget", m_nugget});
  s.parameters.push_back({"log_likelihood", m_log_likelihood});
  s.parameters.push_back({"likelihood_evaluations", static_cast<double>(m_evaluations)});
  return s;
}

std::unique_ptr<Metamodel> GaussianProcess::refit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) const {
  assert(m_fitted);
  auto copy = std::make_unique<GaussianProcess>(m_options);
  copy->fit_with(x, y, m_lengths, m_nugget);
  return copy;
}

}  // namespace demsa::sobol
