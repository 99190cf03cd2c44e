#pragma once
// The study file (TOML): what a study varies, how it samples, what it simulates, where it runs and how it is
// analysed. Every key of the file is one row of settings.hpp (type, default, range, unit, effect, documentation),
// from which the parser, the design hash and the reference of docs/study-file.md come.
//
// Units are SI throughout (m, s, kg, Pa, N). The paper's mg-mm-ms values are converted in docs/study-file.md.
#include "orchestrator/study/parameters.hpp"
#include "sobol/metamodel.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/scaling.hpp"

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::study {

enum class Experiment { pile, oedometer };
enum class PlateMode { servo, trial_step };
enum class TimestepMode { rayleigh, fixed };
enum class ExecutorKind { local, slurm };
/// How the SLURM executor submits: one job array per batch of cases, or one allocation whose cases run as job steps.
enum class SlurmMode { array, pack };
/// The rolling-resistance model of every pair and wall contact (docs/study-file.md, [contact]).
enum class RollingModel { cdt, epsd, epsd2, epsd3, viscous };
/// The unit in which a study gives the viscous model's μ_R (mu_r_pp, mu_r_pw and their ranges).
enum class ViscousUnit { s_m, mm_ms };

/// LIGGGHTS (units si) refuses youngsModulus outside [5e6, 1e9] Pa unless `soft_particles yes` /
/// `hard_particles yes` is given (Material::soft_particles / hard_particles).
inline constexpr double k_liggghts_min_E = 5e6;
inline constexpr double k_liggghts_max_E = 1e9;

/// One varied parameter: a name from contact_parameter_names() and its range.
struct ParameterRange {
  std::string name;
  sobol::Bounds bounds;  ///< low < high; log scale needs low > 0
  int line = 0;          ///< line in the study file (for messages)
};

/// Material values: the fixed value of every contact parameter that is not varied, and the density.
struct Material {
  double E = 1e8;               ///< Young's modulus [Pa]; LIGGGHTS (units si) checks 5e6 <= E <= 1e9
  double nu = 0.3;              ///< Poisson ratio, (0, 0.5)
  double mu_pp = 1.0;           ///< particle-particle Coulomb friction, >= 0
  double mu_pw = 1.0;           ///< particle-wall Coulomb friction, >= 0
  double e_r = 0.4;             ///< coefficient of restitution, (0, 1]
  double mu_r_pp = 0.1;         ///< particle-particle rolling friction (LIGGGHTS `cdt`, dimensionless), >= 0
  double mu_r_pw = 0.1;         ///< particle-wall rolling friction (`cdt`), >= 0
  double density = 2500;        ///< particle density [kg/m^3], > 0 (not in the paper)
  double gravity = 9.81;        ///< |g| [m/s^2], > 0
  bool soft_particles = false;  ///< allow E < 5e6 Pa (LIGGGHTS `soft_particles yes`)
  bool hard_particles = false;  ///< allow E > 1e9 Pa (LIGGGHTS `hard_particles yes`)
};

/// Radii of a particle set: truncated normal N(mean, sd) restricted to [r_min, r_max] (paper Table 2).
struct RadiusDistribution {
  double r_min = 1.0e-3;  ///< [m]
  double r_max = 3.5e-3;  ///< [m]
  double mean = 2.0e-3;   ///< [m]
  double sd = 0.5e-3;     ///< [m]
};

/// Pile experiment (paper §3). Defaults: particle set 1 of Table 2 scaled to `particles`.
struct PileSettings {
  std::string preset;    ///< "", "set1" or "set2" (paper Table 2); fills radii and particles
  int particles = 6000;  ///< number of particles
  RadiusDistribution radii;
  double disc_radius = 0.020;       ///< r_fu: radius of the filling discs [m]
  double fill_height = 0.100;       ///< h_fu: discs below it are present at start [m]
  double pedestal_radius = 0.050;   ///< r_cy [m]
  double pedestal_height = 0.005;   ///< h_cy [m]
  double settle_time = 0.6;         ///< settling after the last disc: the cap [s]
  double settle_speed = 0.0;        ///< settled: particles on the pedestal slower than this x sqrt(|g| r_min); 0 = off
  double settle_quantile = 0.95;    ///< ... this share of them at least (1 = every one)
  double settle_window = 0.05;      ///< ... at every check for this long [s]
  bool remove_fallen = false;       ///< delete particles below the pedestal top and outside its radius
  double target_angle = 33.5;       ///< φ̂ for E_φ [deg]
  int directions = 180;             ///< φ_N (paper §3.3)
  int levels = 10;                  ///< height levels between 0.2 h_P and 0.75 h_P
  double settle_check_time = 0.02;  ///< the settling criterion and the removal are checked every this long [s]
  double domain_half_width = 0.15;  ///< simulation box half width in x and y [m]; particles leaving it are lost

  /// "paper" (§3.3) or "robust": the angle estimator of the measurement (postprocess::AngleEstimator)
  std::string angle_estimator = "paper";
};

/// Radii of the paper's oedometer assembly one (§4; derivation in apply_oedometer_preset): the `paper` preset and the
/// default.
inline constexpr RadiusDistribution k_paper_oedometer_radii{2.0e-3, 3.0e-3, 2.466e-3, 0.25e-3};

/// Oedometer experiment (paper §4).
struct OedometerSettings {
  int particles = 4642;
  std::string preset;  ///< "" or "paper" (assembly one of §4: 4642 particles)
  RadiusDistribution radii = k_paper_oedometer_radii;
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

/// The contact model's rolling resistance; hertz normal and history tangential are fixed.
struct ContactSettings {
  RollingModel rolling_model = RollingModel::cdt;
  double rolling_damping = 0.3;     ///< η_r of epsd and epsd3 (coefficientRollingViscousDamping), [0, 1]
  double rolling_stiffness = 2.25;  ///< epsd3: k_r = rolling_stiffness k_n μ_r² R*² (rollingStiffness), >= 1
  ViscousUnit viscous_unit = ViscousUnit::s_m;  ///< the unit of μ_R for `viscous`
};

/// The LIGGGHTS name of a rolling model ("cdt", ..., "viscous").
std::string_view rolling_model_name(RollingModel model);
/// Factor from the study's μ_R to SI s·m: 1 for s·m, 1e-6 for mm·ms.
double viscous_unit_factor(ViscousUnit unit);

struct TimestepSettings {
  TimestepMode mode = TimestepMode::rayleigh;
  double fraction = 0.15;  ///< dt = fraction * T_R(r_min, E, ν, ρ); (0, 0.3]
  double value = 0.0;      ///< fixed dt [s] (mode fixed)
  double skin = 1e-3;      ///< neighbor list skin [m]; a moving mesh may travel at most skin/2 per step
};

struct SlurmSettings {
  SlurmMode mode = SlurmMode::array;  ///< array: one array task per case; pack: one allocation, one step per case
  std::string partition;              ///< empty: the cluster's default
  std::string account;
  std::string time_limit = "01:00:00";      ///< per case, sbatch --time
  int throttle = 0;                         ///< %N array throttle; 0 = none
  std::vector<std::string> sbatch_options;  ///< extra sbatch options, verbatim
  std::string prologue;                     ///< shell lines before mpirun (module load ...)
  double poll_interval = 5.0;               ///< [s]
};

struct RunSettings {
  ExecutorKind executor = ExecutorKind::local;
  int ranks = 1;                      ///< MPI ranks per case (identical for every case: results depend on it)
  int parallel = 0;                   ///< cases at once (local); 0 = cores / ranks
  bool oversubscribe = false;         ///< allow parallel * ranks > cores
  double timeout = 0.0;               ///< per case [s]; 0 = none
  int retries = 1;                    ///< extra attempts after a failure
  double lost_fraction = 0.01;        ///< lost particles above this fraction fail the case
  std::string liggghts = "liggghts";  ///< executable (name on PATH or path)
  std::string mpirun = "mpirun";
  SlurmSettings slurm;
};

struct AnalysisSettings {
  std::vector<std::string> metamodels{"rsm2", "rsm3", "rbf-cubic", "rbf-tps", "gp"};
  bool second_order = true;
  int bootstrap = 200;  ///< bootstrap resamples, or GP-posterior draws, for confidence intervals
  /// How the intervals of metamodel indices are obtained (sobol/metamodel_sobol.hpp): the design bootstrap for every
  /// metamodel (the default), or a GP's posterior draws for the gp metamodel.
  sobol::MetamodelInterval interval = sobol::MetamodelInterval::design_bootstrap;
  double confidence = 0.95;
  int base_samples = 16384;  ///< QMC base N for metamodel-based indices
  /// The gp metamodel: kernel, trend and an estimated nugget (DEM responses are noisy: a nugget lets the GP smooth
  /// rather than interpolate). Used alike by analyze, report and calibrate.
  sobol::GpKernel gp_kernel = sobol::GpKernel::squared_exponential;
  sobol::GpTrend gp_trend = sobol::GpTrend::constant;
  bool gp_nugget = false;
  /// The metamodel options these settings give.
  sobol::MetamodelOptions metamodel_options() const;
};

/// `[design] replicates = { points = P, repeats = R }`: at the first P design points, R cases each whose particle
/// packing is drawn with another assembly seed (the design point's own case is the first of the R, so R − 1 more
/// cases per point). Off (points = 0) by default.
struct ReplicateSettings {
  int points = 0;   ///< P: design points with replicates (the first P of the design), 0 = none
  int repeats = 0;  ///< R: cases per such point, the design point's own case included (>= 2 when points > 0)
  bool enabled() const { return points > 0; }
  int extra_cases() const { return enabled() ? points * (repeats - 1) : 0; }  ///< P (R − 1)
};

struct StudyConfig {
  std::filesystem::path file;  ///< the study file it was read from
  std::string name;            ///< study name
  Experiment experiment = Experiment::pile;
  std::uint64_t seed = 12345;          ///< one seed for the design, the radii and the initial positions
  std::string design = "lhs-maximin";  ///< a canonical name of sobol::design_kind_names()
  int samples = 16;
  ReplicateSettings replicates;            ///< [design] replicates (DEM noise)
  std::vector<ParameterRange> parameters;  ///< the varied parameters, in the paper's order
  Material material;
  ContactSettings contact;
  PileSettings pile;
  OedometerSettings oedometer;
  TimestepSettings timestep;
  RunSettings run;
  AnalysisSettings analysis;
};

/// The largest study file load_study() reads (a study file is a few kB).
inline constexpr std::size_t k_max_study_file_bytes = 1 << 20;

/// Reads and validates a study file. Throws util::UserError "study.toml:LINE: ..." for unknown keys, wrong types and
/// impossible values, and "FILE: ..." for a folder or a file larger than k_max_study_file_bytes.
StudyConfig load_study(const std::filesystem::path& file);

/// Parses study text (for tests); `file` is the name used in messages.
StudyConfig parse_study(const std::string& text, const std::filesystem::path& file);

/// A stable hash (16 hex digits, FNV-1a 64) of the settings whose effect is cases or measurement (settings.hpp:
/// design_hash_text): everything but [run] and [analysis], except run.ranks (a result depends on the rank count).
std::string design_hash(const StudyConfig& config);

/// The member of Material that holds the contact parameter `key` (a key of contact_parameters()); nullptr for any
/// other name.
double Material::*material_member(std::string_view key);

/// Material values for one sample: config.material with the varied parameters set from `physical`
/// (ordered as config.parameters).
Material material_for(const StudyConfig& config, const std::vector<double>& physical);

}  // namespace demsa::study
