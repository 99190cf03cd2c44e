#include "sobol/posterior.hpp"

#include "sobol/error.hpp"
#include "sobol/gp.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace demsa::sobol {

double constant_model_variance(const Metamodel& model) {
  if (model.kind() == MetamodelKind::gp) return 0.0;
  const Eigen::VectorXd e = model.loo_residuals();
  // A model without leave-one-out residuals, or with 0/0 ones (fitted on as many samples as terms), has an error that
  // cannot be measured: NaN, which GaussianPosterior refuses, never 0.
  if (e.size() == 0 || !e.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  return e.squaredNorm() / static_cast<double>(e.size());  // PRESS / n
}

GaussianPosterior::GaussianPosterior(std::vector<GaussianTarget> targets, int dimension)
    : m_targets(std::move(targets)), m_dimension(dimension) {
  if (m_targets.empty()) throw InputError("Bayesian calibration: no target");
  if (dimension < 1) throw InputError(fmt::format("Bayesian calibration: dimension {} must be >= 1", dimension));
  for (GaussianTarget& t : m_targets) {
    if (t.model == nullptr || !t.model->fitted())
      throw InputError(fmt::format("target {}: the metamodel is not fitted", t.name));
    const int inputs = static_cast<int>(t.model->training_inputs().cols());
    if (t.inputs.empty()) {
      if (inputs != dimension)
        throw InputError(
            fmt::format("target {}: the metamodel has {} inputs, the posterior {}", t.name, inputs, dimension));
      for (int j = 0; j < inputs; ++j) t.inputs.push_back({j, 0.0, 1.0});
    }
    if (static_cast<int>(t.inputs.size()) != inputs)
      throw InputError(
          fmt::format("target {}: {} input maps for a metamodel of {} inputs", t.name, t.inputs.size(), inputs));
    for (const InputMap& m : t.inputs)
      if (m.column < 0 || m.column >= dimension || !std::isfinite(m.offset) || !std::isfinite(m.slope))
        throw InputError(
            fmt::format("target {}: input map to column {} outside 1..{}", t.name, m.column + 1, dimension));
    if (!std::isfinite(t.value)) throw InputError(fmt::format("target {}: value {} is not finite", t.name, t.value));
    if (!(t.sd >= 0.0) || !std::isfinite(t.sd))
      throw InputError(fmt::format("target {}: standard deviation {} must be >= 0", t.name, t.sd));
    if (!(t.weight >= 0.0) || !std::isfinite(t.weight))
      throw InputError(fmt::format("target {}: weight {} must be >= 0", t.name, t.weight));
    const double s2 = constant_model_variance(*t.model);
    if (t.model->kind() != MetamodelKind::gp && !std::isfinite(s2))
      throw InputError(fmt::format(
          "target {}: the metamodel's leave-one-out error cannot be measured (as many samples as terms): its "
          "variance is unknown, not 0",
          t.name));
    if (!std::isfinite(t.sd * t.sd))
      throw InputError(fmt::format("target {}: standard deviation {:g}: its square overflows", t.name, t.sd));
    if (t.model->kind() != MetamodelKind::gp && t.sd == 0.0 && s2 == 0.0)
      throw InputError(fmt::format(
          "target {}: no uncertainty (measurement standard deviation 0 and a metamodel without leave-one-out "
          "error): give the measurement's uncertainty",
          t.name));
    m_constant_variance.push_back(s2);
  }
}

Eigen::MatrixXd GaussianPosterior::model_inputs(const GaussianTarget& target, const Eigen::MatrixXd& u) const {
  Eigen::MatrixXd x(u.rows(), static_cast<Eigen::Index>(target.inputs.size()));
  for (size_t j = 0; j < target.inputs.size(); ++j) {
    const InputMap& m = target.inputs[j];
    // The metamodel was fitted on [0,1]; a prior box inside its range maps inside it (clamped for rounding).
    x.col(static_cast<Eigen::Index>(j)) =
        (m.offset + m.slope * u.col(m.column).array()).cwiseMax(0.0).cwiseMin(1.0).matrix();
  }
  return x;
}

void GaussianPosterior::predict(const Eigen::MatrixXd& u, Eigen::MatrixXd& mean, Eigen::MatrixXd& sd) const {
  const Eigen::Index k_targets = static_cast<Eigen::Index>(m_targets.size());
  mean.resize(u.rows(), k_targets);
  sd.resize(u.rows(), k_targets);
  for (Eigen::Index k = 0; k < k_targets; ++k) {
    const GaussianTarget& t = m_targets[static_cast<size_t>(k)];
    const Eigen::MatrixXd x = model_inputs(t, u);
    mean.col(k) = t.model->predict(x);
    Eigen::ArrayXd variance = Eigen::ArrayXd::Constant(u.rows(), t.sd * t.sd + m_constant_variance[k]);
    if (t.model->kind() == MetamodelKind::gp) {
      const auto& gp = dynamic_cast<const GaussianProcess&>(*t.model);
      variance += gp.predict_sd(x).array().square();
    }
    sd.col(k) = variance.sqrt().matrix();
  }
}

Eigen::VectorXd GaussianPosterior::operator()(const Eigen::MatrixXd& u) const {
  Eigen::MatrixXd mean, sd;
  predict(u, mean, sd);
  Eigen::VectorXd lp = Eigen::VectorXd::Zero(u.rows());
  for (size_t k = 0; k < m_targets.size(); ++k) {
    const GaussianTarget& t = m_targets[k];
    const Eigen::Index c = static_cast<Eigen::Index>(k);
    for (Eigen::Index i = 0; i < u.rows(); ++i) {
      const double v = sd(i, c) * sd(i, c);
      if (!(v > 0.0)) {
        lp(i) = -std::numeric_limits<double>::infinity();
        continue;
      }
      const double r = mean(i, c) - t.value;
      lp(i) += t.weight * (-0.5 * r * r / v - 0.5 * std::log(v));
    }
  }
  return lp;
}

BatchLogDensity posterior_function(const GaussianPosterior& posterior) {
  return [&posterior](const Eigen::MatrixXd& u) { return posterior(u); };
}

double quantile(std::vector<double> v, double p) {
  assert(!v.empty() && p >= 0.0 && p <= 1.0);
  std::sort(v.begin(), v.end());
  const double h = (static_cast<double>(v.size()) - 1.0) * p;
  const size_t lo = static_cast<size_t>(std::floor(h));
  const size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (h - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

std::vector<MarginalSummary> summarise_marginals(const EnsembleResult& result, const std::vector<double>& lower,
                                                 const std::vector<double>& upper) {
  std::vector<MarginalSummary> out;
  for (int j = 0; j < result.dimension; ++j) {
    const Eigen::VectorXd column = result.draws.col(j);
    const std::vector<double> values(column.data(), column.data() + column.size());
    MarginalSummary m;
    m.mean = column.mean();
    m.map = result.best(j);
    m.q05 = quantile(values, 0.05);
    m.q50 = quantile(values, 0.50);
    m.q95 = quantile(values, 0.95);
    m.width_ratio = (m.q95 - m.q05) / (upper[j] - lower[j]);
    out.push_back(m);
  }
  return out;
}

Eigen::MatrixXd posterior_correlation(const Eigen::MatrixXd& draws) {
  const Eigen::MatrixXd centred = draws.rowwise() - draws.colwise().mean();
  Eigen::MatrixXd cov =
      centred.transpose() * centred / static_cast<double>(std::max<Eigen::Index>(draws.rows() - 1, 1));
  const Eigen::VectorXd sd = cov.diagonal().cwiseSqrt();
  Eigen::MatrixXd corr(cov.rows(), cov.cols());
  for (Eigen::Index i = 0; i < cov.rows(); ++i)
    for (Eigen::Index j = 0; j < cov.cols(); ++j)
      corr(i, j) = (sd(i) > 0 && sd(j) > 0) ? cov(i, j) / (sd(i) * sd(j)) : (i == j ? 1.0 : 0.0);
  return corr;
}

}  // namespace demsa::sobol
