// The oedometer's schedule in atom-steps (Experiment::case_cost): every atom for the pour (fill_steps), then, for each
// load, the servo plate's checks up to servo_max_steps (liggghts_templates/oedometer.liggghts), or the trial-step
// plate's trials up to max_trials, each of n_s trial steps and at most n_L relaxation steps (driver.cpp, paper §4).
// Both plates stop a load once it is reached: the cap is the estimate's bound.
//
// The servo plate's expected cost (docs/how-to/cost.md, "The servo oedometer's model"): a load ends when the plate
// force is within load_tolerance and the packing's creep under it has slowed below the plate's rest speed. Its
// simulated time follows E much less than its step count does (steps = time / dt, and dt ~ E^-1/2): over the 31
// finished cases of the calibration example and its noise study (2026-12-04: 1000 particles, loads 100/400/1100 N,
// tolerance 1 N, rest 1e-4 m/s, vel_max 0.05 m/s, kp 0.5), the logarithm of a load's simulated time correlates with
// log E by 0.24, 0.13 and -0.61 (loads 1-3), that of its step count by 0.67, 0.68 and -0.29; a load took 0.4-8.4 s.
// A load's steps are T / dt, at most the cap, with T = 1.61 s fitted on the noise study alone (4 points x 3 packings,
// 36 loads): their steps over their 1 / dt, the ratio estimator of a study's total, which the bill is (their plain
// mean time is 1.82 s: the long loads are those of soft cases, with a longer dt). Stricter criteria and other gains
// are not measured and keep the cap.
//
// The trial-step plate's expected cost (docs/how-to/cost.md, "The trial-step oedometer"): the plate moves
// δ_T0 a trial of n_s steps until the force passes the load (paper §4), so a load's approach is its plate travel over
// δ_T0 trials; its closing is a few relaxations of n_L steps until the relaxed force lies within R_pr.
// The travel to each later load is the bed's, measured by the servo plate on 9 quickstart-size cases (1000 particles
// of mean radius 3.0 mm, E 1e7-1e8 Pa: 1.50 and 1.92 mm to the second and third loads) and 4 paper-size cases (4642 of
// 2.47 mm, E 1e8-1e9 Pa: 0.88, 0.88 and 0.98 mm), 2026-12-05: 0.29 and 0.18 mean particle diameters, geometric mean
// 0.23.
// The travel to the first load is the fill's compaction, which no case.json knows before its run: the plate starts
// plate_gap above the highest particle, a loose fill's top collapses under the first load to a void ratio of about
// e_c whatever E (40 quickstart-size servo cases with fills of void ratio 1.48-2.05 stopped at 1.04-1.44, mean 1.16),
// and a dense fill still compacts by about de_d. With the settled packing a probe read (void ratio e of the fill,
// solid volume V_S, box area A):
//   travel = plate_gap + (V_S / A) max(e - e_c, de_d),
// e_c = 1.107, the mean of the two quickstart-size trial-step cases it was fitted on (E 3.16e7 and 1e8 Pa, fills of
// 1.73 and 1.65, 7.96 and 6.58 mm: 1.088 and 1.126; a third, held out, 1.751 and 8.40 mm, gives 1.069), and
// de_d = 0.12, the median of the six paper-size first loads measured (fills of 0.98-1.02): 0.105, 0.127, 0.129 and
// 0.127 under the servo plate, 0.029 and at least 0.111 (stopped before its load) under the trial-step plate. The
// same fill compacted by 0.029 in one case and by 0.105-0.129 in the five others: one case's first load is billed
// within a factor of about three, a study's total by the median. A held-out paper-size case (sample 3 of
// paper-oedometer.toml, fill 0.992) compacted by 0.164 (5.45 mm) and closed in 26 relaxations: billed 0.68 of its
// steps; the seven first loads' total travel is billed within 1.05. Without a probe, the first travel is 1.0 mean
// diameter, the geometric mean of the servo's (1.12 quickstart size, 0.84 paper size).
// The closing, on those three cases: 5, 19 and 5 relaxations at the first load (mean 9.7), 28, 23 and 38 (the last
// stopped before converging, a floor) at the later ones (mean 29.7). A relaxed force must land within ±R_pr while the
// bed creeps by 0.1-4 N a relaxation, so their count is a lottery.
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/oedometer/oedometer.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/oedometer.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

