// The pile's schedule in atom-steps (Experiment::case_cost): the column's atoms for the first interval, one more disc
// of atoms after each interval, then every atom for the settling cap (liggghts_templates/pile.liggghts).
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/physics.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <limits>
#include <string>

namespace demsa::experiments::pile {

CaseCost case_cost(const study::StudyConfig& config, const nlohmann::json& case_json,
                   const std::filesystem::path& file) {
  constexpr long k_big = std::numeric_limits<int>::max();
  const auto integer = [&](const char* path) {
    const std::optional<long> v = case_integer(case_json, file, path, 0, k_big);
    if (!v) throw util::UserError(fmt::format("{}: no {}: not a pile case of this demsa", file.string(), path));
    return *v;
  };
  const std::optional<double> dt = case_number(case_json, file, "dt", 0.0, 1.0);
  if (!dt || *dt <= 0.0) throw util::UserError(fmt::format("{}: no time step (dt)", file.string()));
  const long particles = integer("assembly.particles");
  const long column = integer("assembly.column_particles");
  const long discs = integer("assembly.discs");
  const long column_discs = integer("assembly.column_discs");
  const long append_steps = integer("pile.append_steps");
  const long settle_steps = integer("pile.settle_steps");
  const long base = case_integer(case_json, file, "assembly.base_particles", 0, k_big).value_or(0);
  const long window_checks = case_integer(case_json, file, "pile.settle_window_checks", 0, k_big).value_or(0);
  const bool remove_fallen = case_json.contains("pile") && case_json["pile"].value("remove_fallen", false);

  // Settling runs in whole checks of settle_check_steps until they cover settle_steps (case.cpp, pile.liggghts).
  const PileSettings& s = settings(config);
  const long check_steps =
      std::max(1L, std::min(settle_steps, steps_for(s.settle_check_time, *dt, "[pile] settle_check_time")));
  const long settle_run = (settle_steps + check_steps - 1) / check_steps * check_steps;

  // Interval k (k = 0 .. appended - 1) runs with the column and k appended discs; a disc holds on average
  // (particles - column) / appended atoms (discs of the same radius hold nearly the same count, paper §3.1).
  const long appended = std::max(0L, discs - column_discs);
  const double per_disc = appended > 0 ? static_cast<double>(particles - column) / static_cast<double>(appended) : 0.0;
  const double a = static_cast<double>(appended);
  const double append_atom_steps =
      static_cast<double>(append_steps) * (a * static_cast<double>(column + base) + per_disc * a * (a - 1.0) / 2.0);
  const double settle_atom_steps = static_cast<double>(settle_run) * static_cast<double>(particles + base);

  CaseCost cost;
  cost.atom_steps = append_atom_steps + settle_atom_steps;
  cost.steps = appended * append_steps + settle_run;
  cost.particles = particles + base;
  cost.may_end_early = window_checks > 0 || remove_fallen;
  cost.schedule = fmt::format(
      "{} atoms at the start, {} discs appended every {} steps, then {} settling steps with {} "
      "atoms{}{}",
      column + base, appended, append_steps, settle_run, particles + base,
      window_checks > 0 ? " (the cap: the settling criterion may end it earlier)" : "",
      remove_fallen ? " (fallen particles removed)" : "");
  return cost;
}

}  // namespace demsa::experiments::pile
