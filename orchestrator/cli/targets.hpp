#pragma once
// The options of measured values and observables (`demsa plan --sd/--observe/--near`; calibrate's are read by
// analysis/calibration_method.hpp): the syntax is the analysis library's (analysis/target_syntax.hpp); its messages
// start with the option as the user typed it.
#include "orchestrator/analysis/target_syntax.hpp"

#include <string>
#include <vector>

namespace demsa::cli {

using analysis::parse_measured;
using analysis::parse_observable;

/// "NAME=SD" or "STUDY:NAME=SD" of `plan --sd`.
inline analysis::ObservableSd parse_observable_sd(const std::string& text) {
  return analysis::parse_observable_sd("--sd", text);
}

}  // namespace demsa::cli
