#pragma once
// Physics of a case that demsa decides before LIGGGHTS runs, shared by every experiment (docs/reference/study-file.md;
// paper §2): the Rayleigh time and the time step, the contact model's LIGGGHTS words, and the limits LIGGGHTS 3.8.0
// enforces or silently needs.
#include "orchestrator/study/config.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::experiments {

/// G = E / (2 (1 + ν)) [Pa].
double shear_modulus(double E, double nu);

/// Rayleigh time of a sphere of radius r [m]: T_R = π r sqrt(ρ/G) / (0.1631 ν + 0.8766) [s]
/// (Li, Xu, Thornton 2005; the usual DEM critical time for Hertz contacts).
double rayleigh_time(double radius, double E, double nu, double density);

/// The time step of one sample.
struct TimestepChoice {
  double dt = 0.0;             ///< [s]
  double rayleigh_time = 0.0;  ///< T_R of the smallest particle [s]
  study::TimestepMode mode = study::TimestepMode::rayleigh;
  double fraction_of_rayleigh() const { return dt / rayleigh_time; }
};

/// dt = fraction × T_R(r_min) (mode rayleigh) or the fixed value; T_R is always computed for the checks.
TimestepChoice choose_timestep(const study::TimestepSettings& settings, const study::Material& material, double r_min);

/// The largest dt / T_R that demsa accepts: above it Hertz contacts between the smallest particles are resolved
/// in fewer than about ten steps and energy blows up.
inline constexpr double k_max_rayleigh_fraction = 0.3;

/// Every LIGGGHTS limit the sample breaks whatever its experiment, each as one sentence that says which limit and
/// why; empty when the case is runnable. Checks: dt ≤ 0.3 T_R; the Young's modulus range without the matching flag.
/// An experiment adds its own (Experiment::limit_violations).
std::vector<std::string> liggghts_limit_violations(const study::Material& material, const TimestepChoice& timestep);

/// The contact model's words after `model hertz tangential history` in `pair_style gran` and every `fix wall/gran`:
/// "rolling_friction cdt", ..., "rolling_friction viscous".
std::string rolling_model_words(const study::ContactSettings& contact);

/// The `fix property/global` lines of the rolling model's coefficients (docs/reference/study-file.md, [contact]): the
/// per type-pair coefficient from ${mu_r_pp} and ${mu_r_pw} (coefficientRollingFriction, or coefficientRollingViscosity
/// for `viscous`), plus ${rolling_damping} for epsd/epsd3 and ${rolling_stiffness} for epsd3.
std::string rolling_property_lines(const study::ContactSettings& contact);

/// A LIGGGHTS template with the study's rolling model: every "rolling_friction cdt" and the coefficientRollingFriction
/// line of the templates (written for `cdt`) replaced. The text is returned unchanged for `cdt`.
std::string with_rolling_model(std::string text, const study::ContactSettings& contact);

/// The value of a rolling coefficient (mu_r_pp, mu_r_pw) that LIGGGHTS reads: μ_R converted to s·m for `viscous`
/// given in mm·ms, the value itself otherwise.
double liggghts_rolling_coefficient(const study::ContactSettings& contact, double value);

/// The library folder of a LIGGGHTS built by scripts/build-liggghts.sh (`<prefix>/lib` holding libliggghts.so.3,
/// the soname `demsa drive-oedometer` loads) for its executable `<prefix>/bin/liggghts`; nullopt for any other
/// executable. A trial-step oedometer, driven in-process by demsa, loads that library (LD_LIBRARY_PATH in run.sh) for
/// the `viscous` model.
std::optional<std::filesystem::path> liggghts_library_dir(const std::string& executable);

/// Number of steps of `duration` seconds at time step dt (at least 1). Throws util::UserError naming `what` (the
/// duration's setting, "[pile] settle_time") when they are more than study::k_max_steps.
long steps_for(double duration, double dt, std::string_view what);

/// The most LIGGGHTS `run` commands one case's schedule may hold (records, settling checks, windows). Each run costs
/// its setup (neighbour lists rebuilt, fixes initialised, often a dump frame) beyond its steps, which the bill's
/// atom-steps do not count: a million one-step runs cost far more than a million steps.
inline constexpr long k_max_runs_per_case = 100000;
/// Throws util::UserError naming `what` (the interval's setting, "[incline] record_angle") when `runs` exceeds
/// k_max_runs_per_case.
void check_run_count(long runs, long steps_per_run, std::string_view what);

}  // namespace demsa::experiments
