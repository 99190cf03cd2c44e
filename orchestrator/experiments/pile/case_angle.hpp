#pragma once
// How a pile measured outside a study run (`demsa postprocess pile`, `demsa compare`) takes its case's measurement:
// what its case.json records (pile.hpp's CaseAngleSettings), but for the options the caller chose itself.
#include "orchestrator/experiments/angle_of_repose.hpp"
#include "postprocess/pile_angle.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace demsa::experiments::pile {

/// The angle options of the pile case whose case.json is `case_json` (read from `file`): the caller's where it chose
/// them, else what the case records (as case_angle_options). Throws util::UserError naming case.json when the case is
/// of another experiment, when it records no pedestal and the caller did not choose both its radius and top (a case
/// of an older demsa: the defaults would measure another pedestal silently; the message names
/// PileAngleOptions.pedestal_radius and .pedestal_top).
CaseAngle case_angle(const nlohmann::json& case_json, const std::filesystem::path& file,
                     const ChosenAngleOptions& chosen);

}  // namespace demsa::experiments::pile
