#include "orchestrator/experiments/oedometer/measurement_json.hpp"

namespace demsa::experiments::oedometer {

namespace pp = demsa::postprocess;

nlohmann::json measurement_json(const pp::OedometerResult& r) {
  nlohmann::json j;
  j["options"] = {{"box_side_m", r.options.box_side},
                  {"floor_z_m", r.options.floor_z},
                  {"solid_volume_m3", r.options.solid_volume},
                  {"measured_settlements_m", r.options.measured_settlements}};
  nlohmann::json steps = nlohmann::json::array();
  for (const pp::OedometerStep& s : r.steps) {
    nlohmann::json step = {{"load_N", s.load_N},       {"plate_z_m", s.plate_z_m},       {"force_N", s.force_N},
                           {"converged", s.converged}, {"settlement_m", s.settlement_m}, {"stress_Pa", s.stress_Pa}};
    step["void_ratio"] = s.void_ratio ? nlohmann::json(*s.void_ratio) : nlohmann::json(nullptr);
    steps.push_back(std::move(step));
  }
  j["steps"] = std::move(steps);
  j["settlements_m"] = r.settlements;
  j["settlement_error_m"] = r.settlement_error ? nlohmann::json(*r.settlement_error) : nlohmann::json(nullptr);
  j["all_converged"] = r.all_converged;
  if (r.history) {
    const pp::PlateHistory& h = *r.history;
    nlohmann::json history = {{"file", h.file},     {"columns", h.columns},     {"step", h.step},
                              {"load_N", h.load_N}, {"plate_z_m", h.plate_z_m}, {"force_N", h.force_N}};
    if (!h.trial.empty()) history["trial"] = h.trial;
    if (!h.delta_m.empty()) history["delta_m"] = h.delta_m;
    if (!h.accepted.empty()) history["accepted"] = h.accepted;
    j["history"] = std::move(history);
    j["trials_accepted"] = r.trials_accepted;
    j["trials_rejected"] = r.trials_rejected;
  } else {
    j["history"] = nullptr;
  }
  return j;
}

}  // namespace demsa::experiments::oedometer
