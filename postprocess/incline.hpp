#pragma once
// The tilting-plate (incline) test of the wall material: probe spheres resting on a flat plate, the plate tilting at a
// constant rate Ω (in the plate's frame: gravity turning, g = |g| (sin θ, 0, −cos θ), θ = Ω t, down-slope = +x).
// Rolling probes are free spheres; sliding probes have their rotation locked (the DEM twin of a sled of glued
// particles), so they can only slide. A probe's onset is the tilt at which it has moved a set distance down-slope.
//
// The tilt at which a probe has moved x lags the threshold angle θ_c at which it starts, because it starts from rest
// under an excess force that grows with the tilt. With μ = tan θ_c, the down-slope acceleration is
//   a = k g (sin θ − μ cos θ) = k g √(1 + μ²) sin(θ − θ_c) ≈ k g √(1 + μ²) Ω t   (t from the onset),
// so x = k g √(1 + μ²) Ω t³ / 6: a sliding block (k = 1, Coulomb friction μ_PW) or a sphere rolling against a constant
// rolling torque μ_r |F_n| R (k = 5/7: the sphere's translational and rotational inertia, I = 2/5 m R²; LIGGGHTS's
// `cdt`, Ai et al. 2011 model A). The measured onset is corrected by Ω t, t solved with θ_c by fixed-point iteration.
// With the viscous rolling model (model B) a sphere rolls at any tilt; its down-slope speed at a set tilt measures
// the rolling viscosity instead.
#include "postprocess/dump.hpp"

#include <filesystem>
#include <optional>
#include <vector>

namespace demsa::postprocess {

struct InclineOptions {
  double tilt_rate = 5.0;        ///< Ω [deg/s], > 0
  long tilt_start_step = 0;      ///< the time step at which the tilt is 0 (the end of the settling)
  double dt = 0.0;               ///< the time step [s], > 0
  double gravity = 9.81;         ///< |g| [m/s²], > 0
  double onset_distance = 2e-3;  ///< down-slope displacement that marks a probe's onset [m], > 0
  double speed_angle = 5.0;      ///< the tilt at which the rolling probes' speed is read [deg]
  long rolling_probes = 0;       ///< atoms 1..rolling_probes roll; the others (sliding probes) cannot; >= 0
  /// The tilt the schedule stops at [deg], in (0, 90]: a probe that moves its onset_distance only after it (between
  /// the last records) has no onset, and a frame beyond 90° is not of this schedule.
  double max_tilt = 90.0;
  void validate() const;  ///< throws std::invalid_argument naming the field
};

/// One probe.
struct InclineProbe {
  long id = 0;
  bool rolling = false;
  std::optional<double> onset_raw;   ///< tilt at which it had moved onset_distance [deg] (linear between frames)
  std::optional<double> onset;       ///< onset_raw less the lag of the start from rest [deg]
  std::optional<double> speed;       ///< down-slope speed at speed_angle [m/s] (rolling probes; linear between frames)
  std::vector<double> tilt;          ///< its frames: tilt [deg]
  std::vector<double> displacement;  ///< ... and down-slope displacement since the first frame [m]
};

struct InclineResult {
  std::vector<InclineProbe> probes;  ///< by id
  /// Medians over the probes that have a value; none when fewer than half of the probes of the kind have one.
  std::optional<double> roll_angle, slide_angle, roll_speed;
  int rolled = 0, slid = 0, with_speed = 0;  ///< probes of each kind with a value
  int rolling_probes = 0, sliding_probes = 0;
  double last_tilt = 0.0;  ///< tilt of the last frame [deg]
};

/// The tilt angle θ_c at which a probe started, from the tilt `measured` [deg] at which it had moved `distance`,
/// for the acceleration factor k (5/7 rolling, 1 sliding); see the header comment.
double incline_onset(double measured, double distance, double k, double tilt_rate, double gravity);

/// Reads every frame of the probes' dump (columns id, x and, for the speed, vx; the timestep gives the tilt) and
/// measures each probe. A probe removed from the dump (it left the test) keeps what its frames showed. Throws
/// ParseError on a malformed dump (an id on two rows of a frame included), InputError on a frame whose tilt exceeds
/// 90° (the dump does not follow the options' schedule), and std::invalid_argument on invalid options.
InclineResult measure_incline(const std::filesystem::path& dump, const InclineOptions& options);

}  // namespace demsa::postprocess
