#pragma once
// The text syntax of measured values and observables, "NAME=V±E", "STUDY:NAME", "NAME=FILE.csv", "NAME=W",
// "NAME=SD", parsed into the analysis library's types (measured_target.hpp, joint_studies.hpp, experiment_plan.hpp):
// what any front end reads from its user. Each function throws util::UserError that starts with `label` (what the
// caller calls the text: `demsa calibrate` passes "--target") and quotes the text as given.
#include "orchestrator/analysis/experiment_plan.hpp"
#include "orchestrator/analysis/joint_studies.hpp"
#include "orchestrator/analysis/measured_target.hpp"

#include <string>
#include <utility>
#include <vector>

namespace demsa::analysis {

/// "NAME" or "STUDY:NAME" (STUDY: a study's `[study] name`).
QualifiedName parse_observable(const std::string& label, const std::string& text);

/// "NAME=V", "NAME=V±E" (also +-) or a curve "NAME=V1,V2,...±E1,E2,..." (one E for all, or one per value) that sets
/// NAME_1, NAME_2, ...; NAME may be STUDY:NAME. Without ± the sd is 0; an explicit ± must be > 0.
std::vector<MeasuredTarget> parse_measured(const std::string& label, const std::string& text);

/// "NAME=FILE.csv": the measured curve the file holds (read_measured_curve).
std::vector<MeasuredTarget> read_target_file(const std::string& label, const std::string& text);

/// "NAME=W" (NAME may be STUDY:NAME), W >= 0: the target's label and its weight.
std::pair<std::string, double> parse_weight(const std::string& label, const std::string& text);

/// "NAME=SD" or "STUDY:NAME=SD": the total sd of a measured observable.
ObservableSd parse_observable_sd(const std::string& label, const std::string& text);

}  // namespace demsa::analysis
