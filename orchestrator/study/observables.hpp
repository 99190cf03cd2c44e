#pragma once
// The observables an experiment produces (paper §3.3 and §4), in table order.
#include "orchestrator/study/config.hpp"

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::study {

/// Stored with a pile's observables, not analysed: 1 when the settling criterion ([pile] settle_speed) was met, 0
/// when the pile reached settle_time still moving (absent when the criterion is off), and the number of particles
/// removed off the pedestal during the run ([pile] remove_fallen).
inline constexpr std::string_view k_settled = "settled";
inline constexpr std::string_view k_removed_off_pedestal = "removed_off_pedestal";

/// The samples whose done run recorded an unsettled pile (k_settled = 0), from Store::observables().
std::vector<int> unsettled_samples(const std::map<int, std::map<std::string, double>>& observables);

/// The names of the observables an experiment produces, in table order (for the analysis).
std::vector<std::string> observable_names(const StudyConfig& config);

/// A case run at one point outside the design (the verification of a calibration) and what it measured.
struct PointRun {
  std::filesystem::path folder;               ///< the case folder
  std::map<std::string, double> observables;  ///< measured values (empty when error is set)
  std::string error;                          ///< why the run or its measurement failed; "" when measured
  double seconds = 0.0;                       ///< wall time of the run [s]
};

}  // namespace demsa::study
