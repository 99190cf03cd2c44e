#include "orchestrator/experiments/physics.hpp"

#include "orchestrator/study/setting_row.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>

namespace demsa::experiments {

using namespace demsa::study;

double shear_modulus(double E, double nu) { return E / (2.0 * (1.0 + nu)); }

double rayleigh_time(double radius, double E, double nu, double density) {
  assert(radius > 0 && E > 0 && density > 0);
  // Li, Xu & Thornton (2005), Powder Technol. 160: T_R = π R sqrt(ρ/G) / (0.1631 ν + 0.8766).
  return std::numbers::pi * radius * std::sqrt(density / shear_modulus(E, nu)) / (0.1631 * nu + 0.8766);
}

TimestepChoice choose_timestep(const TimestepSettings& settings, const Material& material, double r_min) {
  TimestepChoice choice;
  choice.mode = settings.mode;
  choice.rayleigh_time = rayleigh_time(r_min, material.E, material.nu, material.density);
  choice.dt = settings.mode == TimestepMode::rayleigh ? settings.fraction * choice.rayleigh_time : settings.value;
  return choice;
}

std::vector<std::string> liggghts_limit_violations(const Material& material, const TimestepChoice& timestep) {
  std::vector<std::string> problems;
  const double ratio = timestep.fraction_of_rayleigh();
  if (ratio > k_max_rayleigh_fraction) {
    problems.push_back(fmt::format(
        "time step {:.4g} s is {:.3f} Rayleigh times (T_R = {:.4g} s for the smallest radius at E = {:.4g} Pa, "
        "nu = {:.4g}, density = {:.4g} kg/m^3); above {} T_R Hertz contacts are not resolved and the run blows "
        "up: lower [timestep] value or use mode = \"rayleigh\"",
        timestep.dt, ratio, timestep.rayleigh_time, material.E, material.nu, material.density,
        k_max_rayleigh_fraction));
  }
  if (material.E < k_liggghts_min_E && !material.soft_particles) {
    problems.push_back(
        fmt::format("Young's modulus E = {:.4g} Pa is below {:.0e} Pa, which LIGGGHTS refuses in SI units: set "
                    "[material] soft_particles = true to allow it",
                    material.E, k_liggghts_min_E));
  }
  if (material.E > k_liggghts_max_E && !material.hard_particles) {
    problems.push_back(
        fmt::format("Young's modulus E = {:.4g} Pa is above {:.0e} Pa, which LIGGGHTS refuses in SI units: set "
                    "[material] hard_particles = true to allow it",
                    material.E, k_liggghts_max_E));
  }
  return problems;
}

void check_run_count(long runs, long steps_per_run, std::string_view what) {
  if (runs > k_max_runs_per_case)
    throw util::UserError(fmt::format(
        "{} gives {} LIGGGHTS runs of {} step{} in one case, more than {}: each run costs its setup (neighbour lists, "
        "fixes, a dump frame) beyond its steps; lengthen the interval",
        what, runs, steps_per_run, steps_per_run == 1 ? "" : "s", k_max_runs_per_case));
}

long steps_for(double duration, double dt, std::string_view what) {
  const double steps = std::round(duration / dt);
  // Checked before the rounding to an integer, which is undefined beyond a long's range (and for a time step that
  // underflowed to 0: the quotient is infinite or NaN).
  if (!(steps <= study::k_max_steps))
    throw util::UserError(
        fmt::format("{} = {:.4g} s is {:.3g} steps of dt = {:.4g} s, more than {:.0e} (LIGGGHTS reads "
                    "step counts through variables printed with 15 significant digits; even a "
                    "single particle runs about 1e6 steps a second): shorten it or make the time "
                    "step longer",
                    what, duration, steps, dt, study::k_max_steps));
  return std::max(1L, static_cast<long>(steps));
}

namespace {
constexpr std::string_view k_cdt_words = "rolling_friction cdt";
constexpr std::string_view k_cdt_property =
    "fix m5 all property/global coefficientRollingFriction peratomtypepair 2 ${mu_r_pp} ${mu_r_pw} ${mu_r_pw} "
    "${mu_r_pw}\n";
}  // namespace

std::string rolling_model_words(const ContactSettings& contact) {
  return fmt::format("rolling_friction {}", rolling_model_name(contact.rolling_model));
}

std::string rolling_property_lines(const ContactSettings& contact) {
  switch (contact.rolling_model) {
    case RollingModel::cdt:
    case RollingModel::epsd2:
      return std::string(k_cdt_property);
    case RollingModel::epsd:
      return std::string(k_cdt_property) +
             "fix m6 all property/global coefficientRollingViscousDamping peratomtypepair 2 ${rolling_damping} "
             "${rolling_damping} ${rolling_damping} ${rolling_damping}\n";
    case RollingModel::epsd3:
      return std::string(k_cdt_property) +
             "fix m6 all property/global coefficientRollingViscousDamping peratomtypepair 2 ${rolling_damping} "
             "${rolling_damping} ${rolling_damping} ${rolling_damping}\n"
             "fix m7 all property/global rollingStiffness scalar ${rolling_stiffness}\n";
    case RollingModel::viscous:
      return "# rolling_friction viscous: mu_R in s*m (liggghts/rolling_model_viscous.h)\n"
             "fix m5 all property/global coefficientRollingViscosity peratomtypepair 2 ${mu_r_pp} ${mu_r_pw} "
             "${mu_r_pw} ${mu_r_pw}\n";
  }
  assert(false && "rolling model without property lines");
  return {};
}

std::string with_rolling_model(std::string text, const ContactSettings& contact) {
  if (contact.rolling_model == RollingModel::cdt) return text;
  const auto replace_all = [&text](std::string_view from, const std::string& to) {
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
      text.replace(at, from.size(), to);
  };
  replace_all(k_cdt_property, rolling_property_lines(contact));
  replace_all(k_cdt_words, rolling_model_words(contact));
  return text;
}

double liggghts_rolling_coefficient(const ContactSettings& contact, double value) {
  // Divided rather than multiplied by 1e-6 (which is not a double): 5 mm·ms is written as 5e-06 s·m.
  if (contact.rolling_model != RollingModel::viscous || contact.viscous_unit == ViscousUnit::s_m) return value;
  return value / 1e6;  // mm·ms -> s·m
}

std::optional<std::filesystem::path> liggghts_library_dir(const std::string& executable) {
  namespace fs = std::filesystem;
  const fs::path exe(executable);
  if (!exe.is_absolute() || exe.parent_path().filename() != "bin") return std::nullopt;
  const fs::path prefix = exe.parent_path().parent_path();
  std::error_code ec;
  if (!fs::exists(prefix / "demsa-liggghts.txt", ec) || !fs::exists(prefix / "lib" / "libliggghts.so.3", ec))
    return std::nullopt;
  return prefix / "lib";
}

}  // namespace demsa::experiments
