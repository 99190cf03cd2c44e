// The oedometer's schedule in atom-steps (Experiment::case_cost): every atom for the pour (fill_steps), then, for each
// load, the servo plate's checks up to servo_max_steps (liggghts_templates/oedometer.liggghts), or the trial-step
// plate's trials up to max_trials, each of n_s trial steps and at most n_L relaxation steps (driver.cpp, paper §4).
// Both plates stop a load once it is reached: the cap is the estimate's bound, and the study's finished cases (or
// its probe) give the ratio actual / cap.
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/oedometer/oedometer.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <limits>
#include <string>

namespace demsa::experiments::oedometer {

CaseCost case_cost(const study::StudyConfig&, const nlohmann::json& case_json, const std::filesystem::path& file) {
  constexpr long k_big = std::numeric_limits<int>::max();
  const auto integer = [&](const char* path) {
    const std::optional<long> v = case_integer(case_json, file, path, 0, k_big);
    if (!v) throw util::UserError(fmt::format("{}: no {}: not an oedometer case of this demsa", file.string(), path));
    return *v;
  };
  const long particles = integer("assembly.particles");
  const long fill_steps = integer("oedometer.fill_steps");
  const long loads = static_cast<long>(case_list_size(case_json, file, "oedometer.loads_N", 1000));
  if (loads <= 0) throw util::UserError(fmt::format("{}: no oedometer.loads_N", file.string()));
  const bool trial = case_string(case_json, file, "oedometer.plate_mode").value_or("servo") == "trial-step";

  long per_load = 0;
  std::string plate;
  if (trial) {
    const long trial_steps = integer("oedometer.trial_step.trial_steps");
    const long relax_steps = integer("oedometer.trial_step.relax_steps");
    const long max_trials = integer("oedometer.trial_step.max_trials");
    // Each trial runs n_s steps and, when the force overshoots, n_L more; a load not reached adds one step.
    per_load = max_trials * (trial_steps + relax_steps) + 1;
    plate = fmt::format("at most {} trials of {} + {} steps", max_trials, trial_steps, relax_steps);
  } else {
    const long check_steps = integer("oedometer.servo.check_steps");
    const long max_steps = integer("oedometer.servo.max_steps");
    if (check_steps <= 0) throw util::UserError(fmt::format("{}: oedometer.servo.check_steps is 0", file.string()));
    per_load = (max_steps + check_steps - 1) / check_steps * check_steps;
    plate = fmt::format("at most {} servo steps in checks of {}", per_load, check_steps);
  }
  CaseCost cost;
  cost.steps = fill_steps + loads * per_load;
  cost.particles = particles;
  cost.atom_steps = static_cast<double>(cost.steps) * static_cast<double>(particles);
  cost.may_end_early = true;  // a load ends once it is reached
  cost.schedule = fmt::format("{} atoms: {} pouring steps, then {} load(s) of {} (the cap: a load ends once reached)",
                              particles, fill_steps, loads, plate);
  return cost;
}

}  // namespace demsa::experiments::oedometer
