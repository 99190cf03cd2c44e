#pragma once
// Mapping between the unit cube [0,1]^d, where designs, metamodels and Sobol' indices live (paper §6: "the input
// space must be defined in a n-dimensional unit cube"), and the physical parameter space.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace demsa::sobol {

enum class Scale { uniform, log_uniform };

/// "uniform" | "log" (also "log-uniform", "log_uniform"); throws InputError listing the valid names.
Scale scale_from_string(const std::string& name);
std::string to_string(Scale scale);

/// One parameter's range. Valid when low < high (and low > 0 for a log-uniform scale).
struct Bounds {
  double low = 0.0;
  double high = 1.0;
  Scale scale = Scale::uniform;
};

/// Throws InputError naming the parameter index/name and values when a range is invalid.
void validate_bounds(const std::vector<Bounds>& bounds, const std::vector<std::string>& names = {});

/// u in [0,1] -> physical value: low + u (high - low), or low (high/low)^u for a log-uniform scale.
double to_physical(double u, const Bounds& b);
/// Inverse of to_physical.
double to_unit(double x, const Bounds& b);

/// Row-wise mapping of a design (rows = samples, columns = parameters).
Eigen::MatrixXd to_physical(const Eigen::MatrixXd& unit, const std::vector<Bounds>& bounds);
Eigen::MatrixXd to_unit(const Eigen::MatrixXd& physical, const std::vector<Bounds>& bounds);

}  // namespace demsa::sobol
