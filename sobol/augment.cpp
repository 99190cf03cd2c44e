#include "sobol/augment.hpp"

#include "sobol/design.hpp"
#include "sobol/error.hpp"
#include "sobol/random.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

namespace demsa::sobol {

namespace {

/// Σ d_ij^-p over the pairs (i, j), i < j, with j >= first_new (and i any row): the sum behind phi_p_of_new. The
/// distances are divided by `scale` (the smallest of them) before the power, so that the terms neither overflow nor
/// vanish for p = 50; the caller compares sums of the same scale only through phi_p_of_new.
double pair_sum(const Eigen::MatrixXd& x, Eigen::Index first_new, double p) {
  const Eigen::Index n = x.rows();
  double d_min = std::numeric_limits<double>::infinity();
  for (Eigen::Index j = first_new; j < n; ++j)
    for (Eigen::Index i = 0; i < j; ++i) d_min = std::min(d_min, (x.row(i) - x.row(j)).norm());
  if (!(d_min > 0)) return std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (Eigen::Index j = first_new; j < n; ++j)
    for (Eigen::Index i = 0; i < j; ++i) sum += std::pow((x.row(i) - x.row(j)).norm() / d_min, -p);
  // φ_p = d_min^-1 · sum^(1/p): returned in log form by the caller.
  return std::log(sum) / p - std::log(d_min);
}

/// The GP's correlation between the rows of a and b (its kernel and length scales; gp.hpp).
Eigen::MatrixXd correlation(const GaussianProcess& gp, const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const Eigen::VectorXd inverse = gp.lengths().cwiseInverse();
  const Eigen::MatrixXd sa = a * inverse.asDiagonal();
  const Eigen::MatrixXd sb = b * inverse.asDiagonal();
  Eigen::MatrixXd r2 = (-2.0 * sa * sb.transpose()).colwise() + sa.rowwise().squaredNorm();
  r2.rowwise() += sb.rowwise().squaredNorm().transpose();
  r2 = r2.cwiseMax(0.0);
  if (gp.options().kernel == GpKernel::squared_exponential) return (-0.5 * r2.array()).exp().matrix();
  const Eigen::ArrayXXd r = r2.array().sqrt() * std::sqrt(5.0);
  return ((1.0 + r + r.square() / 3.0) * (-r).exp()).matrix();
}

/// Integrated-variance reduction of observing each candidate, for a GP whose training inputs are x (in units of its
/// process variance): mean over the reference points of k_n(ref, c)² / (k_n(c, c) + τ).
Eigen::VectorXd integrated_variance_reduction(const GaussianProcess& gp, const Eigen::MatrixXd& x,
                                              const Eigen::MatrixXd& candidates, const Eigen::MatrixXd& reference) {
  Eigen::MatrixXd r = correlation(gp, x, x);
  r.diagonal().array() += gp.nugget() + GaussianProcess::jitter();
  const Eigen::LLT<Eigen::MatrixXd> llt(r);
  const Eigen::MatrixXd k_xc = correlation(gp, x, candidates);
  const Eigen::MatrixXd a = llt.solve(k_xc);  // R⁻¹ k(X, c)
  const Eigen::MatrixXd cov = correlation(gp, reference, candidates) - correlation(gp, reference, x) * a;
  const Eigen::ArrayXd variance = (1.0 - (k_xc.array() * a.array()).colwise().sum()).max(0.0).transpose();
  const Eigen::ArrayXd denominator = variance + gp.nugget() + GaussianProcess::jitter();
  return (cov.array().square().colwise().mean().transpose() / denominator).matrix();
}

}  // namespace

Eigen::MatrixXd extend_sobol(int start, int added, int dimension, std::uint64_t seed) {
  if (start < 0) throw InputError(fmt::format("start = {}: must be >= 0", start));
  if (added < 1) throw InputError(fmt::format("added = {}: must be >= 1", added));
  const Eigen::MatrixXd all = scrambled_sobol(start + added, dimension, seed);
  return all.bottomRows(added);
}

void LhsExtensionOptions::validate() const {
  if (candidates < 1) throw InputError(fmt::format("candidates = {}: must be >= 1", candidates));
  if (swaps_per_point < 0) throw InputError(fmt::format("swaps_per_point = {}: must be >= 0", swaps_per_point));
  if (!(phi_p_power >= 1)) throw InputError(fmt::format("phi_p_power = {}: must be >= 1", phi_p_power));
}

double phi_p_of_new(const Eigen::MatrixXd& points, Eigen::Index first_new, double p) {
  if (first_new >= points.rows() || points.rows() < 2) return 0.0;
  return std::exp(pair_sum(points, std::max<Eigen::Index>(first_new, 1), p));
}

Eigen::MatrixXd extend_lhs(const Eigen::MatrixXd& existing, int added, std::uint64_t seed,
                           const LhsExtensionOptions& options) {
  options.validate();
  if (added < 1) throw InputError(fmt::format("added = {}: must be >= 1", added));
  const Eigen::Index n = existing.rows();
  const Eigen::Index d = existing.cols();
  if (d < 1) throw InputError("the design has no input (0 columns)");
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index k = 0; k < d; ++k)
      if (!(existing(i, k) >= 0.0 && existing(i, k) <= 1.0))
        throw InputError(fmt::format("point {} input {}: {} is outside [0, 1]", i, k, existing(i, k)));
  const Eigen::Index total = n + added;
  const double strata = static_cast<double>(total);

