#pragma once
// The study file (TOML): what a study varies, how it samples, what it simulates, where it runs and how it is
// analysed. Every key of the file is one row of settings.hpp (type, default, range, unit, effect, documentation),
// from which the parser, the design hash and the reference of docs/reference/study-file.md come.
//
// Units are SI throughout (m, s, kg, Pa, N). The paper's mg-mm-ms values are converted in docs/reference/study-file.md.
#include "orchestrator/study/parameters.hpp"
#include "sobol/metamodel.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/scaling.hpp"

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <typeindex>
#include <typeinfo>
#include <vector>

namespace demsa::study {

enum class TimestepMode { rayleigh, fixed };
enum class ExecutorKind { local, slurm };
/// How the SLURM executor submits: one job array per batch of cases, or one allocation whose cases run as job steps.
enum class SlurmMode { array, pack };
/// The rolling-resistance model of every pair and wall contact (docs/reference/study-file.md, [contact]).
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

class SettingsTable;

/// The settings of the experiments' own sections ([pile], [oedometer], ...), by type: each experiment defines its
/// settings struct (orchestrator/experiments/NAME/) and its rows read and write it through get<T>(). A type not
/// stored reads as its defaults (a default-constructed T), so that a config of one experiment shows the defaults of
/// the others' rows.
class ExperimentSettings {
 public:
  ExperimentSettings() = default;
  ExperimentSettings(const ExperimentSettings& other) { *this = other; }
  ExperimentSettings& operator=(const ExperimentSettings& other) {
    if (this == &other) return *this;
    m_slots.clear();
    for (const auto& [type, slot] : other.m_slots) m_slots.emplace(type, slot->clone());
    return *this;
  }
  ExperimentSettings(ExperimentSettings&&) noexcept = default;
  ExperimentSettings& operator=(ExperimentSettings&&) noexcept = default;
  ~ExperimentSettings() = default;

  /// The stored T, created with its defaults on first use.
  template <typename T>
  T& get() {
    std::unique_ptr<Slot>& slot = m_slots[std::type_index(typeid(T))];
    if (!slot) slot = std::make_unique<Holder<T>>();
    return static_cast<Holder<T>&>(*slot).value;
  }
  /// The stored T, or T's defaults.
  template <typename T>
  const T& get() const {
    const auto it = m_slots.find(std::type_index(typeid(T)));
    if (it == m_slots.end()) {
      static const T defaults{};
      return defaults;
    }
    return static_cast<const Holder<T>&>(*it->second).value;
  }

 private:
  struct Slot {
    virtual ~Slot() = default;
    virtual std::unique_ptr<Slot> clone() const = 0;
  };
  template <typename T>
  struct Holder final : Slot {
    T value{};
    std::unique_ptr<Slot> clone() const override { return std::make_unique<Holder>(*this); }
  };
  std::map<std::type_index, std::unique_ptr<Slot>> m_slots;
};

struct StudyConfig {
  std::filesystem::path file;  ///< the study file it was read from
  std::string name;            ///< study name
  std::string experiment;      ///< the experiment's name ([study] experiment; orchestrator/experiments/registry.hpp)
  std::uint64_t seed = 12345;  ///< one seed for the design, the radii and the initial positions
  std::string design = "lhs-maximin";  ///< a canonical name of sobol::design_kind_names()
  int samples = 16;
  ReplicateSettings replicates;            ///< [design] replicates (DEM noise)
  std::vector<ParameterRange> parameters;  ///< the varied parameters, in the paper's order
  std::vector<ParameterTie> ties;          ///< parameters tied to a varied one (`same_as`), in the paper's order
  Material material;
  ContactSettings contact;
  ExperimentSettings experiment_settings;  ///< the experiments' own sections, by type
  TimestepSettings timestep;
  RunSettings run;
  AnalysisSettings analysis;
  /// The settings table the config was read with (SettingsTable::parse): design_hash() hashes its rows.
  const SettingsTable* table = nullptr;
};

/// The largest study file load_study() reads (a study file is a few kB).
inline constexpr std::size_t k_max_study_file_bytes = 1 << 20;

/// A stable hash (16 hex digits, FNV-1a 64) of the settings whose effect is cases or measurement (settings.hpp:
/// SettingsTable::hash_text of config.table): everything but [run] and [analysis], except run.ranks (a result
/// depends on the rank count).
std::string design_hash(const StudyConfig& config);
/// The same over the settings whose effect is cases only (SettingsTable::cases_hash_text): equal for two configs
/// whose cases are the same and differ at most in how they are measured.
std::string cases_hash(const StudyConfig& config);

/// The member of Material that holds the contact parameter `key` (a key of contact_parameters()); nullptr for any
/// other name.
double Material::*material_member(std::string_view key);

/// Material values for one sample: config.material with the varied parameters set from `physical`
/// (ordered as config.parameters) and each tied parameter set to its partner's value.
Material material_for(const StudyConfig& config, const std::vector<double>& physical);

}  // namespace demsa::study
