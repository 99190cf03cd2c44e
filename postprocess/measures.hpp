#pragma once
// The paper's goodness-of-fit measures between a simulation and the lab.
#include <vector>

namespace demsa::postprocess {

/// E_φ = (φ̂ − φ)² (paper §3.3), angles in degrees.
double angle_error(double measured_angle_deg, double target_angle_deg);

/// E_0 = sqrt(Σ_i (s̃_i − s_i)²) over the load steps (paper §4), settlements in the same unit. Throws InputError
/// when the two lists differ in length.
double settlement_error(const std::vector<double>& simulated, const std::vector<double>& measured);

}  // namespace demsa::postprocess
