#pragma once
// How a pile measured outside a study run (`demsa postprocess pile`, `demsa compare`) takes its case's measurement:
// what its case.json records (pile.hpp's CaseAngleSettings), but for the options the caller chose itself.
#include "postprocess/pile_angle.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace demsa::experiments::pile {

/// Angle options a caller chose itself (a command line's): each flagged one wins over what a case records.
struct ChosenAngleOptions {
  postprocess::PileAngleOptions options;  ///< the caller's values (the defaults where it chose none)
  bool pedestal_radius = false;           ///< options.pedestal_radius was chosen
  bool pedestal_top = false;              ///< options.pedestal_top was chosen (a base layer's top then does not count)
  bool directions = false;                ///< options.directions was chosen
  bool levels = false;                    ///< options.levels was chosen
  bool estimator = false;                 ///< options.estimator was chosen
};

/// A pile case's angle options with the caller's choices, and the particles of its base layer.
struct CaseAngle {
  postprocess::PileAngleOptions options;  ///< not validated: the caller's own choices are its to check
  long base_particles = 0;                ///< atoms 1..N are the base layer, left out of the measurement
};

/// The angle options of the pile case whose case.json is `case_json` (read from `file`): the caller's where it chose
/// them, else what the case records (as case_angle_options). Throws util::UserError naming case.json when the case is
/// of another experiment, when it records no pedestal and the caller did not choose both its radius and top (a case
/// of an older demsa: the defaults would measure another pedestal silently; the message names
/// PileAngleOptions.pedestal_radius and .pedestal_top).
CaseAngle case_angle(const nlohmann::json& case_json, const std::filesystem::path& file,
                     const ChosenAngleOptions& chosen);

}  // namespace demsa::experiments::pile
