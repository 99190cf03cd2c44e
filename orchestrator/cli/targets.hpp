#pragma once
// The command line's syntax of measured values and observables (`demsa calibrate --target/--target-file/--weight`,
// `demsa plan --sd/--observe/--near`), parsed into the analysis library's types. Each throws util::UserError naming
// the option and the text as typed.
#include "orchestrator/analysis/experiment_plan.hpp"
#include "orchestrator/analysis/measured_target.hpp"

#include <string>
#include <utility>
#include <vector>

namespace demsa::cli {

/// "NAME" or "STUDY:NAME" (STUDY: a study's `[study] name`).
analysis::QualifiedName parse_observable(const std::string& option, const std::string& text);

/// "NAME=V", "NAME=V±E" (also +-) or a curve "NAME=V1,V2,...±E1,E2,..." (one E for all, or one per value) that sets
/// NAME_1, NAME_2, ...; NAME may be STUDY:NAME. Without ± the sd is 0; an explicit ± must be > 0.
std::vector<analysis::MeasuredTarget> parse_measured(const std::string& option, const std::string& text);

/// "NAME=FILE.csv" of --target-file: the measured curve the file holds (analysis::read_measured_curve).
std::vector<analysis::MeasuredTarget> read_target_file(const std::string& text);

/// "NAME=W" of --weight (NAME may be STUDY:NAME), W >= 0: the target's label and its weight.
std::pair<std::string, double> parse_weight(const std::string& text);

/// "NAME=SD" or "STUDY:NAME=SD" of `plan --sd`.
analysis::ObservableSd parse_observable_sd(const std::string& text);

}  // namespace demsa::cli
