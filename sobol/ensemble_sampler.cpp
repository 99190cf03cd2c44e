#include "sobol/ensemble_sampler.hpp"

#include "sobol/error.hpp"
#include "sobol/random.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace demsa::sobol {

int EnsembleOptions::walkers_for(int dimension) const {
  if (walkers > 0) return walkers;
  const int w = std::max(32, 4 * dimension);
  return w + (w % 2);
}

void EnsembleOptions::validate(int dimension) const {
  if (dimension < 1) throw InputError(fmt::format("ensemble sampler: dimension {} must be >= 1", dimension));
  if (walkers != 0 && (walkers % 2 != 0 || walkers < 2 * dimension + 2))
    throw InputError(
        fmt::format("walkers {}: must be even and >= 2d + 2 = {} (or 0 for the default)", walkers, 2 * dimension + 2));
  if (steps < 10) throw InputError(fmt::format("steps {}: must be >= 10", steps));
  if (burn_in < 0) throw InputError(fmt::format("burn-in {}: must be >= 0", burn_in));
  // Sizes are bounded before anything is allocated or run: burn_in + steps and the evaluation count are ints, and
  // an overflow would run no step at all and report the starting ensemble as the posterior.
  const std::int64_t w = walkers_for(dimension);
  const double values = static_cast<double>(steps) * static_cast<double>(w) * (dimension + 1.0);
  if (values > k_max_draw_values)
    throw InputError(fmt::format(
        "steps {}: {} walkers × {} steps × {} values per draw = {:.3g} values ({:.1f} GB), more than the {:.3g} "
        "({:.1f} GB) the sampler keeps in memory: at most {} steps",
        steps, w, steps, dimension + 1, values, values * 8e-9, k_max_draw_values, k_max_draw_values * 8e-9,
        static_cast<std::int64_t>(k_max_draw_values / (static_cast<double>(w) * (dimension + 1)))));
  const std::int64_t total = static_cast<std::int64_t>(burn_in) + steps;
  const std::int64_t int_max = std::numeric_limits<int>::max();
  if ((total + 100) * w > int_max) {  // the starting ensemble may take up to 100 draws per walker
    const bool burn = burn_in > steps;
    throw InputError(
        fmt::format("{} {}: {} walkers × ({} burn-in + {} steps + 100 to start) = {} density "
                    "evaluations, more than {} (at most {} steps per walker in all)",
                    burn ? "burn-in" : "steps", burn ? burn_in : steps, w, burn_in, steps, (total + 100) * w, int_max,
                    int_max / w - 100));
  }
  if (!(stretch > 1.0) || !std::isfinite(stretch))
    throw InputError(fmt::format("stretch {}: must be a finite number > 1", stretch));
}

Eigen::VectorXd EnsembleResult::chain(int walker, int j) const {
  Eigen::VectorXd c(steps);
  for (int s = 0; s < steps; ++s) c(s) = draws(static_cast<Eigen::Index>(s) * walkers + walker, j);
  return c;
}

Eigen::MatrixXd EnsembleResult::last() const { return draws.bottomRows(walkers); }

