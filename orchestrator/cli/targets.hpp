#pragma once
// The options of measured values and observables (`demsa calibrate --target/--target-file/--weight`, `demsa plan
// --sd/--observe/--near`): the syntax is the analysis library's (analysis/target_syntax.hpp); its messages start
// with the option as the user typed it.
#include "orchestrator/analysis/target_syntax.hpp"

#include <string>
#include <utility>
#include <vector>

namespace demsa::cli {

using analysis::parse_measured;
using analysis::parse_observable;

/// "NAME=FILE.csv" of --target-file.
inline std::vector<analysis::MeasuredTarget> read_target_file(const std::string& text) {
  return analysis::read_target_file("--target-file", text);
}

/// "NAME=W" of --weight.
inline std::pair<std::string, double> parse_weight(const std::string& text) {
  return analysis::parse_weight("--weight", text);
}

/// "NAME=SD" or "STUDY:NAME=SD" of `plan --sd`.
inline analysis::ObservableSd parse_observable_sd(const std::string& text) {
  return analysis::parse_observable_sd("--sd", text);
}

}  // namespace demsa::cli
