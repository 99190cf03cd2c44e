#include "sobol/metamodel_sobol.hpp"

#include "sobol/random.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>
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
  qmc.bootstrap = 0;
  qmc.seed = options.seed;
  qmc.stop = options.stop;
  return sobol_indices([&model](const Eigen::MatrixXd& x) { return model.predict(x); }, design, qmc);
}

}  // namespace

void MetamodelSobolOptions::validate() const {
  if (base < 2) throw InputError(fmt::format("sobol base = {}: must be at least 2", base));
  if (bootstrap < 0) throw InputError(fmt::format("sobol bootstrap = {}: must be >= 0", bootstrap));
  if (!(confidence > 0.0 && confidence < 1.0))
    throw InputError(fmt::format("sobol confidence = {}: must be in (0, 1)", confidence));
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
