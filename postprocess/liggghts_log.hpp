#pragma once
// Reading a LIGGGHTS log (`-log log.liggghts`) or its screen output: the version line, the thermo table of every
// run, WARNING and ERROR lines, lost atoms and the loop times.
#include "postprocess/error.hpp"

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace demsa::postprocess {

/// The thermo rows of one `run` (the header line that names the columns, then numeric rows).
struct ThermoBlock {
  long header_line = 0;                   ///< 1-based line of the column header (`Step Atoms KinEng ...`)
  std::vector<std::string> columns;       ///< as written (`Step`, `Atoms`, `KinEng`, `c_rke`, ...)
  std::vector<std::vector<double>> rows;  ///< rows[i][c]

  /// Index of `name` (case-sensitive), or -1.
  int column_index(const std::string& name) const;
  /// Index of the last column that holds kinetic energy, or -1: the thermo keyword `ke` (`KinEng`) or a compute,
  /// variable or fix named ke, vke, kineng or kinetic... (`c_ke`, `v_ke`, `v_kinetic`, `c_KE`; any case).
  int kinetic_energy_column() const;
};

/// One `Loop time of T on P procs for N steps with M atoms` line.
struct LoopSummary {
  long line = 0;
  double seconds = 0.0;
  int procs = 0;
  long steps = 0;
  long atoms = 0;
};

/// A WARNING or ERROR line: its 1-based line and its text after `WARNING: ` / `ERROR: ` (or `ERROR on proc N: `).
struct LogMessage {
  long line = 0;
  std::string text;
};

struct LiggghtsLog {
  std::string version;              ///< e.g. `LIGGGHTS-PUBLIC 3.8.0` (empty when the banner is absent)
  std::vector<ThermoBlock> thermo;  ///< one block per run that printed thermo output
  std::vector<LoopSummary> loops;   ///< one per finished run
  std::vector<LogMessage> warnings;
  std::vector<LogMessage> errors;
  /// Atoms lost: from `Lost atoms: original N current M` when LIGGGHTS printed it, else the sum of every decrease of
  /// the `Atoms` thermo column between consecutive rows (atoms added by create_atoms/insertion are not losses).
  long lost_atoms = 0;
  double loop_seconds = 0.0;                 ///< sum of the loop times
  long steps = 0;                            ///< sum of the steps of the finished runs
  std::optional<double> total_wall_seconds;  ///< `Total wall time: h:mm:ss`, when the log has that line
};

/// Reads the log at `path`. Lines it does not recognise are skipped (a log also echoes the input script); a thermo
/// row that is cut short (a killed run) ends its block. A thermo row is a line of as many numbers as the header
/// names columns, `nan` and `inf` included (a blown-up run prints them). An ERROR line starts, after blanks, with
/// `ERROR:` or `ERROR on proc N:`. Throws ParseError when the file cannot be read, has a line over 1 MiB (binary
/// data, not a log) or is over 1 GiB (every thermo row is kept: stream such a log with scan_thermo).
LiggghtsLog read_liggghts_log(const std::filesystem::path& path);

/// The same from text held in memory.
LiggghtsLog parse_liggghts_log(const std::string& text);

/// One thermo row met by scan_thermo.
struct ThermoRow {
  const ThermoBlock& block;               ///< the header of the row's block (its `rows` stay empty)
  long line;                              ///< 1-based line of the row
  const std::vector<std::string>& words;  ///< the values as written (`1.5e3`, `nan`, `-nan`, `inf`)
  const std::vector<double>& values;      ///< the same parsed, one per column of `block`
};

/// Streams the thermo rows of the log at `path` in file order with the rules of read_liggghts_log, holding one row
/// at a time (a log can be hundreds of MB). `visit` returns false to stop the scan. Throws ParseError when the
/// file cannot be read or has a line over 1 MiB.
void scan_thermo(const std::filesystem::path& path, const std::function<bool(const ThermoRow&)>& visit);

/// The first ERROR line of a LIGGGHTS log, screen output or any text file (the rule of read_liggghts_log), as
/// written without its leading blanks (`ERROR: Lost atoms: ... (../thermo.cpp:407)`); "" when it has none or does
/// not exist. Streams the file; a line over 1 MiB (binary data) ends the search.
std::string first_error_line(const std::filesystem::path& path);

}  // namespace demsa::postprocess
