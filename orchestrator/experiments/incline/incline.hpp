#pragma once
// The incline (tilting plate) of the wall material: probe spheres of the material on a plate of the wall material
// that tilts slowly until they roll (free spheres: μ_R,PW) or slide (rotation-locked spheres, the DEM twin of a sled
// of glued particles: μ_PW). No two probes ever touch, so the particle-particle parameters play no part. Its settings
// ([incline]), case, measurement (postprocess/incline.hpp) and report.
#include "orchestrator/experiments/experiment.hpp"
#include "orchestrator/study/setting_row.hpp"

#include <string>
#include <string_view>

namespace demsa::experiments::incline {

/// [incline]. Radii default to the paper's particle set 1 (Table 2).
struct InclineSettings {
  std::string preset;               ///< "", "set1" or "set2": the radii of the paper's particle sets
  study::RadiusDistribution radii;  ///< the probes' radii
  int rolling_probes = 12;          ///< free spheres
  int sliding_probes = 12;          ///< rotation-locked spheres
  double lane_spacing = 0.008;      ///< distance between neighbouring probes' lanes [m] (> 2 r_max)
  double settle_time = 0.05;        ///< on the level plate before the tilt [s]
  double tilt_rate = 5.0;           ///< Ω [deg/s]
  double max_angle = 70.0;          ///< the tilt stops here [deg]
  double record_angle = 0.25;       ///< the probes are recorded every this much tilt [deg]
  double onset_distance = 0.002;    ///< a probe has started once it moved this far down the slope [m]
  double speed_angle = 5.0;         ///< the rolling probes' speed is read at this tilt [deg]
  double stop_distance = 0.3;       ///< a probe this far down the slope has left the test and is removed [m]
};

const InclineSettings& settings(const study::StudyConfig& config);
InclineSettings& settings(study::StudyConfig& config);

/// The incline's descriptor (registry.hpp lists it).
const Experiment& experiment();

// ---------------------------------------------------------------- observables
/// The one range of each setting the measurement reads back from case.json, checked by its row of the study file and
/// by the measurement alike (issue 45).
/// `[incline] onset_distance` [m]: from a micrometre (k_min_radius: no smaller particle) to a metre.
inline study::SettingBounds onset_distance_bounds() { return study::between(study::k_min_radius, true, 1, true); }
/// `[incline] speed_angle` and `max_angle` [deg]: a tilt above level and short of vertical.
inline study::SettingBounds tilt_bounds() { return study::between(0, false, 89, true); }
/// `[incline] record_angle` [deg]: each record is one LIGGGHTS run and one dump frame of every probe, so at most
/// max_angle / record_angle of them (8900 at 0.01°; the default 0.25° records 240 over 60°).
inline study::SettingBounds record_angle_bounds() {
  return study::between(0.01, true, 10, true, "each record is a LIGGGHTS run and a dump frame of every probe");
}

inline constexpr std::string_view k_roll_angle = "roll_angle";        ///< tilt at which the free probes roll [deg]
inline constexpr std::string_view k_slide_angle = "slide_angle";      ///< tilt at which the locked probes slide [deg]
inline constexpr std::string_view k_roll_speed = "roll_speed";        ///< free probes' speed at speed_angle [m/s]
inline constexpr std::string_view k_probes_rolled = "probes_rolled";  ///< recorded: free probes with an onset
inline constexpr std::string_view k_probes_slid = "probes_slid";      ///< recorded: locked probes with an onset

// ---------------------------------------------------------------- files of an incline case
inline constexpr const char* k_final_dump = "incline_final.dump";
inline constexpr const char* k_probes_dump = "incline_probes.dump";  ///< every probe every record_angle
inline constexpr const char* k_end = "incline_end.txt";              ///< `end_tilt T`, `removed N`

}  // namespace demsa::experiments::incline

namespace demsa::experiments::incline {

/// The atom-steps of a written case by its schedule (case.cpp): Experiment::case_cost.
CaseCost case_cost(const study::StudyConfig& config, const nlohmann::json& case_json, const std::filesystem::path& file,
                   const nlohmann::json& probed);

}  // namespace demsa::experiments::incline
