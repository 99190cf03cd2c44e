#include "sobol/metamodel.hpp"

#include "sobol/enum_names.hpp"
#include "sobol/gp.hpp"
#include "sobol/rbf.hpp"
#include "sobol/rsm.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

namespace demsa::sobol {

namespace {

const EnumNames<MetamodelKind>& metamodel_kind_names() {
  static const EnumNames<MetamodelKind> names{"metamodel",
                                              {{MetamodelKind::rsm1, "rsm1"},
                                               {MetamodelKind::rsm2, "rsm2"},
                                               {MetamodelKind::rsm3, "rsm3"},
                                               {MetamodelKind::rbf_cubic, "rbf-cubic"},
                                               {MetamodelKind::rbf_tps, "rbf-tps"},
                                               {MetamodelKind::gp, "gp"}}};
  return names;
}

const EnumNames<GpKernel>& gp_kernel_names() {
  static const EnumNames<GpKernel> names{
      "GP kernel",
      {{GpKernel::squared_exponential, "squared-exponential"}, {GpKernel::matern52, "matern52"}},
      {{"se", GpKernel::squared_exponential},
       {"gaussian", GpKernel::squared_exponential},
       {"matern-5/2", GpKernel::matern52}}};
  return names;
}

const EnumNames<GpTrend>& gp_trend_names() {
  static const EnumNames<GpTrend> names{"GP trend", {{GpTrend::constant, "constant"}, {GpTrend::linear, "linear"}}};
  return names;
}

}  // namespace

MetamodelKind metamodel_kind_from_string(const std::string& name) { return metamodel_kind_names().from_string(name); }
std::string to_string(MetamodelKind kind) { return metamodel_kind_names().to_string(kind); }
std::vector<std::string> metamodel_names() { return metamodel_kind_names().names(); }

GpKernel gp_kernel_from_string(const std::string& name) { return gp_kernel_names().from_string(name); }
std::string to_string(GpKernel kernel) { return gp_kernel_names().to_string(kernel); }

GpTrend gp_trend_from_string(const std::string& name) { return gp_trend_names().from_string(name); }
std::string to_string(GpTrend trend) { return gp_trend_names().to_string(trend); }

void GpOptions::validate() const {
  if (!(min_length > 0.0)) throw InputError(fmt::format("gp min_length = {}: must be > 0", min_length));
  if (!(max_length > min_length))
    throw InputError(fmt::format("gp max_length = {}: must be > min_length ({})", max_length, min_length));
  if (!(min_nugget > 0.0)) throw InputError(fmt::format("gp min_nugget = {}: must be > 0", min_nugget));
  if (!(max_nugget > min_nugget))
    throw InputError(fmt::format("gp max_nugget = {}: must be > min_nugget ({})", max_nugget, min_nugget));
  if (!std::isnan(noise_share) && !(noise_share >= 0.0 && std::isfinite(noise_share)))
    throw InputError(fmt::format("gp noise_share = {}: must be a number >= 0 (or NaN: not measured)", noise_share));
  if (!std::isnan(noise_share) && !nugget)
    throw InputError(fmt::format("gp noise_share = {}: a measured noise needs the nugget", noise_share));
  if (starts < 1) throw InputError(fmt::format("gp starts = {}: must be at least 1", starts));
  if (max_evaluations < 10)
    throw InputError(fmt::format("gp max_evaluations = {}: must be at least 10", max_evaluations));
}

void MetamodelOptions::validate() const { gp.validate(); }

void Metamodel::store_training_data(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, int min_samples) {
  m_fitted = false;
  if (x.rows() != y.size())
    throw InputError(fmt::format("{}: {} input rows but {} outputs", name(), x.rows(), y.size()));
  if (x.cols() < 1) throw InputError(fmt::format("{}: the data have no input column", name()));
  if (x.rows() < min_samples)
    throw InputError(
        fmt::format("{} needs at least {} samples for {} inputs (got {})", name(), min_samples, x.cols(), x.rows()));
  constexpr double tolerance = 1e-9;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    for (Eigen::Index k = 0; k < x.cols(); ++k) {
      const double v = x(i, k);
      if (!std::isfinite(v))
        throw DataError(static_cast<int>(i), static_cast<int>(k), fmt::format("{} is not a finite number", v));
      if (v < -tolerance || v > 1.0 + tolerance)
        throw DataError(static_cast<int>(i), static_cast<int>(k),
                        fmt::format("{} is outside the unit cube [0, 1] (scale the inputs to their bounds first)", v));
    }
    if (!std::isfinite(y(i)))
      throw DataError(static_cast<int>(i), -1, fmt::format("output {} is not a finite number", y(i)));
  }
  for (Eigen::Index k = 0; k < x.cols(); ++k)
    if (x.col(k).maxCoeff() == x.col(k).minCoeff())
      throw DataError(-1, static_cast<int>(k),
                      fmt::format("constant input (every sample is {}): it carries no information; drop it", x(0, k)));
  m_x = x;
  m_y = y;
}