EnsembleResult sample_ensemble(const BatchLogDensity& log_density, const std::vector<double>& lower,
                               const std::vector<double>& upper, const EnsembleOptions& options) {
  const int d = static_cast<int>(lower.size());
  options.validate(d);
  if (upper.size() != lower.size())
    throw InputError(fmt::format("ensemble sampler: {} lower and {} upper bounds", lower.size(), upper.size()));
  for (int j = 0; j < d; ++j)
    if (!(lower[j] < upper[j]))
      throw InputError(
          fmt::format("ensemble sampler: input {}: lower {} must be below upper {}", j + 1, lower[j], upper[j]));
  const int n_walkers = options.walkers_for(d);
  const int half = n_walkers / 2;
  Random rng(options.seed);
  const auto inside = [&](const Eigen::VectorXd& x) {
    for (int j = 0; j < d; ++j)
      if (!(x(j) >= lower[j] && x(j) <= upper[j])) return false;
    return true;
  };

  EnsembleResult r;
  r.dimension = d;
  r.walkers = n_walkers;
  r.steps = options.steps;
  r.seed = options.seed;
  r.best_log_density = -std::numeric_limits<double>::infinity();

  // Initial ensemble: the given one, else uniform draws from the box (the uniform prior), redrawn where the density
  // is zero.
  Eigen::MatrixXd x(n_walkers, d);
  Eigen::VectorXd lp = Eigen::VectorXd::Constant(n_walkers, -std::numeric_limits<double>::infinity());
  std::vector<int> missing(n_walkers);
  for (int w = 0; w < n_walkers; ++w) missing[w] = w;
  if (options.start.size() > 0) {
    if (options.start.rows() != n_walkers || options.start.cols() != d)
      throw InputError(fmt::format("ensemble sampler: a starting ensemble of {} × {} for {} walkers in {} dimensions",
                                   options.start.rows(), options.start.cols(), n_walkers, d));
    for (int w = 0; w < n_walkers; ++w)
      if (!inside(options.start.row(w).transpose()))
        throw InputError(fmt::format("ensemble sampler: starting walker {} lies outside the box", w + 1));
    x = options.start;
    lp = log_density(x);
    r.evaluations += n_walkers;
    for (int w = 0; w < n_walkers; ++w)
      if (!std::isfinite(lp(w)))
        throw InputError(fmt::format("ensemble sampler: starting walker {} has density zero", w + 1));
    missing.clear();
  }
  for (int attempt = 0; !missing.empty(); ++attempt) {
    if (attempt >= 100)
      throw InputError(fmt::format("ensemble sampler: no point of finite density in {} uniform draws from the box",
                                   100 * n_walkers));
    Eigen::MatrixXd trial(static_cast<Eigen::Index>(missing.size()), d);
    for (Eigen::Index i = 0; i < trial.rows(); ++i)
      for (int j = 0; j < d; ++j) trial(i, j) = lower[j] + rng.uniform() * (upper[j] - lower[j]);
    const Eigen::VectorXd v = log_density(trial);
    r.evaluations += static_cast<int>(trial.rows());
    std::vector<int> still;
    for (Eigen::Index i = 0; i < trial.rows(); ++i) {
      if (std::isfinite(v(i))) {
        x.row(missing[i]) = trial.row(i);
        lp(missing[i]) = v(i);
      } else {
        still.push_back(missing[i]);
      }
    }
    missing = still;
  }
  for (int w = 0; w < n_walkers; ++w)
    if (lp(w) > r.best_log_density) {
      r.best_log_density = lp(w);
      r.best = x.row(w).transpose();
    }

  r.draws.resize(static_cast<Eigen::Index>(options.steps) * n_walkers, d);
  r.log_density.resize(static_cast<Eigen::Index>(options.steps) * n_walkers);
  const double a = options.stretch;
  long accepted = 0;
  Eigen::MatrixXd proposal(half, d);
  Eigen::VectorXd log_z(half);
  Eigen::VectorXd proposal_lp(half);
  std::vector<char> in_box(half);
  const int total = options.burn_in + options.steps;
  for (int step = 0; step < total; ++step) {
    // Stretch move (Goodman & Weare 2010, eq. 7; emcee's parallel version): the walkers of one half move along the
    // line through a random walker of the other half, y = x_j + z (x_k - x_j), z ~ g(z) ∝ 1/√z on [1/a, a],
    // accepted with probability min(1, z^(d-1) p(y)/p(x_k)).
    for (int part = 0; part < 2; ++part) {
      const int first = part * half;
      const int other = (1 - part) * half;
      for (int i = 0; i < half; ++i) {
        const int j = other + static_cast<int>(rng.below(static_cast<std::uint64_t>(half)));
        const double u = rng.uniform();
        const double z = std::pow((a - 1.0) * u + 1.0, 2) / a;
        log_z(i) = std::log(z);
        proposal.row(i) = x.row(j) + z * (x.row(first + i) - x.row(j));
        in_box[i] = inside(proposal.row(i).transpose()) ? 1 : 0;
      }
      // Only the points in the box are evaluated; the others have prior density zero.
      std::vector<int> rows;
      for (int i = 0; i < half; ++i)
        if (in_box[i]) rows.push_back(i);
      proposal_lp.setConstant(-std::numeric_limits<double>::infinity());
      if (!rows.empty()) {
        Eigen::MatrixXd batch(static_cast<Eigen::Index>(rows.size()), d);
        for (size_t k = 0; k < rows.size(); ++k) batch.row(static_cast<Eigen::Index>(k)) = proposal.row(rows[k]);
        const Eigen::VectorXd v = log_density(batch);
        r.evaluations += static_cast<int>(rows.size());
        for (size_t k = 0; k < rows.size(); ++k) proposal_lp(rows[k]) = v(static_cast<Eigen::Index>(k));
      }
      for (int i = 0; i < half; ++i) {
        const double log_ratio = (d - 1) * log_z(i) + proposal_lp(i) - lp(first + i);
        const double u = rng.uniform();
        if (std::isfinite(proposal_lp(i)) && std::log(u) < log_ratio) {
          x.row(first + i) = proposal.row(i);
          lp(first + i) = proposal_lp(i);
          if (step >= options.burn_in) ++accepted;
          if (proposal_lp(i) > r.best_log_density) {
            r.best_log_density = proposal_lp(i);
            r.best = proposal.row(i).transpose();
          }
        }
      }
    }
    if (step >= options.burn_in) {
      const Eigen::Index s = step - options.burn_in;
      r.draws.middleRows(s * n_walkers, n_walkers) = x;
      r.log_density.segment(s * n_walkers, n_walkers) = lp;
    }
  }
  r.acceptance = static_cast<double>(accepted) / (static_cast<double>(options.steps) * n_walkers);
  return r;
}

