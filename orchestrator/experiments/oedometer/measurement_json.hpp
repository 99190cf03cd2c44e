#pragma once
// The JSON form of an oedometer's measurement (`demsa postprocess oedometer --json`): the options, every load step
// (load, plate, force, settlement, stress, void ratio), the settlements and E_0, and the plate history when one was
// read (SI units, as the keys' suffixes say).
#include "postprocess/oedometer.hpp"

#include <nlohmann/json.hpp>

namespace demsa::experiments::oedometer {

nlohmann::json measurement_json(const postprocess::OedometerResult& result);

}  // namespace demsa::experiments::oedometer
