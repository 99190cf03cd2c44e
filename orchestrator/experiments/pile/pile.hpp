#pragma once
// The angle-of-repose pile (paper §3): particles poured in discs onto a pedestal cylinder, settled, measured by the
// angle of its flanks (§3.3). Its settings ([pile]), its assembly and case, its measurement and report.
#include "orchestrator/experiments/assembly.hpp"
#include "orchestrator/experiments/experiment.hpp"
#include "orchestrator/study/setting_row.hpp"
#include "postprocess/pile_angle.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::experiments::pile {

/// What the pile stands on: the pedestal's wall material, or a fixed layer of the material's own particles glued to
/// the pedestal top (every contact of the pile's base is then particle-particle).
enum class PileBase { wall, particles };

/// The pedestal's top as LIGGGHTS sees it: the mesh (demsa's pedestal.stl: rim, side band and top), or a primitive
/// plane at the top's height with the particles past the rim deleted at every check. The plane costs 1.53 times fewer
/// CPU-seconds with the same mean angle, but lowers the angle's sensitivity to μ_R,PW and leaves more quickstart piles
/// unsettled (docs/explanation/benchmarks.md, "The pedestal top as a plane"): the mesh stays the default.
enum class PedestalTop { mesh, plane };

/// [pile] (paper §3). Defaults: particle set 1 of Table 2 scaled to `particles`.
struct PileSettings {
  std::string preset;    ///< "", "set1" or "set2" (paper Table 2); fills radii and particles
  int particles = 6000;  ///< number of particles
  study::RadiusDistribution radii;
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
  PileBase base = PileBase::wall;  ///< the pedestal top: its wall, or a frozen layer of the material's particles
  PedestalTop pedestal_top = PedestalTop::mesh;  ///< the pedestal top's wall in LIGGGHTS (plane_pedestal)

  // The pile in time: snapshots during settling, measured like the final pile.
  double history_interval = 0.1;      ///< a snapshot every this long after the last disc [s]; 0 = none
  bool keep_snapshots = false;        ///< keep the snapshot dumps once measured
  std::vector<double> measure_times;  ///< angle@T: the angle T seconds after the last disc, for each T [s]
  double drift_window = 0.2;          ///< angle_drift: the robust slope of the angle over the last this long [s]
  double drift_limit = 1.0;           ///< settled also requires |angle_drift| at most this [deg/s]
};

/// The [pile] settings of a study.
const PileSettings& settings(const study::StudyConfig& config);
PileSettings& settings(study::StudyConfig& config);

/// Whether a case's pedestal top is the primitive plane rather than the mesh.
bool plane_pedestal(const PileSettings& s);

/// The pile's descriptor (registry.hpp lists it).
const Experiment& experiment();

/// Its tool, `demsa postprocess NAME` (Experiment::case_tool; tool.cpp).
std::unique_ptr<CaseTool> make_case_tool();

// ---------------------------------------------------------------- observables (paper §3.3)
/// The one range of each measurement setting read back from case.json, checked by its row of the study file and by the
/// measurement alike, so that what the study file accepts the measurement reads (issue 45: a drift_window of 1e-300 s
/// passed the study file, then every case failed at its measurement).
/// `[pile] drift_window` [s]: from a microsecond (below any snapshot interval) to the longest stage.
inline study::SettingBounds drift_window_bounds() { return study::between(1e-6, true, study::k_max_duration, true); }
/// `[pile] drift_limit` [deg/s]: from 1e-9 (no pile's angle is steadier) to 1e6.
inline study::SettingBounds drift_limit_bounds() { return study::between(1e-9, true, 1e6, true); }

inline constexpr std::string_view k_angle = "angle";              ///< angle of repose φ [deg]
inline constexpr std::string_view k_angle_sd = "angle_sd";        ///< spread of φ over the directions [deg]
inline constexpr std::string_view k_pile_height = "pile_height";  ///< h_P [m]
inline constexpr std::string_view k_particles_on_pedestal = "particles_on_pedestal";
/// Particles removed off the pedestal during the run ([pile] remove_fallen); recorded, not analysed.
inline constexpr std::string_view k_removed_off_pedestal = "removed_off_pedestal";
/// The angle's drift at the end of settling: the Theil–Sen slope of the angle over the last [pile] drift_window
/// [deg/s]; recorded, not analysed.
inline constexpr std::string_view k_angle_drift = "angle_drift";
/// angle@T: the angle T seconds after the last disc ([pile] measure_times), analysed like the final angle.
inline constexpr std::string_view k_angle_at = "angle@";
/// angle_series@T: the angle of every snapshot of the settling ([pile] history_interval); recorded, not analysed.
inline constexpr std::string_view k_angle_series = "angle_series@";