Eigen::MatrixXd highest_density_start(const Eigen::MatrixXd& points, const Eigen::VectorXd& log_density, int walkers) {
  assert(points.rows() == log_density.size() && walkers > 0);
  std::vector<Eigen::Index> finite;
  for (Eigen::Index i = 0; i < log_density.size(); ++i)
    if (std::isfinite(log_density(i))) finite.push_back(i);
  if (static_cast<Eigen::Index>(finite.size()) < walkers)
    throw InputError(fmt::format("ensemble sampler: {} of {} points have a finite density, fewer than the {} walkers",
                                 finite.size(), points.rows(), walkers));
  std::partial_sort(finite.begin(), finite.begin() + walkers, finite.end(),
                    [&](Eigen::Index a, Eigen::Index b) { return log_density(a) > log_density(b); });
  Eigen::MatrixXd start(walkers, points.cols());
  for (int w = 0; w < walkers; ++w) start.row(w) = points.row(finite[static_cast<size_t>(w)]);
  return start;
}

double integrated_time(const Eigen::MatrixXd& chains, double c) {
  const Eigen::Index n = chains.rows();
  const Eigen::Index m = chains.cols();
  assert(n >= 2 && m >= 1);
  Eigen::MatrixXd centred = chains.rowwise() - chains.colwise().mean();
  Eigen::VectorXd variance(m);
  for (Eigen::Index w = 0; w < m; ++w) variance(w) = centred.col(w).squaredNorm() / static_cast<double>(n);
  // Walkers whose chain never moved carry no information on the correlation.
  std::vector<Eigen::Index> moving;
  for (Eigen::Index w = 0; w < m; ++w)
    if (variance(w) > 0.0) moving.push_back(w);
  if (moving.empty()) return 1.0;
  // τ(M) = 1 + 2 Σ_{t=1..M} ρ(t), ρ the autocorrelation averaged over walkers (emcee's function_1d per walker,
  // averaged); the window is the first M with M >= c τ(M) (Sokal's automatic windowing).
  double tau = 1.0;
  for (Eigen::Index t = 1; t < n; ++t) {
    double rho = 0.0;
    for (const Eigen::Index w : moving) {
      const double acf =
          centred.col(w).head(n - t).dot(centred.col(w).tail(n - t)) / (static_cast<double>(n) * variance(w));
      rho += acf;
    }
    rho /= static_cast<double>(moving.size());
    tau += 2.0 * rho;
    if (static_cast<double>(t) >= c * tau) return tau;
  }
  return tau;  // the window never closed: τ is at least this large (the chain is too short to tell)
}

