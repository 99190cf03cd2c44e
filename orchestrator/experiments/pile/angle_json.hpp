#pragma once
// The JSON form of a pile's measured angle of repose (`demsa postprocess pile --json`): the dump and case.json it came
// from, the options it was measured with, the angle with its spread, and every direction's line and boundary
// particle (lengths in m, angles in degrees, as the keys' suffixes say).
#include "postprocess/pile_angle.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace demsa::experiments::pile {

/// `case_json`: the case.json whose settings were used ("" when none: null).
nlohmann::json angle_result_json(const postprocess::PileAngleResult& result, const std::string& dump,
                                 const std::string& case_json);

}  // namespace demsa::experiments::pile