/// The name of the observable `prefix` at time `t` [s]: "angle@0.6" (the shortest text that reads back as t).
std::string timed_observable(std::string_view prefix, double t);

// ---------------------------------------------------------------- files of a pile case
inline constexpr const char* k_final_dump = "pile_final.dump";    ///< id type x y z radius vx vy vz
inline constexpr const char* k_settling = "pile_settling.txt";    ///< how settling ended, particles removed
inline constexpr const char* k_pedestal_stl = "pedestal.stl";     ///< the pedestal mesh
inline constexpr const char* k_history_csv = "pile_history.csv";  ///< the measured snapshots of the settling
/// The snapshot of the particles at settling check K (0: the end of the last disc): pile_snapshot_K.dump.
std::string snapshot_file(long check);

// ---------------------------------------------------------------- assembly (paper §3.1)
/// One horizontal disc of the pile: particle centres in the plane z = 0 (the height is set by the schedule).
using Disc = std::vector<Particle>;

/// Fills one disc of radius `disc_radius` by concentric annuli (paper §3.1, Fig. 1a): ring k has radius 2 r_U k
/// (k = 0 is the centre particle) and is used while 2 r_U k + r_U ≤ disc_radius; along a ring, consecutive
/// particles are spaced by the chord r_a + r_b + gap, and a ring closes when the next particle would overlap its
/// first. Consumes radii from `radii` starting at `next`, advancing it; returns an empty disc when none are left.
Disc fill_disc(const std::vector<double>& radii, std::size_t& next, double r_upper, double disc_radius, double gap);

/// The pile's initial column and its appended discs (paper §3.1–3.2).
struct PileAssembly {
  std::vector<Disc> discs;       ///< every disc in order; particle z is its height at insertion
  int column_discs = 0;          ///< discs 0..column_discs-1 are present at the start
  double append_height = 0.0;    ///< z of every later disc: pedestal top + h_fu [m]
  double r_upper = 0.0;          ///< r_U: the upper radius bound [m]
  std::vector<double> radii;     ///< all radii in insertion order
  int particles() const;         ///< total count
  int column_particles() const;  ///< particles present at the start
};

/// Disc k of the column sits at z = pedestal_height + r_U + 2 r_U k while that is ≤ pedestal_height + h_fu; the
/// rest are appended at pedestal_height + h_fu, one every sqrt(4 r_U/|g|) (heights from the pedestal top: a disc
/// at r_U above the ground would cut the pedestal).
PileAssembly build_assembly(const PileSettings& settings, std::uint64_t seed);

/// The frozen layer of `base = "particles"`: the material's particles (radii from [pile]'s distribution, drawn with
/// their own seed derived from `seed`, so that the pile's own radii are those of a wall-base pile) on a hexagonal
/// lattice of pitch k_base_pitch × r_mean over the pedestal top, each resting on it (centre at top + r, on the top:
/// a particle of the rim may overhang it). Identical for every sample of a study. The pedestal mesh of such a case is
/// its side band only: the layer covers the top.
std::vector<Particle> build_base_layer(const PileSettings& settings, std::uint64_t seed);

/// The lattice pitch of the base layer in units of the mean radius: neighbours of mean size touch (pitch 2 r_mean),
/// so that a pile particle finds no gap down to the pedestal's wall between them (docs/explanation/experiments.md
/// measures how often one still touches it).
inline constexpr double k_base_pitch = 2.0;

/// Paper §3.2: a new disc is appended every t = sqrt(4 r_U / |g|) — the time in which a disc released at rest falls
/// 2 r_U, the vertical disc spacing.
double disc_append_interval(double r_upper, double gravity);

// ---------------------------------------------------------------- measurement
/// How the settling of a pile ended, as pile.liggghts writes it to pile_settling.txt (`key value` lines).
struct PileSettling {
  bool criterion = false;           ///< the settling criterion was on ([pile] settle_speed > 0)
  bool settled = false;             ///< ... and met before settle_time
  long end_step = 0;                ///< step at which settling ended
  double fastest = 0.0;             ///< fastest particle on the pedestal then [m/s]
  double speed_limit = 0.0;         ///< the criterion's speed [m/s]
  long on_pedestal = 0;             ///< particles on the pedestal then
  long fast_on_pedestal = 0;        ///< ... of them faster than speed_limit
  long removed = 0;                 ///< particles removed off the pedestal during the run
  std::optional<long> start_step;   ///< the step at which settling began (the end of the last disc)
  std::optional<long> check_steps;  ///< steps between settling checks
};

