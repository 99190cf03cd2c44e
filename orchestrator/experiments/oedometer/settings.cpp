#include "orchestrator/experiments/oedometer/oedometer.hpp"

#include "orchestrator/study/setting_row.hpp"

#include <fmt/core.h>

#include <cmath>

// The [oedometer] section of the study file: its rows, the rules between them, and its prose in
// docs/reference/study-file.md.
namespace demsa::experiments::oedometer {

using namespace demsa::study;

namespace {

void apply_preset(OedometerSettings& oedometer, const std::string& preset) {
  // Paper §4: assembly one has 4642 particles and the void ratio 0.66, with the pore volume computed on a
  // 10 x 10 x 5 cm^3 sample: V_P = 500 cm^3 - V_S. (The paper's formula reads e_1 = V_S / V_P, but a solid
  // fraction of 1/1.66 = 0.60 is a sphere packing under load and 0.40 is not, so e = V_P / V_S as usual.) The
  // paper gives no radii; these give that solid volume in expectation:
  //   V_S = 500 cm^3 / (1 + 0.66) = 301.2 cm^3, so E[r^3] = V_S / (4642 * 4/3 pi) = 15.49 mm^3.
  // Radii are N(mu, sd) truncated to [a, b] = [2.0, 3.0] mm with sd = 0.25 mm, i.e. density proportional to
  // phi((r - mu)/sd) on [a, b]; E[r^3] = int_a^b r^3 phi dr / int_a^b phi dr (trapezoid rule, 2e5 intervals).
  // mu = 2.466 mm gives E[r] = 2.4737 mm and E[r^3] = 15.496 mm^3: V_S = 301.30 cm^3 and e = 500 / 301.30 - 1 =
  // 0.6595 (mu = 2.47 mm would give 0.653). The former radii, 2.5 to 3.5 mm around 3 mm (E[r^3] = 27.4 mm^3),
  // put V_S = 533 cm^3 above the 500 cm^3 of the sample.
  oedometer.preset = preset;
  oedometer.particles = 4642;
  oedometer.radii = k_paper_radii;
}

const SettingBounds k_gain_bounds = between(0, true, 1e12, true);

#define OED(member) \
  [](auto& c) -> auto& { return settings(c).member; }

}  // namespace

const OedometerSettings& settings(const StudyConfig& config) {
  return config.experiment_settings.get<OedometerSettings>();
}
OedometerSettings& settings(StudyConfig& config) { return config.experiment_settings.get<OedometerSettings>(); }

std::vector<Setting> oedometer_settings() {
  std::vector<Row> rows;
  const auto add = [&](Row& row) { rows.push_back(std::move(row)); };
  add(preset("oedometer", OED(preset), {"paper"},
             [](StudyConfig& c, const std::string& name) { apply_preset(settings(c), name); })
          .doc("`paper`: assembly one of §4: 4642 particles, radii [2.0, 3.0] mm, mean 2.466, sd 0.25, whose "
               "expected solid volume V_S = 301 cm³ gives the paper's void ratio e = V_P/V_S = 0.66 on a 10 × 10 × "
               "5 cm³ sample (the paper gives no radii). Other keys override it"));
  add(Row("oedometer", "particles")
          .integer(OED(particles),
                   between(1, true, k_max_particles, true,
                           "the case writer holds every particle, and the text of its data file, in memory"))
          .cases("oed.particles")
          .doc("number of particles"));
  radius_rows(rows, "oedometer", "oed.", OED(radii));
  add(Row("oedometer", "box_side")
          .number(OED(box_side), between(0, false, 10, true))
          .unit("m")
          .cases("oed.box_side")
          .doc("side of the square box; at least 2.2 `r_max` (a lattice cell of 2 `r_max` and its gaps)"));
  add(Row("oedometer", "box_height")
          .number(OED(box_height), between(0, false, 100, true))
          .unit("m")
          .cases("oed.box_height")
          .doc("box height; a case whose settled packing top plus `plate_gap` lies above it stops after the fill "
               "with an error naming this key (both plate modes)"));
  add(Row("oedometer", "fill_time")
          .number(OED(fill_time), between(0, false, k_max_duration, true))
          .unit("s")
          .cases("oed.fill_time")
          .doc("pouring and settling before loading"));
  add(Row("oedometer", "loads")
          .numbers(OED(loads), between(0, false, 1e9, true))
          .check([](const SettingValue& v) {
            const auto& loads = std::get<std::vector<double>>(v);
            if (loads.empty()) throw SettingError("needs at least one load");
            for (std::size_t i = 0; i < loads.size(); ++i) {
              if (!(loads[i] > 0))
                throw SettingError(fmt::format("load {} is {} N; loads must be > 0", i + 1, loads[i]));
              if (i > 0 && !(loads[i] > loads[i - 1]))
                throw SettingError(fmt::format("loads must increase: {} N follows {} N", loads[i], loads[i - 1]));
            }
          })
          .range("at least one, in (0, 1e+09], increasing")
          .unit("N")
          .cases("oed.load")
          .doc("the loads L_n"));
  add(Row("oedometer", "measured_settlements")
          .numbers(OED(measured_settlements), between(-100, true, 100, true))
          .range("none, or one per load after the first, each in [-100, 100]")
          .unit("m")
          .measurement("oed.measured_settlement")
          .doc("s̃_i for loads 2..n relative to load 1: a finished case stores its error E_0 against them"));
  add(Row("oedometer", "plate_mode")
          .choice(OED(plate_mode),
                  std::vector<std::pair<std::string, PlateMode>>{{"servo", PlateMode::servo},
                                                                 {"trial-step", PlateMode::trial_step}})
          .cases("oed.mode")
          .doc("`servo` (`fix mesh/surface/stress/servo`) or `trial-step` (the paper's algorithm)"));
  add(Row("oedometer", "plate_gap")
          .number(OED(plate_gap), between(0, true, 100, true))
          .unit("m")
          .cases("oed.plate_gap")
          .doc("the plate starts this far above the settled packing"));
  add(Row("oedometer", "load_tolerance")
          .number(OED(load_tolerance), between(0, false, 1e9, true))
          .unit("N")
          .cases("oed.tol")
          .doc("\\|F − L\\| that counts as reached (paper R_pr)"));
  add(Row("oedometer", "servo_vel_max")
          .number(OED(servo_vel_max), between(0, false, 1e3, true))
          .unit("m/s")
          .cases("oed.vmax")
          .doc("servo speed limit; must be below skin/(2 dt)"));
  add(Row("oedometer", "servo_kp").number(OED(servo_kp), k_gain_bounds).cases("oed.kp").doc("servo proportional gain"));
  add(Row("oedometer", "servo_ki").number(OED(servo_ki), k_gain_bounds).cases("oed.ki").doc("servo integral gain"));
  add(Row("oedometer", "servo_kd").number(OED(servo_kd), k_gain_bounds).cases("oed.kd").doc("servo derivative gain"));
  add(Row("oedometer", "servo_max_steps")
          .integer(OED(servo_max_steps), step_bounds())
          .unit("steps")
          .cases("oed.smax")
          .doc("servo: a load not reached by then is recorded as not converged"));
  add(Row("oedometer", "servo_check_steps")
          .integer(OED(servo_check_steps), step_bounds())
          .unit("steps")
          .cases("oed.scheck")
          .doc("servo: force averaged and the load checked every this many steps (rounded up to a multiple of 10)"));
  add(Row("oedometer", "rest_velocity")
          .number(OED(rest_velocity), between(0, false, 1e3, true))
          .unit("m/s")
          .cases("oed.vrest")
          .doc("servo: the plate is at rest when its mean speed over a check is below this"));
  add(Row("oedometer", "trial_steps")
          .integer(OED(trial_steps), step_bounds())
          .unit("steps")
          .cases("oed.ns")
          .doc("trial-step: n_s"));
  add(Row("oedometer", "relax_steps")
          .integer(OED(relax_steps), step_bounds())
          .unit("steps")
          .cases("oed.nl")
          .doc("trial-step: n_L"));
  add(Row("oedometer", "trial_reduction")
          .number(OED(trial_reduction), between(0, false, 1, false))
          .cases("oed.mt")
          .doc("trial-step: m_T"));
  add(Row("oedometer", "trial_step0")
          .number(OED(trial_step0), between(0, false, 1, true))
          .unit("m")
          .cases("oed.d0")
          .doc("trial-step: δ_T0 (the paper's 0.0075 mm)"));
  add(Row("oedometer", "trial_floor")
          .number(OED(trial_floor), between(0, false, 1, true))
          .cases("oed.floor")
          .doc("trial-step: smallest trial step as a fraction of δ_T0"));
  add(Row("oedometer", "max_trials")
          .integer(OED(max_trials), between(1, true, 1e6, true))
          .cases("oed.maxtrials")
          .doc("trial-step: trials per load before it is recorded as not converged"));

  return finish_rows(rows);
}

#undef OED

std::vector<SettingSection> oedometer_sections() {
  return {{"oedometer", "Defaults: assembly one of the paper's §4 (`preset = \"paper\"`).", ""}};
}

void check_oedometer(const StudyConfig& config, const SectionCheck& at) {
  const OedometerSettings& o = settings(config);
  check_radii(o.radii, at);
  if (!o.measured_settlements.empty() && o.measured_settlements.size() + 1 != o.loads.size())
    at.fail("measured_settlements",
            fmt::format("has {} values; it needs one per load after the first ({} loads -> {} values)",
                        o.measured_settlements.size(), o.loads.size(), o.loads.size() - 1));
  // The lattice (build_assembly) has cells of 2 r_max with a gap of 0.1 r_max between them and the walls.
  const double gap = 0.1 * o.radii.r_max, cell = 2.0 * o.radii.r_max + gap;
  if (!(std::floor((o.box_side - gap) / cell) >= 1))
    at.fail("box_side",
            fmt::format("{} m is too small for particles of radius {} m: it must be at least 2.2 r_max = {:.4g} m",
                        o.box_side, o.radii.r_max, 2.2 * o.radii.r_max));
}

}  // namespace demsa::experiments::oedometer
