#include "orchestrator/experiments/oedometer/oedometer.hpp"

#include "orchestrator/experiments/geometry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/signals.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

// The oedometer's case (paper §4): its loose lattice packing and the files of its folder, for either plate.
namespace demsa::experiments::oedometer {

using namespace demsa::study;

namespace fs = std::filesystem;

OedometerAssembly build_assembly(const OedometerSettings& s, std::uint64_t seed) {
  OedometerAssembly a;
  const std::vector<double> radii = truncated_normal_radii(s.radii, s.particles, seed);
  // Cell gap: 10 % of r_max, so that neighbouring particles never touch before they are poured.
  const double gap = 0.1 * s.radii.r_max;
  const double cell = 2.0 * s.radii.r_max + gap;
  const int n = static_cast<int>(std::floor((s.box_side - gap) / cell));
  assert(n >= 1);
  // Up to (10 m / 2.1 um)^2 sites: more than an int holds, and more than any particle count (all in one layer then).
  a.per_layer = static_cast<int>(std::min<long long>(static_cast<long long>(n) * n, std::numeric_limits<int>::max()));
  const double offset = -s.box_side / 2.0 + (s.box_side - n * cell) / 2.0 + cell / 2.0;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));  // golden angle [rad]
  for (std::size_t i = 0; i < radii.size(); ++i) {
    if (i % 4096 == 0) util::throw_if_stop_raised();
    const int index = static_cast<int>(i);
    const int layer = index / a.per_layer, k = index % a.per_layer;
    const int ix = k / n, iy = k % n;
    const double r = radii[i];
    const double shift = s.radii.r_max - r;
    Particle p;
    p.radius = r;
    p.x = offset + ix * cell + shift * std::cos(golden * index);
    p.y = offset + iy * cell + shift * std::sin(golden * index);
    p.z = cell / 2.0 + layer * cell;
    a.top = std::max(a.top, p.z + r);
    a.solid_volume += 4.0 / 3.0 * std::numbers::pi * r * r * r;
    a.layers = layer + 1;
    a.particles.push_back(p);
  }
  return a;
}

namespace {

/// An oedometer case between its assembly and its files.
class OedometerDraft final : public CaseDraft {
 public:
  OedometerDraft(const StudyConfig& config, std::uint64_t seed)
      : m_config(config), m_assembly(build_assembly(settings(config), seed)) {}
  double smallest_radius() const override {
    double r_min = 0;
    for (const Particle& p : m_assembly.particles) r_min = r_min == 0 ? p.radius : std::min(r_min, p.radius);
    return r_min;
  }
  CaseWritten write(const Material& m, const TimestepChoice& ts, Params& params, const fs::path& dir) const override;