double split_rhat(const Eigen::MatrixXd& chains) {
  const Eigen::Index half = chains.rows() / 2;
  const Eigen::Index m = 2 * chains.cols();
  assert(half >= 2);
  // Gelman et al. 2013, eq. 11.2-11.4: B/n = variance of the chain means, W = mean within-chain variance,
  // var+ = (n-1)/n W + B/n, R̂ = sqrt(var+ / W); the second half starts at rows - half so both have `half` rows.
  Eigen::VectorXd means(m), variances(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::Index col = k / 2;
    const Eigen::Index start = (k % 2 == 0) ? 0 : chains.rows() - half;
    const Eigen::VectorXd piece = chains.col(col).segment(start, half);
    means(k) = piece.mean();
    variances(k) = (piece.array() - means(k)).square().sum() / static_cast<double>(half - 1);
  }
  const double w = variances.mean();
  const double between = (means.array() - means.mean()).square().sum() / static_cast<double>(m - 1);  // B/n
  if (!(w > 0.0)) return between > 0.0 ? std::numeric_limits<double>::infinity() : 1.0;
  const double var_plus = (static_cast<double>(half - 1) / static_cast<double>(half)) * w + between;
  return std::sqrt(var_plus / w);
}

ChainDiagnostics diagnose(const EnsembleResult& result, const std::string& steps_name,
                          const std::string& walkers_name) {
  ChainDiagnostics d;
  d.acceptance = result.acceptance;
  const double draws = static_cast<double>(result.steps) * result.walkers;
  d.min_ess = std::numeric_limits<double>::infinity();
  for (int j = 0; j < result.dimension; ++j) {
    Eigen::MatrixXd chains(result.steps, result.walkers);
    for (int w = 0; w < result.walkers; ++w) chains.col(w) = result.chain(w, j);
    const double tau = integrated_time(chains);
    const double rhat = split_rhat(chains);
    d.tau.push_back(tau);
    d.rhat.push_back(rhat);
    d.ess.push_back(draws / tau);
    d.max_tau = std::max(d.max_tau, tau);
    d.max_rhat = std::max(d.max_rhat, rhat);
    d.min_ess = std::min(d.min_ess, draws / tau);
  }
  const bool long_enough = result.steps >= 50.0 * d.max_tau;  // emcee: trust τ only for chains > 50 τ
  const bool mixed = d.max_rhat < 1.05;
  d.converged = long_enough && mixed;
  if (!d.converged) {
    std::vector<std::string> why;
    if (!long_enough)
      why.push_back(fmt::format("{} steps per walker are fewer than 50 τ = {:.0f}: raise {} to at least {:.0f}",
                                result.steps, 50.0 * d.max_tau, steps_name, std::ceil(50.0 * d.max_tau)));
    if (!mixed)
      why.push_back(fmt::format("split R̂ = {:.3f} >= 1.05: the walkers disagree; raise {} and {}", d.max_rhat,
                                steps_name, walkers_name));
    if (d.acceptance < 0.1)
      why.push_back(fmt::format("acceptance {:.2f} is low (a narrow or multimodal posterior): raise {}", d.acceptance,
                                walkers_name));
    for (size_t i = 0; i < why.size(); ++i) d.advice += (i ? "; " : "") + why[i];
  }
  return d;
}

}  // namespace demsa::sobol
