// The pile's schedule in atom-steps (Experiment::case_cost): the column's atoms for the first interval, one more disc
// of atoms after each interval, then every atom for the settling cap (liggghts_templates/pile.liggghts). A pile that
// removes its fallen particles holds at most what its pedestal can carry (pedestal_capacity): the atoms of each
// interval are counted up to that.
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/physics.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace demsa::experiments::pile {

double pedestal_capacity(const PileSettings& s) {
  // A cone of the angle of repose on the pedestal's top, plus one layer of mean particles over the top, at the solid
  // fraction of a random loose packing, 0.6 (Onoda & Liniger, Phys. Rev. Lett. 64 (1990) 2727), in mean particle
  // volumes (E[r^3] = mean^3 + 3 mean sd^2 of the radius distribution). The angle is the larger of target_angle and
  // 35 degrees, so that the bill errs on the dear side. Against the quickstart's settled piles (docs/how-to/cost.md):
  // 1745 at 32.8 degrees against 1764 on the pedestal, 1922 at 36.3 against 1894.
  constexpr double k_solid_fraction = 0.6;
  constexpr double k_pi = 3.14159265358979323846;
  const double angle = std::max(s.target_angle, 35.0) * k_pi / 180.0;
  const double r = s.pedestal_radius;
  const double mean = s.radii.mean;
  const double particle = 4.0 / 3.0 * k_pi * (mean * mean * mean + 3.0 * mean * s.radii.sd * s.radii.sd);
  const double volume = k_pi * r * r * r * std::tan(angle) / 3.0 + k_pi * r * r * 2.0 * mean;
  return particle > 0.0 ? k_solid_fraction * volume / particle : std::numeric_limits<double>::infinity();
}

CaseCost case_cost(const study::StudyConfig& config, const nlohmann::json& case_json, const std::filesystem::path& file,
                   const nlohmann::json& /*probed*/) {
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
  // With remove_fallen, what the pedestal carries and one disc still falling onto it.
  const double most = remove_fallen ? pedestal_capacity(s) + per_disc : std::numeric_limits<double>::infinity();
  double append_atom_steps = 0.0;
  for (long k = 0; k < appended; ++k)
    append_atom_steps += std::min(static_cast<double>(column) + per_disc * static_cast<double>(k), most);
  append_atom_steps = static_cast<double>(append_steps) * (append_atom_steps + static_cast<double>(appended * base));
  const double settle_atom_steps =
      static_cast<double>(settle_run) * (std::min(static_cast<double>(particles), most) + static_cast<double>(base));

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
      remove_fallen ? fmt::format(" (fallen particles removed: at most {:.0f} on the pedestal)", most) : "");
  return cost;
}

}  // namespace demsa::experiments::pile
