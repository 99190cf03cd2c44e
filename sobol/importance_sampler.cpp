#include "sobol/importance_sampler.hpp"

#include "sobol/error.hpp"
#include "sobol/random.hpp"

#include <fmt/core.h>
#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace demsa::sobol {
namespace {

constexpr int k_max_draws = 1000000;  // draws × d doubles per round: 56 MB at d = 7
constexpr double k_log_two_pi = 1.8378770664093453;
constexpr int k_max_tries = 1000;  // draws of the Gaussian for one point inside the box

/// Weighted mean and covariance of the rows of x (weights summing to 1).
void weighted_moments(const Eigen::MatrixXd& x, const Eigen::VectorXd& w, Eigen::VectorXd& mean,
                      Eigen::MatrixXd& covariance) {
  mean = x.transpose() * w;
  const Eigen::MatrixXd centred = x.rowwise() - mean.transpose();
  covariance = centred.transpose() * w.asDiagonal() * centred;
}

/// Rounds pooled into one importance sample: the largest log weight over them, and their Kish size.
struct Pool {
  double top = -std::numeric_limits<double>::infinity();
  double ess = 0.0;
};

/// Kish's effective sample size of unnormalised weights.
double kish_ess(const Eigen::VectorXd& w) {
  const double total = w.sum();
  const double squares = w.squaredNorm();
  return squares > 0.0 ? total * total / squares : 0.0;
}

/// exp(log_w - top), exactly 0 where log_w is not finite (Eigen's vectorised exp turns -inf into a denormal).
Eigen::VectorXd weights_of(const Eigen::VectorXd& log_w, double top) {
  Eigen::VectorXd w(log_w.size());
  for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = std::isfinite(log_w(i)) ? std::exp(log_w(i) - top) : 0.0;
  return w;
}

}  // namespace

void ImportanceOptions::validate() const {
  if (draws < 100 || draws > k_max_draws)
    throw InputError(fmt::format("importance sampler: draws {} must be in 100..{}", draws, k_max_draws));
  if (rounds < 1) throw InputError(fmt::format("importance sampler: rounds {} must be >= 1", rounds));
  if (!(min_ess > 0) || !std::isfinite(min_ess))
    throw InputError(fmt::format("importance sampler: min_ess {} must be a finite number > 0", min_ess));
  if (!(defensive > 0 && defensive < 1))
    throw InputError(fmt::format("importance sampler: defensive {} must be in (0, 1)", defensive));
  if (!(inflation >= 1) || !std::isfinite(inflation))
    throw InputError(fmt::format("importance sampler: inflation {} must be a finite number >= 1", inflation));
}

std::pair<double, double> weighted_interval(const Eigen::MatrixXd& points, int j,
                                            const std::vector<Eigen::Index>& order, const Eigen::VectorXd& weights,
                                            double total, double low, double high) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  if (order.empty()) return {nan, nan};
  double cumulative = 0.0, q_low = nan;
  for (const Eigen::Index i : order) {
    cumulative += weights(i);
    if (std::isnan(q_low) && cumulative >= low * total) q_low = points(i, j);
    if (cumulative >= high * total) return {q_low, points(i, j)};
  }
  return {q_low, points(order.back(), j)};  // rounding left the sum a little below high · total
}

std::vector<Eigen::Index> rows_by_column(const Eigen::MatrixXd& points, int j) {
  std::vector<Eigen::Index> order(static_cast<size_t>(points.rows()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return points(a, j) < points(b, j); });
  return order;
}

std::pair<double, double> ImportanceResult::interval(int j, double low, double high) const {
  return weighted_interval(points, j, rows_by_column(points, j), weights, 1.0, low, high);
}

