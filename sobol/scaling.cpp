#include "sobol/scaling.hpp"

#include "sobol/enum_names.hpp"
#include "sobol/error.hpp"

#include <fmt/core.h>

#include <cassert>
#include <cmath>

namespace demsa::sobol {

namespace {

const EnumNames<Scale>& scale_names() {
  static const EnumNames<Scale> names{
      "scale",
      {{Scale::uniform, "uniform"}, {Scale::log_uniform, "log"}},
      {{"linear", Scale::uniform}, {"log-uniform", Scale::log_uniform}, {"log_uniform", Scale::log_uniform}}};
  return names;
}

}  // namespace

Scale scale_from_string(const std::string& name) { return scale_names().from_string(name); }
std::string to_string(Scale scale) { return scale_names().to_string(scale); }

void validate_bounds(const std::vector<Bounds>& bounds, const std::vector<std::string>& names) {
  for (std::size_t j = 0; j < bounds.size(); ++j) {
    const std::string who = j < names.size() ? "'" + names[j] + "'" : fmt::format("#{}", j + 1);
    const Bounds& b = bounds[j];
    if (!std::isfinite(b.low) || !std::isfinite(b.high))
      throw InputError(fmt::format("parameter {}: bounds must be finite (low={}, high={})", who, b.low, b.high));
    if (!(b.low < b.high))
      throw InputError(fmt::format("parameter {}: low ({}) must be less than high ({})", who, b.low, b.high));
    if (b.scale == Scale::log_uniform && b.low <= 0.0)
      throw InputError(fmt::format("parameter {}: a log scale needs low > 0 (low={})", who, b.low));
  }
}

double to_physical(double u, const Bounds& b) {
  if (b.scale == Scale::log_uniform) return b.low * std::pow(b.high / b.low, u);
  return b.low + u * (b.high - b.low);
}

double to_unit(double x, const Bounds& b) {
  if (b.scale == Scale::log_uniform) return std::log(x / b.low) / std::log(b.high / b.low);
  return (x - b.low) / (b.high - b.low);
}

Eigen::MatrixXd to_physical(const Eigen::MatrixXd& unit, const std::vector<Bounds>& bounds) {
  assert(static_cast<std::size_t>(unit.cols()) == bounds.size());
  Eigen::MatrixXd out(unit.rows(), unit.cols());
  for (Eigen::Index j = 0; j < unit.cols(); ++j)
    for (Eigen::Index i = 0; i < unit.rows(); ++i) out(i, j) = to_physical(unit(i, j), bounds[j]);
  return out;
}

Eigen::MatrixXd to_unit(const Eigen::MatrixXd& physical, const std::vector<Bounds>& bounds) {
  assert(static_cast<std::size_t>(physical.cols()) == bounds.size());
  Eigen::MatrixXd out(physical.rows(), physical.cols());
  for (Eigen::Index j = 0; j < physical.cols(); ++j)
    for (Eigen::Index i = 0; i < physical.rows(); ++i) out(i, j) = to_unit(physical(i, j), bounds[j]);
  return out;
}

}  // namespace demsa::sobol