/// Reads FOLDER/pile_settling.txt; nothing when the file does not exist. Throws postprocess::ParseError (file:line)
/// on a line that is not `key number` or a missing key.
std::optional<PileSettling> read_settling(const std::filesystem::path& folder);

/// The pedestal (pedestal_radius, its top at pedestal_height), directions, levels, target angle and estimator of
/// [pile]; the band of levels is left unset, so each estimator measures on its own (postprocess::PileAngleOptions).
postprocess::PileAngleOptions angle_options(const PileSettings& settings);

/// What a pile case's case.json records of its measurement (its "pile" object): the pedestal and the
/// angle_measurement. A key a case does not record (a case of an older demsa) is unset.
struct CaseAngleSettings {
  std::optional<double> pedestal_radius;                 ///< pile.pedestal_radius_m
  std::optional<double> pedestal_top;                    ///< pile.pedestal_height_m (the ground is at z = 0)
  std::optional<int> directions;                         ///< pile.angle_measurement.directions
  std::optional<int> levels;                             ///< pile.angle_measurement.levels
  std::optional<postprocess::AngleEstimator> estimator;  ///< pile.angle_measurement.estimator
  std::optional<long> base_particles;  ///< pile.base.particles: atoms 1..N are the frozen base layer, not the pile
  std::optional<double> base_top;      ///< pile.base.top_m: the plane the pile stands on, z of the layer's mean top
};

/// Reads them from case.json (`file` names it in messages). Throws util::UserError "FILE: pile.KEY = VALUE: ..." on a
/// value of the wrong type or outside the range of its [pile] row.
CaseAngleSettings read_case_angle_settings(const nlohmann::json& case_json, const std::filesystem::path& file);

/// The angle options of a pile case, as its study measured it: the pedestal and measurement its case.json records
/// (on a base layer, heights start at the layer's mean top). Throws util::UserError naming case.json when it records
/// no pedestal.
postprocess::PileAngleOptions case_angle_options(const nlohmann::json& case_json, const std::filesystem::path& file);

// ---------------------------------------------------------------- the pile in time
/// Which settling checks of a case write a snapshot (pile_history.liggghts): check 0 (the end of the last disc), every
/// `every` checks up to `checks` (none when `every` is 0), and the check of each measure time; sorted, unique. The
/// check of time T is round(T / check_time).
struct SnapshotPlan {
  std::vector<long> checks;          ///< the checks that write a snapshot
  std::vector<long> measure_checks;  ///< the check of each of [pile] measure_times, in its order
  long min_checks = 0;               ///< the criterion may not end settling before this check
};
SnapshotPlan snapshot_plan(const PileSettings& settings, long checks, long check_steps, double dt);

/// The most snapshots a case may write ([pile] history_interval and settle_time): each is a dump of every particle.
inline constexpr long k_max_snapshots = 2000;

/// One moment of a pile's settling, measured on a snapshot (or the final dump).
struct PileMoment {
  long check = -1;            ///< the settling check of the snapshot; -1: the final dump
  double time = 0.0;          ///< seconds after the last disc
  double angle = 0.0;         ///< by the study's estimator [deg]
  double angle_paper = 0.0;   ///< by the paper's estimator (§3.3) [deg]
  double angle_robust = 0.0;  ///< by the robust estimator [deg]
  double height = 0.0;        ///< h_P [m]
  long on_pedestal = 0;       ///< particles on the pedestal
};

/// The drift of the angle at the end of a series: the Theil–Sen slope (Theil 1950, Sen 1968) of angle on time over
/// the moments within `window` seconds of the last one [deg/s]; NaN with fewer than two such moments.
double angle_drift(const std::vector<PileMoment>& moments, double window);

/// Writes the series as FOLDER/pile_history.csv; reads it back (throws postprocess::ParseError at file:line).
void write_history(const std::filesystem::path& folder, const std::vector<PileMoment>& moments);
std::vector<PileMoment> read_history(const std::filesystem::path& folder);

}  // namespace demsa::experiments::pile

namespace demsa::experiments::pile {

/// The particles a pedestal carries in a pile (cost.cpp): a cone at the larger of target_angle and 35 degrees plus one
/// layer over the top, at a solid fraction of 0.6, in mean particle volumes.
double pedestal_capacity(const PileSettings& settings);

/// The atom-steps of a written pile case by its schedule (cost.cpp): Experiment::case_cost. With remove_fallen, the
/// atoms of each interval count up to pedestal_capacity and one disc.
CaseCost case_cost(const study::StudyConfig& config, const nlohmann::json& case_json, const std::filesystem::path& file,
                   const nlohmann::json& probed);

}  // namespace demsa::experiments::pile