ImportanceResult adaptive_importance_sample(const BatchLogDensity& log_density, const std::vector<double>& lower,
                                            const std::vector<double>& upper, const Eigen::MatrixXd& points,
                                            const Eigen::VectorXd& log_density_at_points,
                                            const ImportanceOptions& options) {
  options.validate();
  const int d = static_cast<int>(lower.size());
  if (d < 1 || upper.size() != lower.size() || points.cols() != d || points.rows() != log_density_at_points.size())
    throw InputError(fmt::format("importance sampler: a box of {} and {} bounds, points {} × {}, {} densities",
                                 lower.size(), upper.size(), points.rows(), points.cols(),
                                 log_density_at_points.size()));
  Eigen::VectorXd width(d);
  double log_volume = 0.0;
  for (int j = 0; j < d; ++j) {
    width(j) = upper[static_cast<size_t>(j)] - lower[static_cast<size_t>(j)];
    if (!(width(j) > 0) || !std::isfinite(width(j)))
      throw InputError(fmt::format("importance sampler: parameter {}'s box [{}, {}] is empty", j,
                                   lower[static_cast<size_t>(j)], upper[static_cast<size_t>(j)]));
    log_volume += std::log(width(j));
  }
  const double top = log_density_at_points.maxCoeff();
  if (!std::isfinite(top))
    throw InputError("importance sampler: no starting point has a finite density to fit the first proposal to");

  // The variance floor of a fit carried by few draws: a quarter of the starting points' spacing squared, the spacing
  // of n uniform points in d dimensions being width · n^(-1/d).
  const double spacing = std::pow(static_cast<double>(points.rows()), -1.0 / d);
  const Eigen::VectorXd floor_variance = (0.5 * spacing * width).array().square().matrix();
  const auto fit = [&](const Eigen::MatrixXd& x, const Eigen::VectorXd& w, double ess, Eigen::VectorXd& mean,
                       Eigen::MatrixXd& covariance) {
    weighted_moments(x, w / w.sum(), mean, covariance);
    covariance *= options.inflation * options.inflation;
    if (ess < 2.0 * (d + 1))
      covariance.diagonal() += floor_variance;  // too few draws carry the fit to trust its shape
    else
      covariance.diagonal() += 1e-12 * width.array().square().matrix();  // keeps it positive definite
  };

  const Eigen::VectorXd w0 = weights_of(log_density_at_points, top);
  Eigen::VectorXd mean;
  Eigen::MatrixXd covariance;
  fit(points, w0, kish_ess(w0), mean, covariance);

  Random random(options.seed);
  ImportanceResult result;
  struct Round {
    Eigen::MatrixXd x;
    Eigen::VectorXd log_w;  ///< log density - log proposal; -inf outside the box
  };
  std::vector<Round> drawn;
  const double log_uniform = std::log(options.defensive) - log_volume;
  const double log_gaussian_share = std::log1p(-options.defensive);
  for (int round = 0; round < options.rounds; ++round) {
    const Eigen::LLT<Eigen::MatrixXd> llt(covariance);
    if (llt.info() != Eigen::Success) break;  // a degenerate fit: the caller samples another way
    const Eigen::MatrixXd factor = llt.matrixL();
    const double log_det_half = factor.diagonal().array().log().sum();
    Eigen::MatrixXd x(options.draws, d);
    Eigen::VectorXd log_q(options.draws);
    // The Gaussian is truncated to the box by drawing again (a posterior flat along a parameter would otherwise lose
    // the draws past its edges); its density inside is then divided by its mass in the box, estimated by the share of
    // draws that landed inside (a constant of the round, so it matters only where rounds are pooled).
    long tries = 0, landed = 0;
    std::vector<char> in_box(static_cast<size_t>(options.draws), 0);
    const auto inside_box = [&](Eigen::Index i) {
      for (int j = 0; j < d; ++j)
        if (!(x(i, j) >= lower[static_cast<size_t>(j)] && x(i, j) <= upper[static_cast<size_t>(j)])) return false;
      return true;
    };
    for (int i = 0; i < options.draws; ++i) {
      if (random.uniform() < options.defensive) {
        for (int j = 0; j < d; ++j) x(i, j) = lower[static_cast<size_t>(j)] + width(j) * random.uniform();
        in_box[static_cast<size_t>(i)] = 1;
        continue;
      }
      for (int attempt = 0; attempt < k_max_tries && !in_box[static_cast<size_t>(i)]; ++attempt) {
        Eigen::VectorXd z(d);
        for (int j = 0; j < d; ++j) z(j) = random.normal();
        x.row(i) = (mean + factor * z).transpose();
        ++tries;
        if (inside_box(i)) {
          in_box[static_cast<size_t>(i)] = 1;
          ++landed;
        }
      }
    }
    const double log_mass = landed > 0 ? std::log(static_cast<double>(landed) / static_cast<double>(tries)) : 0.0;
    std::vector<Eigen::Index> inside;
    for (int i = 0; i < options.draws; ++i) {
      if (!in_box[static_cast<size_t>(i)]) continue;  // the Gaussian missed the box k_max_tries times: weight 0
      inside.push_back(i);
      // The mixture's density: log(share · box density + (1 - share) · truncated Gaussian density).
      const Eigen::VectorXd y = factor.triangularView<Eigen::Lower>().solve((x.row(i).transpose() - mean).eval());
      const double log_normal =
          -0.5 * y.squaredNorm() - log_det_half - 0.5 * d * k_log_two_pi + log_gaussian_share - log_mass;
      const double m = std::max(log_uniform, log_normal);
      log_q(i) = m + std::log(std::exp(log_uniform - m) + std::exp(log_normal - m));
    }
    Eigen::MatrixXd x_inside(static_cast<Eigen::Index>(inside.size()), d);
    for (size_t k = 0; k < inside.size(); ++k) x_inside.row(static_cast<Eigen::Index>(k)) = x.row(inside[k]);
    Eigen::VectorXd log_w = Eigen::VectorXd::Constant(options.draws, -std::numeric_limits<double>::infinity());
    if (!inside.empty()) {
      const Eigen::VectorXd lp = log_density(x_inside);
      for (size_t k = 0; k < inside.size(); ++k) log_w(inside[k]) = lp(static_cast<Eigen::Index>(k)) - log_q(inside[k]);
    }
    result.evaluations += static_cast<int>(inside.size());
    result.rounds = round + 1;
    const double best = log_w.maxCoeff();
    if (!std::isfinite(best)) break;  // no draw landed where the density lives
    const Eigen::VectorXd w = weights_of(log_w, best);
    const double ess = kish_ess(w);
    drawn.push_back({std::move(x), std::move(log_w)});
    // The last k rounds pooled, each draw weighted by density / its own round's proposal: the weights share one
    // scale (the density's constant), so the pool is one importance sample (Cappé et al. 2004, §2.2) and its Kish
    // size counts what every round adds. The fewest last rounds that reach min_ess are kept.
    const auto pool = [&](size_t first) {
      Pool p;
      for (size_t r = first; r < drawn.size(); ++r) p.top = std::max(p.top, drawn[r].log_w.maxCoeff());
      double sum = 0.0, squares = 0.0;
      for (size_t r = first; r < drawn.size(); ++r) {
        const Eigen::VectorXd wr = weights_of(drawn[r].log_w, p.top);
        sum += wr.sum();
        squares += wr.squaredNorm();
      }
      p.ess = squares > 0.0 ? sum * sum / squares : 0.0;
      return p;
    };
    int kept = 0;
    Pool pooled;
    for (int k = 1; k <= static_cast<int>(drawn.size()) && kept == 0; ++k) {
      pooled = pool(drawn.size() - static_cast<size_t>(k));
      if (pooled.ess >= options.min_ess) kept = k;
    }
    if (kept > 0 || round + 1 == options.rounds) {
      const int k = kept > 0 ? kept : 1;
      const size_t first = drawn.size() - static_cast<size_t>(k);
      if (kept == 0) pooled = pool(first);
      result.points.resize(static_cast<Eigen::Index>(k) * options.draws, d);
      result.weights.resize(static_cast<Eigen::Index>(k) * options.draws);
      for (size_t r = first; r < drawn.size(); ++r) {
        const Eigen::Index row = static_cast<Eigen::Index>(r - first) * options.draws;
        result.points.middleRows(row, options.draws) = drawn[r].x;
        result.weights.segment(row, options.draws) = weights_of(drawn[r].log_w, pooled.top);
      }
      result.weights /= result.weights.sum();
      result.ess = kept > 0 ? pooled.ess : ess;
      result.converged = kept > 0;
      break;
    }
    fit(drawn.back().x, w, ess, mean, covariance);
  }
  return result;
}

}  // namespace demsa::sobol