MetamodelSummary Metamodel::base_summary(const Eigen::VectorXd& fitted_values, int terms) const {
  const Eigen::VectorXd loo = loo_residuals();
  MetamodelSummary s;
  s.name = name();
  s.samples = static_cast<int>(m_x.rows());
  s.dimension = static_cast<int>(m_x.cols());
  s.terms = terms;
  s.mean = m_y.mean();
  const double sst = (m_y.array() - s.mean).square().sum();
  s.sd = s.samples > 1 ? std::sqrt(sst / (s.samples - 1)) : 0.0;
  const double sse = (m_y - fitted_values).squaredNorm();
  const double press = loo.squaredNorm();
  s.r2 = sst > 0.0 ? 1.0 - sse / sst : std::numeric_limits<double>::quiet_NaN();
  s.adjusted_r2 = s.r2;
  s.q2 = sst > 0.0 ? 1.0 - press / sst : std::numeric_limits<double>::quiet_NaN();
  s.rmse_loo = std::sqrt(press / s.samples);
  return s;
}

void check_no_duplicates(const Eigen::MatrixXd& x) {
  std::vector<Eigen::Index> order(static_cast<std::size_t>(x.rows()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  auto less = [&](Eigen::Index a, Eigen::Index b) {
    for (Eigen::Index k = 0; k < x.cols(); ++k)
      if (x(a, k) != x(b, k)) return x(a, k) < x(b, k);
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  for (std::size_t t = 1; t < order.size(); ++t) {
    const Eigen::Index a = order[t - 1], b = order[t];
    if (x.row(a) == x.row(b)) {
      const Eigen::Index first = std::min(a, b), second = std::max(a, b);
      throw DataError(static_cast<int>(second), -1,
                      fmt::format("duplicates the point of sample {}: an interpolating metamodel needs distinct "
                                  "points (average the repeats, or use an RSM or a GP with a nugget)",
                                  first + 1),
                      static_cast<int>(first));
    }
  }
}

std::unique_ptr<Metamodel> make_metamodel(MetamodelKind kind, const MetamodelOptions& options) {
  options.validate();
  switch (kind) {
    case MetamodelKind::rsm1:
      return std::make_unique<PolynomialRsm>(1);
    case MetamodelKind::rsm2:
      return std::make_unique<PolynomialRsm>(2);
    case MetamodelKind::rsm3:
      return std::make_unique<PolynomialRsm>(3);
    case MetamodelKind::rbf_cubic:
    case MetamodelKind::rbf_tps:
      return std::make_unique<RbfInterpolant>(kind);
    case MetamodelKind::gp:
      return std::make_unique<GaussianProcess>(options.gp);
  }
  assert(false && "unhandled MetamodelKind");
  return nullptr;
}

std::unique_ptr<Metamodel> make_metamodel(const std::string& name, const MetamodelOptions& options) {
  return make_metamodel(metamodel_kind_from_string(name), options);
}

}  // namespace demsa::sobol