namespace demsa::experiments::oedometer {

namespace {

/// The simulated time of a servo load [s] (this file's header): the 36 loads of the calibration example's noise
/// study, 4 points x 3 packings over its ranges: 3.36e6 steps over 2.09e6 s^-1 of their 1 / dt.
constexpr double k_servo_seconds_per_load = 1.61;
/// The criterion and the gains those loads were measured with.
constexpr double k_measured_tolerance_n = 1.0;
constexpr double k_measured_rest_velocity = 1e-4;
constexpr double k_measured_free_speed = 0.025;  // vel_max x kp [m/s]
/// Bühlmann's credibility k of the model (exec/cost.hpp): one case's actual / expected has a variance of 0.33-0.42
/// (the example's 19 cases, the noise study's 12), and the model's error from study to study is taken as a standard
/// deviation of 0.2 (variance 0.04): wider than the 0.93-1.07 of its two hold-out checks, for the packings, sizes and
/// machines not measured. 0.37 / 0.04 ~ 10: the first finished cases move the bill a little, ten of them halfway.
constexpr double k_model_weight_cases = 10.0;
/// Atom-steps per CPU-second of those 12 cases (3.57e9 in 557.5 CPU-s, wait4's rusage) over the standard run's of the
/// same LIGGGHTS on the same machine (8.68e6, 8.64e6-9.00e6 measured again three times the same day).
constexpr double k_rate_factor = 0.738;

/// The trial-step plate's travel to its first load without a probe and to each later one, in mean particle diameters,
/// and its relaxations at the first and at each later load (this file's header).
constexpr double k_trial_first_travel_diameters = 1.0;
constexpr double k_trial_later_travel_diameters = 0.23;
constexpr double k_trial_first_closing_relaxations = 9.7;
constexpr double k_trial_later_closing_relaxations = 29.7;
/// With the settled packing of a probe: the void ratio a loose fill collapses to under the first load, and the
/// compaction of a dense fill's void ratio (this file's header).
constexpr double k_trial_collapsed_void_ratio = 1.107;
constexpr double k_trial_dense_compaction = 0.12;
/// The trial-step case's atom-steps per CPU-second over the standard run's: 2.05e10 atom-steps in 3328 CPU-s (6.16e6,
/// its process's CPU time, beside other runs as the servo's 0.738 was measured) against 8.68e6.
constexpr double k_trial_rate_factor = 0.71;

/// Whether the servo's criterion and gains are those the model was measured with, or laxer (a larger tolerance or
/// rest speed ends a load sooner): a stricter criterion creeps for longer (a tolerance of 0.03 N and a rest speed of
/// 1e-3 m/s took 3.07 s a load in 20 cases, 7 of them to their cap).
bool servo_model_holds(const nlohmann::json& case_json, const std::filesystem::path& file) {
  const std::optional<double> tolerance = case_number(case_json, file, "oedometer.load_tolerance_N", 0.0, 1e12);
  const std::optional<double> rest = case_number(case_json, file, "oedometer.servo.rest_velocity_m_s", 0.0, 1e12);
  const std::optional<double> vel_max = case_number(case_json, file, "oedometer.servo.vel_max_m_s", 0.0, 1e12);
  const std::optional<double> kp = case_number(case_json, file, "oedometer.servo.kp", 0.0, 1e12);
  const std::optional<double> ki = case_number(case_json, file, "oedometer.servo.ki", 0.0, 1e12);
  const std::optional<double> kd = case_number(case_json, file, "oedometer.servo.kd", 0.0, 1e12);
  if (!tolerance || !rest || !vel_max || !kp) return false;
  if (ki.value_or(0.0) != 0.0 || kd.value_or(0.0) != 0.0) return false;
  return *tolerance >= k_measured_tolerance_n && *rest >= k_measured_rest_velocity &&
         std::abs(*vel_max * *kp - k_measured_free_speed) <= 1e-9;
}

struct FirstTravel {
  double metres = 0.0;
  double void_ratio = 0.0;  ///< the fill's
};

/// The trial-step plate's travel to the first load from the settled packing a probe read (this file's header); none
/// without one, or when case.json lacks the solid volume or the box.
std::optional<FirstTravel> first_travel_of_fill(const nlohmann::json& case_json, const std::filesystem::path& file,
                                                const nlohmann::json& probed) {
  if (!probed.is_object()) return std::nullopt;
  const auto number = [&](const char* key) -> std::optional<double> {
    const auto it = probed.find(key);
    if (it == probed.end() || !it->is_number()) return std::nullopt;
    const double v = it->get<double>();
    return std::isfinite(v) && v >= 0.0 ? std::optional<double>(v) : std::nullopt;
  };
  const std::optional<double> void_ratio = number("void_ratio");
  const std::optional<double> gap = number("plate_gap_m");
  const std::optional<double> solid = case_number(case_json, file, "assembly.solid_volume_m3", 0.0, 1e6);
  const std::optional<double> side = case_number(case_json, file, "oedometer.box_side_m", 0.0, 1e3);
  if (!void_ratio || !gap || !solid || !side || !(*side > 0.0)) return std::nullopt;
  const double compaction = std::max(*void_ratio - k_trial_collapsed_void_ratio, k_trial_dense_compaction);
  return FirstTravel{*gap + *solid / (*side * *side) * compaction, *void_ratio};
}

}  // namespace

nlohmann::json probe_state(const std::filesystem::path& folder) {
  const std::filesystem::path states = folder / k_plate_states;
  if (!std::filesystem::is_regular_file(states)) return nullptr;
  const std::optional<postprocess::SettledPacking> p = postprocess::read_settled_packing(states);
  if (!p) return nullptr;
  return {{"particles", p->particles},
          {"top_z_m", p->top_z_m},
          {"void_ratio", p->void_ratio},
          {"plate_gap_m", p->plate_start_z_m - p->top_z_m}};
}

CaseCost case_cost(const study::StudyConfig&, const nlohmann::json& case_json, const std::filesystem::path& file,
                   const nlohmann::json& probed) {
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

  CaseCost cost;
  long per_load = 0;
  std::string plate;
  std::optional<double> expected_per_load;  // the plate's model's steps a load, when it applies
  if (trial) {
    const long trial_steps = integer("oedometer.trial_step.trial_steps");
    const long relax_steps = integer("oedometer.trial_step.relax_steps");
    const long max_trials = integer("oedometer.trial_step.max_trials");
    // Each trial runs n_s steps and, when the force overshoots, n_L more; a load not reached adds one step.
    per_load = max_trials * (trial_steps + relax_steps) + 1;
    plate = fmt::format("at most {} trials of {} + {} steps", max_trials, trial_steps, relax_steps);
    const std::optional<double> step0 = case_number(case_json, file, "oedometer.trial_step.trial_step0_m", 0.0, 1.0);
    const std::optional<double> radius = case_number(case_json, file, "assembly.radius_mean_m", 0.0, 1.0);
    if (step0 && *step0 > 0.0 && radius && *radius > 0.0) {
      const double diameter = 2.0 * *radius;
      const std::optional<FirstTravel> settled = first_travel_of_fill(case_json, file, probed);
      const double first_travel = settled ? settled->metres : k_trial_first_travel_diameters * diameter;
      // Each load's approach in trials of n_s steps, then its closing; the model's mean over the loads.
      const double travel = first_travel + static_cast<double>(loads - 1) * k_trial_later_travel_diameters * diameter;
      const double relaxations =
          k_trial_first_closing_relaxations + static_cast<double>(loads - 1) * k_trial_later_closing_relaxations;
      const double steps = travel / *step0 * static_cast<double>(trial_steps) +
                           relaxations * static_cast<double>(trial_steps + relax_steps);
      expected_per_load = std::min(static_cast<double>(per_load), steps / static_cast<double>(loads));
      const std::string first =
          settled
              ? fmt::format(
                    "{:.2f} mm to the first load (the probe's fill: void ratio {:.3g}, collapsing to {:.4g} or, "
                    "if denser, by {:.2g})",
                    settled->metres * 1e3, settled->void_ratio, k_trial_collapsed_void_ratio, k_trial_dense_compaction)
              : fmt::format(
                    "{:.2g} mean particle diameter{} to the first load (no probe read the fill: `--probe` does)",
                    k_trial_first_travel_diameters, k_trial_first_travel_diameters == 1.0 ? "" : "s");
      cost.expected = fmt::format(
          "the trial-step oedometer's model: the plate travels {} and {:.2g} mean diameters to each later one in "
          "trials of delta_T0, then {:.2g} relaxations at the first load and {:.3g} at each later one, measured on 13 "
          "servo cases of two sizes and four trial-step cases; docs/how-to/cost.md",
          first, k_trial_later_travel_diameters, k_trial_first_closing_relaxations, k_trial_later_closing_relaxations);
    }
    cost.rate_factor = k_trial_rate_factor;
    cost.rate_factor_source = fmt::format(
        "x {:.2f}, the trial-step oedometer's atom-steps per CPU-second over the standard run's (one quickstart-size "
        "case, 6.16e6 against 8.68e6, 2026-12-05; docs/how-to/cost.md)",
        k_trial_rate_factor);
  } else {
    const long check_steps = integer("oedometer.servo.check_steps");
    const long max_steps = integer("oedometer.servo.max_steps");
    if (check_steps <= 0) throw util::UserError(fmt::format("{}: oedometer.servo.check_steps is 0", file.string()));
    per_load = (max_steps + check_steps - 1) / check_steps * check_steps;
    plate = fmt::format("at most {} servo steps in checks of {}", per_load, check_steps);
    const std::optional<double> dt = case_number(case_json, file, "dt", 0.0, 1.0);
    if (dt && *dt > 0.0 && servo_model_holds(case_json, file)) {
      expected_per_load = std::min(static_cast<double>(per_load), k_servo_seconds_per_load / *dt);
      cost.expected = fmt::format(
          "the servo oedometer's model: {:.3g} s of simulated time a load over each case's dt, measured on 36 loads of "
          "12 quickstart-size cases with the same criterion; docs/how-to/cost.md",
          k_servo_seconds_per_load);
    }
    cost.rate_factor = k_rate_factor;
    cost.rate_factor_source = fmt::format(
        "x {:.3f}, the servo oedometer's atom-steps per CPU-second over the standard run's (12 quickstart-size cases, "
        "6.41e6 against 8.68e6, 2026-12-04; docs/how-to/cost.md)",
        k_rate_factor);
  }
  cost.steps = fill_steps + loads * per_load;
  cost.particles = particles;
  cost.atom_steps = static_cast<double>(cost.steps) * static_cast<double>(particles);
  cost.may_end_early = true;  // a load ends once it is reached
  cost.schedule = fmt::format("{} atoms: {} pouring steps, then {} load(s) of {} (the cap: a load ends once reached)",
                              particles, fill_steps, loads, plate);
  if (expected_per_load) {
    cost.expected_atom_steps = (static_cast<double>(fill_steps) + static_cast<double>(loads) * *expected_per_load) *
                               static_cast<double>(particles);
    cost.expected_weight = k_model_weight_cases;
  }
  return cost;
}

}  // namespace demsa::experiments::oedometer
