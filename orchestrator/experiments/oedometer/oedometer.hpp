#pragma once
// The oedometer (paper §4): particles poured into a box and loaded by a force-driven plate, measured by the
// settlements per load. Its settings ([oedometer]), assembly and case, its measurement and report, and the paper's
// trial-step plate loop (driver.hpp).
#include "orchestrator/experiments/assembly.hpp"
#include "orchestrator/experiments/experiment.hpp"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::experiments::oedometer {

enum class PlateMode { servo, trial_step };

/// Radii of the paper's oedometer assembly one (§4; derivation in settings.cpp): the `paper` preset and the default.
inline constexpr study::RadiusDistribution k_paper_radii{2.0e-3, 3.0e-3, 2.466e-3, 0.25e-3};

/// [oedometer] (paper §4).
struct OedometerSettings {
  int particles = 4642;
  std::string preset;  ///< "" or "paper" (assembly one of §4: 4642 particles)
  study::RadiusDistribution radii = k_paper_radii;
  double box_side = 0.10;                                   ///< [m]
  double box_height = 0.10;                                 ///< [m]
  double fill_time = 0.5;                                   ///< pouring and settling before loading [s]
  std::vector<double> loads{100.0, 400.0, 1100.0, 2700.0};  ///< L_n [N], increasing
  std::vector<double> measured_settlements;                 ///< s̃_i for loads 1..n-1 relative to load 0 [m]
  PlateMode plate_mode = PlateMode::servo;
  // servo mode
  double servo_vel_max = 0.05;  ///< [m/s]; must be < skin/(2 dt)
  double servo_kp = 0.5;
  double servo_ki = 0.0;
  double servo_kd = 0.0;
  double load_tolerance = 0.03;   ///< |F - L| that counts as reached [N] (paper R_pr = 0.03 N)
  long servo_max_steps = 400000;  ///< give up on a load after this many steps
  long servo_check_steps = 2000;  ///< servo: force averaged and the load checked every this many steps
  double rest_velocity = 1e-3;    ///< servo: the plate is at rest when its mean speed over a check is below [m/s]
  double plate_gap = 0.5e-3;      ///< the plate starts this far above the settled packing [m]
  // trial-step mode (paper §4 constants)
  long trial_steps = 15000;        ///< n_s
  long relax_steps = 80000;        ///< n_L
  double trial_reduction = 0.95;   ///< m_T
  double trial_step0 = 0.0075e-3;  ///< δ_T0 [m]
  double trial_floor = 0.05;       ///< minimum trial step as a fraction of δ_T0
  int max_trials = 2000;           ///< per load
};

/// The [oedometer] settings of a study.
const OedometerSettings& settings(const study::StudyConfig& config);
OedometerSettings& settings(study::StudyConfig& config);

/// The oedometer's descriptor (registry.hpp lists it).
const Experiment& experiment();

/// Its tool, `demsa postprocess NAME` (Experiment::case_tool; tool.cpp).
std::unique_ptr<CaseTool> make_case_tool();

// ---------------------------------------------------------------- observables (paper §4)
inline constexpr std::string_view k_settlement_error = "settlement_error";  ///< E_0 [m]
/// "settlement_K": the settlement s_K at load K relative to load 0 [m], K >= 1.
std::string settlement_name(std::size_t k);
/// K of a "settlement_K" name; nullopt for any other name.
std::optional<std::size_t> settlement_index(std::string_view name);

// ---------------------------------------------------------------- files of an oedometer case
inline constexpr const char* k_final_dump = "oedometer_final.dump";  ///< id type x y z radius vx vy vz
inline constexpr const char* k_plate_history = "plate_history.txt";  ///< step load_N plate_z_m force_N ...
inline constexpr const char* k_plate_states = "plate_states.txt";    ///< load_N plate_z_m force_N converged
inline constexpr const char* k_plate_stl = "plate.stl";              ///< the load plate at z = 0
/// The hidden command of the trial-step plate loop (driver.hpp), which run.sh starts.
inline constexpr const char* k_driver_command = "drive-oedometer";

// ---------------------------------------------------------------- assembly
/// The oedometer's loose initial packing: a square lattice of cells of side 2 r_max + gap filling the box's base,
/// layer on layer from the floor, each particle shifted inside its cell by a deterministic golden-angle offset of
/// length r_max − r so that the packing is not a perfect lattice and poured it settles into a random packing.
struct OedometerAssembly {
  std::vector<Particle> particles;
  int per_layer = 0;  ///< particles per lattice layer
  int layers = 0;
  double top = 0.0;           ///< highest particle top [m]
  double solid_volume = 0.0;  ///< Σ 4/3 π r³ [m³]
};

OedometerAssembly build_assembly(const OedometerSettings& settings, std::uint64_t seed);

/// The atom-steps of a written case by its schedule (cost.cpp): Experiment::case_cost. A trial-step case's first load
/// follows the settled packing that a probe read (probe_state), when `probed` holds one.
CaseCost case_cost(const study::StudyConfig& config, const nlohmann::json& case_json, const std::filesystem::path& file,
                   const nlohmann::json& probed);
/// The settled packing of the case in `folder` once its fill is done (plate_states.txt's first comment), as JSON
/// for case_cost; null before (cost.cpp): Experiment::probe_state.
nlohmann::json probe_state(const std::filesystem::path& folder);

}  // namespace demsa::experiments::oedometer
