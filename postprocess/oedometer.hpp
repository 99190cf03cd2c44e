#pragma once
// The oedometer observables (paper §4): settlement per load step relative to the first load's plate position,
// vertical stress, void ratio, the plate iteration history and E_0 against measured settlements.
//
// Inputs are the two plate files every oedometer case writes:
//  - plate_history.txt: `#` comments; the last comment line starting with `# step` names the columns; required
//    `step load_N plate_z_m force_N`, optional `trial delta_m accepted` (trial-step mode); rows in time order.
//  - plate_states.txt: one row per load step reached: `load_N plate_z_m force_N converged`.
#include "postprocess/dump.hpp"
#include "postprocess/error.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::postprocess {

/// plate_history.txt, column by column. Optional columns are empty when the file does not have them.
struct PlateHistory {
  std::string file;
  std::vector<std::string> columns;  ///< as named by the `# step ...` line
  std::vector<long> step;
  std::vector<double> load_N;
  std::vector<double> plate_z_m;
  std::vector<double> force_N;
  std::vector<long> trial;      ///< trial-step mode: trial number within the load
  std::vector<double> delta_m;  ///< trial-step mode: trial step δ_Ta [m]
  std::vector<int> accepted;    ///< trial-step mode: 1 accepted, 0 rejected (backup restored)
  std::size_t size() const { return step.size(); }
};

/// One row of plate_states.txt: the plate at a load step that was reached.
struct PlateState {
  double load_N = 0;
  double plate_z_m = 0;
  double force_N = 0;
  bool converged = false;
};

/// Throws ParseError (file, line, value) on a missing column header, a missing required column, a short row, a
/// non-numeric or non-finite field, a negative load, a load below the row before (loads never decrease), a plate
/// position or trial step beyond 1 km, a line over 64 KiB or a file over 64 MiB (not a plate file). A file without
/// rows is valid (empty result).
PlateHistory read_plate_history(const std::filesystem::path& path);
std::vector<PlateState> read_plate_states(const std::filesystem::path& path);
/// The same from text held in memory; `name` stands for the file in messages.
PlateHistory parse_plate_history(std::string_view text, const std::string& name);
std::vector<PlateState> parse_plate_states(std::string_view text, const std::string& name);

/// The packing after the fill, as liggghts_templates/oedometer_fill.liggghts records it in the first comment of
/// plate_states.txt ("# settled packing: particles N, top_z_m Z, void_ratio E, plate_start_z_m Z0").
struct SettledPacking {
  long particles = 0;
  double top_z_m = 0;          ///< the highest particle's top
  double void_ratio = 0;       ///< e = A top_z / V_S - 1
  double plate_start_z_m = 0;  ///< where the plate starts: top_z + the plate's gap
};

/// The settled packing of a plate_states.txt (or its text); none when it has no such comment (the fill did not finish).
/// Throws ParseError (file, line, value) on that comment with a missing, non-numeric or non-finite field, fewer than
/// one particle, a negative void ratio or a plate start below the top.
std::optional<SettledPacking> read_settled_packing(const std::filesystem::path& path);
std::optional<SettledPacking> parse_settled_packing(std::string_view text, const std::string& name);

/// Load states from a history alone: the last row of each consecutive run of equal load (in trial-step mode the
/// last accepted row); converged when |force − load| ≤ load_tolerance.
std::vector<PlateState> states_from_history(const PlateHistory& history, double load_tolerance);

struct OedometerOptions {
  double box_side = 0.10;     ///< inner side of the square box: area A = side² [m] (paper: 10 cm); > 0
  double floor_z = 0.0;       ///< z of the box floor: sample height = plate_z − floor_z [m]
  double solid_volume = 0.0;  ///< V_S, volume of the particles [m³]; 0 = void ratio not computed; ≥ 0
  /// Measured settlements s̃_i [m] for the loads after the first (i = 1..n−1, the first load's settlement being 0
  /// by definition); may also hold n values starting with the first load's 0. Empty = E_0 not computed.
  std::vector<double> measured_settlements;

  /// Throws std::invalid_argument naming the field, its value and the rule.
  void validate() const;
};

struct OedometerStep {
  double load_N = 0;                 ///< L_n
  double plate_z_m = 0;              ///< plate height h at the accepted state
  double force_N = 0;                ///< particle force on the plate at that state
  bool converged = false;            ///< the plate file said the load was reached within its tolerance
  double settlement_m = 0;           ///< s = h_0 − h (paper §4)
  double stress_Pa = 0;              ///< vertical stress L_n / A
  std::optional<double> void_ratio;  ///< e = V_voids / V_S with V_voids = A (h − floor_z) − V_S, when V_S is known
};

struct OedometerResult {
  OedometerOptions options;          ///< echo
  std::vector<OedometerStep> steps;  ///< one per load state, in load order
  /// s_i for i = 1..n−1 (the settlements compared with measurements) [m].
  std::vector<double> settlements;
  std::optional<double> settlement_error;  ///< E_0 = sqrt(Σ (s̃_i − s_i)²) [m], when measured settlements were given
  bool all_converged = false;
  std::optional<PlateHistory> history;  ///< the plate iteration history, when it was given
  std::size_t trials_accepted = 0;      ///< trial-step mode: accepted / rejected trial rows in the history
  std::size_t trials_rejected = 0;
};

/// Computes the settlements from the load states (at least one). Throws InputError when the number of measured
/// settlements fits neither n−1 nor n states.
OedometerResult measure_oedometer(const std::vector<PlateState>& states, const OedometerOptions& options = {},
                                  std::optional<PlateHistory> history = std::nullopt);

/// V_S = Σ 4/3 π r³ of the particles [m³].
double solid_volume(const Particles& particles);

}  // namespace demsa::postprocess