  // The empty strata of every input among the n + m of the extended design (at least m: n points fill at most n).
  std::vector<std::vector<int>> empty(static_cast<std::size_t>(d));
  for (Eigen::Index k = 0; k < d; ++k) {
    std::vector<char> used(static_cast<std::size_t>(total), 0);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto s = std::min<Eigen::Index>(static_cast<Eigen::Index>(existing(i, k) * strata), total - 1);
      used[static_cast<std::size_t>(s)] = 1;
    }
    for (Eigen::Index s = 0; s < total; ++s)
      if (!used[static_cast<std::size_t>(s)]) empty[static_cast<std::size_t>(k)].push_back(static_cast<int>(s));
  }

  Random rng(seed);
  // A new point's coordinate k: its stratum, and its place inside it (fixed per point and input, so that the local
  // search moves strata, not offsets).
  Eigen::MatrixXd offsets(added, d);
  for (Eigen::Index i = 0; i < added; ++i)
    for (Eigen::Index k = 0; k < d; ++k) offsets(i, k) = options.centred ? 0.5 : rng.uniform();
  using Strata = std::vector<std::vector<int>>;  // [input][new point] -> stratum; the unused empty ones after them
  const auto place = [&](Eigen::MatrixXd& x, const Strata& s) {
    for (Eigen::Index k = 0; k < d; ++k)
      for (Eigen::Index i = 0; i < added; ++i)
        x(n + i, k) = (s[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)] + offsets(i, k)) / strata;
  };
  Eigen::MatrixXd x(total, d);
  x.topRows(n) = existing;

  const double p = options.phi_p_power;
  Strata best;
  double best_value = std::numeric_limits<double>::infinity();
  for (int c = 0; c < options.candidates; ++c) {
    Strata s = empty;
    for (std::vector<int>& column : s) rng.shuffle(column);  // the first m of each shuffled list are taken
    place(x, s);
    const double value = pair_sum(x, n, p);
    if (value < best_value) {
      best_value = value;
      best = std::move(s);
    }
  }

  // Local search: swap the strata of two new points in one input, or give a new point an unused empty stratum.
  place(x, best);
  const long moves = static_cast<long>(options.swaps_per_point) * added;
  for (long move = 0; move < moves; ++move) {
    const auto k = static_cast<std::size_t>(rng.below(static_cast<std::uint64_t>(d)));
    std::vector<int>& column = best[k];
    const auto a = static_cast<std::size_t>(rng.below(static_cast<std::uint64_t>(added)));
    const auto b = static_cast<std::size_t>(rng.below(column.size()));
    if (a == b) continue;
    std::swap(column[a], column[b]);
    place(x, best);
    const double value = pair_sum(x, n, p);
    if (value < best_value) {
      best_value = value;
    } else {
      std::swap(column[a], column[b]);
    }
  }
  place(x, best);
  return x.bottomRows(added);
}

void VarianceSelectionOptions::validate() const {
  if (batch < 1) throw InputError(fmt::format("batch = {}: must be >= 1", batch));
  if (candidates < batch) throw InputError(fmt::format("candidates = {}: must be >= batch ({})", candidates, batch));
  if (reference < 1) throw InputError(fmt::format("reference = {}: must be >= 1", reference));
  if (!(min_distance_fraction >= 0))
    throw InputError(fmt::format("min_distance_fraction = {}: must be >= 0", min_distance_fraction));
}