 private:
  const StudyConfig& m_config;
  OedometerAssembly m_assembly;
};

CaseWritten OedometerDraft::write(const Material& m, const TimestepChoice& ts, Params& params,
                                  const fs::path& dir) const {
  const StudyConfig& c = m_config;
  const OedometerSettings& s = settings(c);
  const OedometerAssembly& a = m_assembly;
  const long fill_steps = steps_for(s.fill_time, ts.dt, "[oedometer] fill_time");
  // Averaging windows sample every 10 steps, so a check interval is a multiple of 10.
  const long check_steps = std::max(10L, (s.servo_check_steps + 9) / 10 * 10);
  const long max_checks = (s.servo_max_steps + check_steps - 1) / check_steps;

  params.comment("oedometer (paper §4)");
  params.integer("particles", static_cast<long>(a.particles.size()), "particles");
  params.number("box_side", s.box_side, "box base side [m]");
  params.number("box_lo", -s.box_side / 2.0, "box walls at x, y = box_lo and box_hi [m]");
  params.number("box_hi", s.box_side / 2.0, "");
  params.number("box_height", s.box_height, "settled top + plate_gap above it stops the case [m]");
  params.number("solid_volume", a.solid_volume, "sum of particle volumes [m^3]");
  params.integer("fill_steps", fill_steps, "pouring and settling");
  params.number("plate_gap", s.plate_gap, "plate starts this far above the settled top [m]");
  params.integer("n_loads", static_cast<long>(s.loads.size()), "load steps");
  for (std::size_t i = 0; i < s.loads.size(); ++i) params.number(fmt::format("load_{}", i + 1), s.loads[i], "load [N]");
  params.number("load_tolerance", s.load_tolerance, "|F - L| that counts as reached [N]");
  params.comment("servo plate");
  params.number("servo_vel_max", s.servo_vel_max, "[m/s]");
  params.number("servo_kp", s.servo_kp, "proportional gain");
  params.number("servo_ki", s.servo_ki, "integral gain");
  params.number("servo_kd", s.servo_kd, "derivative gain");
  params.integer("servo_check_steps", check_steps, "load checked every this many steps");
  params.integer("servo_check_samples", check_steps / 10, "force samples per check (every 10 steps)");
  params.integer("servo_max_checks", max_checks, "checks before a load is given up");
  params.number("rest_velocity", s.rest_velocity, "plate at rest below this mean speed [m/s]");
  params.integer("history_steps", 100, "plate_history.txt every this many steps");

  const double half = s.box_side / 2.0 * 1.02;
  const double zhi = std::max(s.box_height, a.top) + 0.02;
  std::string data =
      data_header("demsa oedometer: loose lattice", static_cast<int>(a.particles.size()), half, -0.001, zhi);
  int id = 0;
  for (const Particle& p : a.particles) data += atom_line(++id, p, m.density);
  write_text(dir / "oedometer_particles.data", data);
  write_text(dir / k_plate_stl, to_ascii_stl(plate_mesh(s.box_side), "plate"));
  const bool trial = s.plate_mode == PlateMode::trial_step;
  write_text(dir / k_case_input,
             with_rolling_model(template_text(trial ? "oedometer_trial.liggghts" : "oedometer.liggghts"), c.contact));
  for (const char* include :
       {"oedometer_box.liggghts", "oedometer_fill.liggghts", "oedometer_plate.liggghts", "oedometer_restore.liggghts"})
    write_text(dir / include, with_rolling_model(template_text(include), c.contact));

  CaseWritten w;
  w.particles = static_cast<long>(a.particles.size());
  std::vector<double> radii;
  double sum = 0;
  for (const Particle& p : a.particles) {
    radii.push_back(p.radius);
    sum += p.radius;
  }
  w.assembly = {{"particles", a.particles.size()},
                {"per_layer", a.per_layer},
                {"layers", a.layers},
                {"lattice_top_m", a.top},
                {"solid_volume_m3", a.solid_volume},
                {"radius_min_m", smallest_radius()},
                {"radius_max_m", *std::max_element(radii.begin(), radii.end())},
                {"radius_mean_m", sum / static_cast<double>(radii.size())},
                {"void_ratio", "measured after settling: first comment of plate_states.txt"}};
  w.experiment = {{"plate_mode", trial ? "trial-step" : "servo"},
                  {"loads_N", s.loads},
                  {"load_tolerance_N", s.load_tolerance},
                  {"fill_steps", fill_steps},
                  {"box_side_m", s.box_side},
                  {"box_height_m", s.box_height}};
  if (trial) {
    w.experiment["trial_step"] = {{"trial_steps", s.trial_steps},         {"relax_steps", s.relax_steps},
                                  {"trial_reduction", s.trial_reduction}, {"trial_step0_m", s.trial_step0},
                                  {"trial_floor", s.trial_floor},         {"max_trials", s.max_trials}};
  } else {
    w.experiment["servo"] = {{"vel_max_m_s", s.servo_vel_max},
                             {"kp", s.servo_kp},
                             {"ki", s.servo_ki},
                             {"kd", s.servo_kd},
                             {"check_steps", check_steps},
                             {"max_steps", s.servo_max_steps},
                             {"rest_velocity_m_s", s.rest_velocity}};
  }
  // How the finished case is measured (oedometer.cpp), so that `demsa measure CASE` measures it the same way: only
  // when given, so that a case without them reads as before.
  if (!s.measured_settlements.empty()) w.experiment["measured_settlements_m"] = s.measured_settlements;
  return w;
}

}  // namespace

std::unique_ptr<CaseDraft> draft_case(const StudyConfig& config, std::uint64_t assembly_seed) {
  return std::make_unique<OedometerDraft>(config, assembly_seed);
}

std::vector<std::string> limit_violations(const StudyConfig& config, const Material&, const TimestepChoice& timestep) {
  std::vector<std::string> problems;
  const OedometerSettings& s = settings(config);
  if (s.plate_mode == PlateMode::servo) {
    const double limit = config.timestep.skin / (2.0 * timestep.dt);
    if (s.servo_vel_max >= limit) {
      problems.push_back(fmt::format(
          "[oedometer] servo_vel_max = {:.4g} m/s reaches skin/(2 dt) = {:.4g} m/s (skin {:.4g} m, dt {:.4g} s): "
          "a mesh moving more than half the neighbor skin per step misses contacts; lower servo_vel_max or raise "
          "[timestep] skin",
          s.servo_vel_max, limit, config.timestep.skin, timestep.dt));
    }
  }
  return problems;
}

std::string driver_command(const StudyConfig& config) {
  return settings(config).plate_mode == PlateMode::trial_step ? k_driver_command : "";
}

}  // namespace demsa::experiments::oedometer
