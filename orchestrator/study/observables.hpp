#pragma once
// The observables an experiment produces (paper §3.3 and §4), in table order.
#include "orchestrator/study/config.hpp"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace demsa::study {

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