Eigen::MatrixXd select_by_variance(const std::vector<const GaussianProcess*>& models, const Eigen::MatrixXd& existing,
                                   const VarianceSelectionOptions& options) {
  options.validate();
  if (models.empty()) throw InputError("select_by_variance: no Gaussian process to take the variance of");
  const Eigen::Index d = existing.cols();
  for (const GaussianProcess* m : models)
    if (m == nullptr || !m->fitted() || m->training_inputs().cols() != d)
      throw InputError("select_by_variance: a model is not fitted, or not on the design's inputs");
  const Eigen::Index n = existing.rows();

  const Eigen::MatrixXd candidates = latin_hypercube(options.candidates, static_cast<int>(d), options.seed);
  const Eigen::MatrixXd reference =
      options.criterion == SelectionCriterion::integrated_variance
          ? latin_hypercube(options.reference, static_cast<int>(d), options.seed ^ 0x5851F42D4C957F2DULL)
          : Eigen::MatrixXd();
  // The design's typical spacing: mean nearest-neighbour distance, shrunk to the density after the batch.
  double spacing = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    double nearest = std::numeric_limits<double>::infinity();
    for (Eigen::Index j = 0; j < n; ++j)
      if (j != i) nearest = std::min(nearest, (existing.row(i) - existing.row(j)).norm());
    spacing += std::isfinite(nearest) ? nearest : 0.0;
  }
  spacing = n > 1 ? spacing / static_cast<double>(n) : 0.5;
  spacing *= std::pow(static_cast<double>(n) / static_cast<double>(n + options.batch), 1.0 / static_cast<double>(d));
  // Distance of every candidate to the nearest design or chosen point.
  Eigen::VectorXd nearest = Eigen::VectorXd::Constant(candidates.rows(), std::numeric_limits<double>::infinity());
  for (Eigen::Index c = 0; c < candidates.rows(); ++c)
    for (Eigen::Index i = 0; i < n; ++i)
      nearest(c) = std::min(nearest(c), (candidates.row(c) - existing.row(i)).norm());

  // Working copies: each model refitted (same hyperparameters) on the inputs with the chosen points added.
  std::vector<std::unique_ptr<Metamodel>> working;
  std::vector<const GaussianProcess*> current = models;
  Eigen::MatrixXd chosen(options.batch, d);
  std::vector<char> taken(static_cast<std::size_t>(candidates.rows()), 0);
  for (int b = 0; b < options.batch; ++b) {
    Eigen::VectorXd score = Eigen::VectorXd::Zero(candidates.rows());
    for (const GaussianProcess* m : current) {
      if (options.criterion == SelectionCriterion::integrated_variance) {
        score += integrated_variance_reduction(*m, m->training_inputs(), candidates, reference);
      } else {
        const Eigen::VectorXd sd = m->predict_sd(candidates);
        score += (sd.array().square() / m->process_variance()).matrix();
      }
    }
    Eigen::Index pick = -1;
    for (double limit = options.min_distance_fraction * spacing; pick < 0; limit *= 0.5) {
      double best = -std::numeric_limits<double>::infinity();
      for (Eigen::Index c = 0; c < candidates.rows(); ++c) {
        if (taken[static_cast<std::size_t>(c)] || nearest(c) < limit) continue;
        if (score(c) > best) {
          best = score(c);
          pick = c;
        }
      }
      if (limit < 1e-12 && pick < 0) throw NumericalError("select_by_variance: no candidate left");
    }
    taken[static_cast<std::size_t>(pick)] = 1;
    chosen.row(b) = candidates.row(pick);
    for (Eigen::Index c = 0; c < candidates.rows(); ++c)
      nearest(c) = std::min(nearest(c), (candidates.row(c) - candidates.row(pick)).norm());
    if (b + 1 == options.batch) break;
    std::vector<std::unique_ptr<Metamodel>> next;
    std::vector<const GaussianProcess*> next_current;
    for (const GaussianProcess* m : current) {
      Eigen::MatrixXd x(m->training_inputs().rows() + 1, d);
      x.topRows(m->training_inputs().rows()) = m->training_inputs();
      x.bottomRows(1) = candidates.row(pick);
      Eigen::VectorXd y(x.rows());
      y.head(x.rows() - 1) = m->training_outputs();
      y(x.rows() - 1) = m->predict(candidates.row(pick))(0);
      next.push_back(m->refit(x, y));
      next_current.push_back(static_cast<const GaussianProcess*>(next.back().get()));
    }
    working = std::move(next);
    current = std::move(next_current);
  }
  return chosen;
}

}  // namespace demsa::sobol
