#include "sobol/metamodel_sobol.hpp"

#include "sobol/enum_names.hpp"
#include "sobol/gp.hpp"
#include "sobol/random.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <set>

namespace demsa::sobol {

namespace {

double percentile(std::vector<double> v, double q) {
  assert(!v.empty());
  std::sort(v.begin(), v.end());
  const double h = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (h - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

/// Point estimates of one model: exact for an RSM when allowed, else QMC on the shared design.
SobolResult point_indices(const Metamodel& model, const SaltelliDesign& design, const MetamodelSobolOptions& options) {
  if (options.exact_for_rsm)
    if (const auto* rsm = dynamic_cast<const PolynomialRsm*>(&model)) return rsm_exact_indices(*rsm);
  SobolOptions qmc;
  qmc.second_order = options.second_order;
  qmc.interval = SaltelliInterval::none;  // point estimates: the metamodel's interval is made here
  qmc.seed = options.seed;
  qmc.stop = options.stop;
  return sobol_indices([&model](const Eigen::MatrixXd& x) { return model.predict(x); }, design, qmc);
}

const EnumNames<MetamodelInterval>& interval_names() {
  static const EnumNames<MetamodelInterval> names{
      "interval method",
      {{MetamodelInterval::gp_posterior, "gp-posterior"}, {MetamodelInterval::design_bootstrap, "design-bootstrap"}}};
  return names;
}

/// Quantile p in (0.5, 1) of the standard normal, by bisection on Φ(z) = erfc(-z/√2)/2 (to 1e-12).
double normal_quantile(double p) {
  double lo = 0.0, hi = 40.0;
  while (hi - lo > 1e-12) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(-mid / std::numbers::sqrt2) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

/// Sample standard deviation (n - 1 in the denominator); 0 for fewer than 2 values.
double sample_sd(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  double mean = 0.0;
  for (const double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  double ss = 0.0;
  for (const double x : v) ss += (x - mean) * (x - mean);
  return std::sqrt(ss / static_cast<double>(v.size() - 1));
}

/// The replicates of every index of one result, in a fixed order: S1 (d), ST (d), residual, S2 (pairs).
std::vector<double> flatten(const SobolResult& r) {
  std::vector<double> out;
  for (const IndexEstimate& e : r.first) out.push_back(e.value);
  for (const IndexEstimate& e : r.total) out.push_back(e.value);
  out.push_back(r.residual.value);
  for (const SecondOrderIndex& e : r.second) out.push_back(e.s.value);
  return out;
}

/// Every estimate of a result in the order of flatten().
std::vector<IndexEstimate*> estimates(SobolResult& r) {
  std::vector<IndexEstimate*> out;
  for (IndexEstimate& e : r.first) out.push_back(&e);
  for (IndexEstimate& e : r.total) out.push_back(&e);
  out.push_back(&r.residual);
  for (SecondOrderIndex& e : r.second) out.push_back(&e.s);
  return out;
}

/// The GP-posterior interval (metamodel_sobol.hpp, after Le Gratiet, Cannamela & Iooss 2014, §3): `result` holds
/// the indices of the posterior mean on `design`; `design_for(seed)` draws an independently scrambled design.
template <typename DesignFor>
void add_posterior_interval(const GaussianProcess& gp, const SaltelliDesign& design, const DesignFor& design_for,
                            const MetamodelSobolOptions& options, SobolResult& result) {
  const int d = design.dimension;
  SobolOptions qmc;
  qmc.second_order = options.second_order;
  qmc.interval = SaltelliInterval::none;  // point estimates: the metamodel's interval is made here
  qmc.stop = options.stop;
  const std::vector<IndexEstimate*> targets = estimates(result);
  std::vector<std::vector<double>> draws(targets.size());
  // The draws on the stacked design, in chunks of columns that keep the matrix near 4 M values (32 MB), each chunk
  // with random features of its own.
  const Eigen::MatrixXd stacked = design.stacked();
  const int chunk =
      std::clamp(static_cast<int>(4'000'000 / std::max<Eigen::Index>(stacked.rows(), 1)), 1, options.bootstrap);
  Random chunk_seeds(options.seed ^ 0x9E3779B97F4A7C15ULL);
  int succeeded = 0;
  for (int done = 0; done < options.bootstrap; done += chunk) {
    throw_if_stopped(options.stop);
    const int count = std::min(chunk, options.bootstrap - done);
    const Eigen::MatrixXd values = gp.posterior_draws(stacked, count, chunk_seeds.bits(), options.features);
    for (int c = 0; c < count; ++c) {
      SobolResult rep;
      try {
        rep = sobol_indices(split_responses(values.col(c), d, options.second_order), qmc);
      } catch (const NumericalError&) {
        continue;  // a draw of negligible variance has no indices
      }
      ++succeeded;
      const std::vector<double> v = flatten(rep);
      for (std::size_t k = 0; k < v.size(); ++k) draws[k].push_back(v[k]);
    }
  }
  // The QMC error of the estimate: the posterior mean's indices on independently scrambled designs of the same N.
  Random design_seeds(options.seed ^ 0x2545F4914F6CDD1DULL);
  std::vector<std::vector<double>> scrambles(targets.size());
  for (int q = 0; q < options.qmc_replicates; ++q) {
    throw_if_stopped(options.stop);
    const SaltelliDesign scrambled = design_for(design_seeds.bits());
    const SobolResult rep = point_indices(gp, scrambled, options);
    const std::vector<double> v = flatten(rep);
    for (std::size_t k = 0; k < v.size(); ++k) scrambles[k].push_back(v[k]);
  }
  if (2 * succeeded < options.bootstrap) {
    result.bootstrap = 0;
    result.note = fmt::format("no interval: only {} of {} GP-posterior draws of {} had a variance", succeeded,
                              options.bootstrap, gp.name());
    return;
  }
  const double lo = 0.5 * (1.0 - options.confidence), hi = 0.5 * (1.0 + options.confidence);
  const double z = normal_quantile(hi);
  for (std::size_t k = 0; k < targets.size(); ++k) {
    IndexEstimate& e = *targets[k];
    const double median = percentile(draws[k], 0.5);
    const double qmc_half = z * sample_sd(scrambles[k]);
    e.lower = e.value - std::hypot(median - percentile(draws[k], lo), qmc_half);
    e.upper = e.value + std::hypot(percentile(draws[k], hi) - median, qmc_half);
  }
  result.bootstrap = succeeded;
  result.note = fmt::format(
      "GP-posterior interval: {} draws of the posterior of {} at its fitted hyperparameters, QMC error from {} "
      "scrambled designs added",
      succeeded, gp.name(), options.qmc_replicates);
}

}  // namespace

MetamodelInterval metamodel_interval_from_string(const std::string& name) { return interval_names().from_string(name); }
std::string to_string(MetamodelInterval interval) { return interval_names().to_string(interval); }
std::vector<std::string> metamodel_interval_names() { return interval_names().names(); }

void MetamodelSobolOptions::validate() const {
  if (base < 2) throw InputError(fmt::format("sobol base = {}: must be at least 2", base));
  if (bootstrap < 0) throw InputError(fmt::format("sobol bootstrap = {}: must be >= 0", bootstrap));
  if (!(confidence > 0.0 && confidence < 1.0))
    throw InputError(fmt::format("sobol confidence = {}: must be in (0, 1)", confidence));
  if (features < 1) throw InputError(fmt::format("sobol features = {}: must be at least 1", features));
  if (qmc_replicates < 2)
    throw InputError(fmt::format("sobol qmc_replicates = {}: must be at least 2", qmc_replicates));
}

SobolResult rsm_exact_indices(const PolynomialRsm& rsm) {
  assert(rsm.fitted());
  const std::vector<std::vector<int>>& terms = rsm.terms();
  const Eigen::VectorXd& c = rsm.coefficients();
  const int d = static_cast<int>(rsm.training_inputs().cols());
  // Sudret 2008, eq. 32-33: with an orthonormal basis, V = Σ_{α≠0} c_α² and each D_u sums the terms of support u.
  double variance = 0.0;
  std::vector<double> first(static_cast<std::size_t>(d), 0.0), total(static_cast<std::size_t>(d), 0.0);
  Eigen::MatrixXd pair = Eigen::MatrixXd::Zero(d, d);
  double mean = 0.0;
  for (std::size_t t = 0; t < terms.size(); ++t) {
    std::vector<int> support;
    for (int k = 0; k < d; ++k)
      if (terms[t][static_cast<std::size_t>(k)] > 0) support.push_back(k);
    const double c2 = c(static_cast<Eigen::Index>(t)) * c(static_cast<Eigen::Index>(t));
    if (support.empty()) {
      mean = c(static_cast<Eigen::Index>(t));
      continue;
    }
    variance += c2;
    for (const int k : support) total[static_cast<std::size_t>(k)] += c2;
    if (support.size() == 1) first[static_cast<std::size_t>(support[0])] += c2;
    if (support.size() == 2) pair(support[0], support[1]) += c2;
  }
  if (negligible_variance(mean, variance))
    throw NumericalError(
        fmt::format("{}: the fitted polynomial is constant: Sobol' indices are undefined", rsm.name()));
  SobolResult r;
  r.method = "rsm-exact";
  r.dimension = d;
  r.mean = mean;
  r.variance = variance;
  double sum = 0.0;
  for (int k = 0; k < d; ++k) {
    const double s1 = first[static_cast<std::size_t>(k)] / variance;
    const double st = total[static_cast<std::size_t>(k)] / variance;
    r.first.push_back({s1, s1, s1});
    r.total.push_back({st, st, st});
    sum += s1;
  }
  r.residual = {1.0 - sum, 1.0 - sum, 1.0 - sum};
  for (int i = 0; i < d; ++i)
    for (int j = i + 1; j < d; ++j) {
      const double s2 = pair(i, j) / variance;
      r.second.push_back({i, j, {s2, s2, s2}});
    }
  return r;
}

SobolResult metamodel_sobol(const Metamodel& fitted, const MetamodelSobolOptions& options) {
  options.validate();
  assert(fitted.fitted());
  const Eigen::MatrixXd& x = fitted.training_inputs();
  const Eigen::VectorXd& y = fitted.training_outputs();
  const int d = static_cast<int>(x.cols());
  const bool exact = options.exact_for_rsm && dynamic_cast<const PolynomialRsm*>(&fitted) != nullptr;

  // The QMC design of the indices, scrambled by `seed` (none for the exact RSM indices).
  const auto design_for = [&](std::uint64_t seed) {
    if (exact) return SaltelliDesign{};
    SaltelliOptions so;
    so.base = options.base;
    so.dimension = d;
    so.second_order = options.second_order;
    so.seed = seed;
    return saltelli_design(so);
  };
  const SaltelliDesign design = design_for(options.seed);
  SobolResult result = point_indices(fitted, design, options);
  if (!options.second_order) result.second.clear();

  const auto* gp = dynamic_cast<const GaussianProcess*>(&fitted);
  if (!exact && gp != nullptr && options.interval == MetamodelInterval::gp_posterior && options.bootstrap > 0) {
    result.confidence = options.confidence;
    result.seed = options.seed;
    result.method = "metamodel-qmc";
    add_posterior_interval(*gp, design, design_for, options, result);
    return result;
  }

  // Design bootstrap: refit on resampled training points, recompute on an independently scrambled design.
  Random rng(options.seed ^ 0xD1B54A32D192ED03ULL);
  Random design_seeds(options.seed ^ 0x2545F4914F6CDD1DULL);
  const Eigen::Index n = x.rows();
  std::vector<std::vector<double>> first(static_cast<std::size_t>(d)), total(static_cast<std::size_t>(d)),
      second(result.second.size());
  std::vector<double> residual;
  int succeeded = 0;
  for (int b = 0; b < options.bootstrap; ++b) {
    throw_if_stopped(options.stop);
    const std::uint64_t design_seed = design_seeds.bits();  // drawn for every refit, fitted or not
    std::vector<Eigen::Index> picks(static_cast<std::size_t>(n));
    for (Eigen::Index& p : picks) p = static_cast<Eigen::Index>(rng.below(static_cast<std::uint64_t>(n)));
    if (fitted.interpolates()) {
      // Interpolators cannot take a repeated point: keep the distinct points of the resample.
      const std::set<Eigen::Index> distinct(picks.begin(), picks.end());
      picks.assign(distinct.begin(), distinct.end());
    }
    Eigen::MatrixXd xb(static_cast<Eigen::Index>(picks.size()), d);
    Eigen::VectorXd yb(static_cast<Eigen::Index>(picks.size()));
    for (std::size_t r = 0; r < picks.size(); ++r) {
      xb.row(static_cast<Eigen::Index>(r)) = x.row(picks[r]);
      yb(static_cast<Eigen::Index>(r)) = y(picks[r]);
    }
    SobolResult rep;
    try {
      const std::unique_ptr<Metamodel> model = fitted.refit(xb, yb);
      const SaltelliDesign scrambled = design_for(design_seed);
      rep = point_indices(*model, scrambled, options);
    } catch (const InputError&) {
      continue;  // a resample that cannot be fitted (a constant column, too few distinct points)
    } catch (const NumericalError&) {
      continue;
    }
    ++succeeded;
    for (int k = 0; k < d; ++k) {
      first[static_cast<std::size_t>(k)].push_back(rep.first[static_cast<std::size_t>(k)].value);
      total[static_cast<std::size_t>(k)].push_back(rep.total[static_cast<std::size_t>(k)].value);
    }
    residual.push_back(rep.residual.value);
    for (std::size_t k = 0; k < second.size(); ++k) second[k].push_back(rep.second[k].s.value);
  }
  result.confidence = options.confidence;
  result.seed = options.seed;
  if (!exact) result.method = "metamodel-qmc";
  if (options.bootstrap > 0 && 2 * succeeded < options.bootstrap) {
    // Percentiles of a handful of refits would be an interval in name only: the estimates stand without one.
    result.bootstrap = 0;
    result.note = fmt::format(
        "no interval: only {} of {} design-bootstrap refits of {} succeeded (too few or too clustered training "
        "points)",
        succeeded, options.bootstrap, fitted.name());
    return result;
  }
  const double lo = 0.5 * (1.0 - options.confidence), hi = 0.5 * (1.0 + options.confidence);
  // The refits see fewer distinct points than the full fit, which shifts their indices; only the spread of the
  // replicates is used: the percentile interval is moved so that its median sits on the full-data estimate.
  auto widen = [&](IndexEstimate& e, const std::vector<double>& reps) {
    if (reps.empty()) return;
    const double median = percentile(reps, 0.5);
    e.lower = e.value - (median - percentile(reps, lo));
    e.upper = e.value + (percentile(reps, hi) - median);
  };
  for (int k = 0; k < d; ++k) {
    widen(result.first[static_cast<std::size_t>(k)], first[static_cast<std::size_t>(k)]);
    widen(result.total[static_cast<std::size_t>(k)], total[static_cast<std::size_t>(k)]);
  }
  widen(result.residual, residual);
  for (std::size_t k = 0; k < second.size(); ++k) widen(result.second[k].s, second[k]);
  result.bootstrap = succeeded;
  return result;
}

}  // namespace demsa::sobol
