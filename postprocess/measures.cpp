#include "postprocess/measures.hpp"

#include "postprocess/error.hpp"

#include <fmt/core.h>

#include <cmath>

namespace demsa::postprocess {

double angle_error(double measured_angle_deg, double target_angle_deg) {
  const double d = target_angle_deg - measured_angle_deg;
  return d * d;
}

double settlement_error(const std::vector<double>& simulated, const std::vector<double>& measured) {
  if (simulated.size() != measured.size())
    throw InputError(fmt::format("{} simulated settlements but {} measured ones", simulated.size(), measured.size()));
  double sum = 0.0;
  for (std::size_t i = 0; i < simulated.size(); ++i) sum += (measured[i] - simulated[i]) * (measured[i] - simulated[i]);
  return std::sqrt(sum);
}

}  // namespace demsa::postprocess
