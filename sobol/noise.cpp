#include "sobol/noise.hpp"

#include "sobol/error.hpp"

#include <fmt/core.h>

#include <cassert>
#include <cmath>

namespace demsa::sobol {

namespace {

/// Regularised lower incomplete gamma P(a, x) (Numerical Recipes, 3rd ed., §6.2: gser and gcf).
double regularized_gamma_p(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_front = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    // Series: P = e^{-x} x^a / Γ(a) Σ_n x^n / (a (a+1) ... (a+n)).
    double ap = a, sum = 1.0 / a, term = sum;
    for (int n = 0; n < 1000; ++n) {
      ap += 1.0;
      term *= x / ap;
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return sum * std::exp(log_front);
  }
  // Continued fraction for Q = 1 − P (modified Lentz).
  constexpr double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_front) * h;
}

}  // namespace

double chi_square_cdf(double x, double nu) {
  assert(nu > 0.0);
  return regularized_gamma_p(0.5 * nu, 0.5 * x);
}

double chi_square_quantile(double p, double nu) {
  assert(p > 0.0 && p < 1.0 && nu > 0.0);
  double lo = 0.0, hi = std::max(1.0, nu);
  while (chi_square_cdf(hi, nu) < p) hi *= 2.0;
  for (int k = 0; k < 300 && hi - lo > 1e-12 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    (chi_square_cdf(mid, nu) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

NoiseEstimate pooled_noise_variance(const std::vector<std::vector<double>>& groups, double confidence) {
  if (!(confidence > 0.0 && confidence < 1.0))
    throw InputError(fmt::format("noise: confidence {}: must lie in (0, 1)", confidence));
  NoiseEstimate e;
  e.confidence = confidence;
  double ss = 0.0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const std::vector<double>& values = groups[g];
    for (double v : values)
      if (!std::isfinite(v)) throw InputError(fmt::format("noise: point {} holds the value {}", g, v));
    if (values.size() < 2) continue;
    double mean = 0.0;
    for (double v : values) mean += v;
    mean /= static_cast<double>(values.size());
    for (double v : values) ss += (v - mean) * (v - mean);
    ++e.points;
    e.values += static_cast<int>(values.size());
    e.dof += static_cast<int>(values.size()) - 1;
  }
  if (e.dof == 0) throw InputError("noise: no point has two values: the noise variance needs replicates");
  const double nu = static_cast<double>(e.dof);
  e.variance = ss / nu;
  e.lower = ss / chi_square_quantile(0.5 * (1.0 + confidence), nu);
  e.upper = ss / chi_square_quantile(0.5 * (1.0 - confidence), nu);
  return e;
}

}  // namespace demsa::sobol
