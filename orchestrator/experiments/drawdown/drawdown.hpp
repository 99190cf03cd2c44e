#pragma once
// The draw-down test (Roessler, Richter, Katterfeld & Will 2019, Powder Technol. 343): a box of the material empties
// through a slot in its floor, leaving a static slope on each side of the slot, an angle made by the material against
// itself. Its settings ([drawdown]), case, measurement (postprocess/drawdown.hpp) and report.
#include "orchestrator/experiments/assembly.hpp"
#include "orchestrator/experiments/experiment.hpp"
#include "orchestrator/study/setting_row.hpp"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::experiments::drawdown {

/// The box's floor: the wall material, or a frozen layer of the material's particles glued onto it.
enum class DrawdownFloor { wall, particles };

/// [drawdown]. Radii default to the paper's particle set 1 (Table 2).
struct DrawdownSettings {
  std::string preset;               ///< "", "set1" or "set2": the radii of the paper's particle sets
  int particles = 1850;             ///< the loose fill
  study::RadiusDistribution radii;  ///< of the fill and of a floor layer
  double slot_width = 0.030;        ///< the slot across the box's floor, along y [m]
  double side_width = 0.036;        ///< floor from the slot's edge to each wall [m]
  double depth = 0.020;             ///< the box's length along the slot, periodic [m]
  double fill_height = 0.14;        ///< the loose fill is placed up to this height [m]
  DrawdownFloor floor = DrawdownFloor::particles;
  double fill_time = 0.3;       ///< the fill settles on the closed floor [s]
  double check_time = 0.01;     ///< the discharge is recorded and fallen particles removed every this long [s]
  double window = 0.1;          ///< the flow has stopped once less than stop_share of the fill left in a window [s]
  double stop_share = 0.005;    ///< ... of the fill's mass
  double min_time = 0.3;        ///< ... at this time after the opening or later [s]
  double time_cap = 3.0;        ///< the run ends here still flowing (flagged unsettled) [s]
  double removal_depth = 0.02;  ///< particles this far below the floor are discharged and removed [m]
  // measurement (postprocess/drawdown.hpp)
  int slices = 5;           ///< planes across the slope
  double bin_width = 3e-3;  ///< [m]
  double edge_skip = 4e-3;  ///< [m]
  double wall_skip = 6e-3;  ///< [m]
};

const DrawdownSettings& settings(const study::StudyConfig& config);
DrawdownSettings& settings(study::StudyConfig& config);

/// The draw-down's descriptor (registry.hpp lists it).
const Experiment& experiment();

/// The lattice pitch of a floor layer in units of the mean radius (as the pile's base layer).
inline constexpr double k_floor_pitch = 2.0;

/// The frozen floor layer of `floor = "particles"`: the material's particles on a hexagonal lattice, its rows along
/// the slot at a pitch that divides the periodic depth, on the floor left and right of the slot (none over the slot or
/// into the walls), resting on it; radii from [drawdown]'s distribution with a seed of their own derived from `seed`.
std::vector<Particle> build_floor_layer(const DrawdownSettings& settings, std::uint64_t seed);

/// The loose fill: `particles` spheres placed by random sequential addition (Widom 1966) in the box above the floor
/// (above a floor layer's top when there is one) up to fill_height, none overlapping another or a wall, larger first;
/// positions and radii from `seed`. Throws util::UserError naming [drawdown] fill_height when they do not fit.
std::vector<Particle> build_fill(const DrawdownSettings& settings, std::uint64_t seed, double floor_top);
/// The fill's radii from `seed`, as build_fill draws them (before sorting).
std::vector<double> fill_radii(const DrawdownSettings& settings, std::uint64_t seed);

// ---------------------------------------------------------------- observables
/// The one range of `[drawdown] bin_width` [m], checked by its row of the study file and by the measurement reading
/// it back from case.json (issue 45): from a micrometre (k_min_radius) to a metre.
/// The largest solid fraction of the loose fill over the box up to fill_height that the study file accepts: the
/// saturation of random sequential addition of spheres (Zhang & Torquato 2013, Phys. Rev. E 88, 053312: 0.3841).
inline constexpr double k_max_fill_fraction = 0.38;
inline study::SettingBounds bin_width_bounds() { return study::between(study::k_min_radius, true, 1, true); }

inline constexpr std::string_view k_slope_angle = "slope_angle";              ///< [deg]
inline constexpr std::string_view k_discharged_mass = "discharged_mass";      ///< [kg]
inline constexpr std::string_view k_discharge_rate = "discharge_rate";        ///< [kg/s]
inline constexpr std::string_view k_retained_fraction = "retained_fraction";  ///< recorded: mass left / fill mass

// ---------------------------------------------------------------- files of a draw-down case
inline constexpr const char* k_final_dump = "drawdown_final.dump";
inline constexpr const char* k_discharge = "drawdown_discharge.txt";  ///< t_open discharged_kg atoms
inline constexpr const char* k_end = "drawdown_end.txt";  ///< stopped, t_open, fill_mass, discharged, removed

}  // namespace demsa::experiments::drawdown

namespace demsa::experiments::drawdown {

/// The atom-steps of a written case by its schedule (case.cpp): Experiment::case_cost.
CaseCost case_cost(const study::StudyConfig& config, const nlohmann::json& case_json, const std::filesystem::path& file,
                   const nlohmann::json& probed);

}  // namespace demsa::experiments::drawdown
