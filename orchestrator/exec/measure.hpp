#pragma once
// The observables of a finished case folder (paper §3.3 for the pile, §4 for the oedometer).
#include "orchestrator/study/config.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <string>

namespace demsa::exec {

/// How the settling of a pile ended, as pile.liggghts writes it to pile_settling.txt (`key value` lines).
struct PileSettling {
  bool criterion = false;     ///< the settling criterion was on ([pile] settle_speed > 0)
  bool settled = false;       ///< ... and met before settle_time
  long end_step = 0;          ///< step at which settling ended
  double fastest = 0.0;       ///< fastest particle on the pedestal then [m/s]
  double speed_limit = 0.0;   ///< the criterion's speed [m/s]
  long on_pedestal = 0;       ///< particles on the pedestal then
  long fast_on_pedestal = 0;  ///< ... of them faster than speed_limit
  long removed = 0;           ///< particles removed off the pedestal during the run
};

/// Reads FOLDER/pile_settling.txt; nothing when the file does not exist. Throws postprocess::ParseError (file:line)
/// on a line that is not `key number` or a missing key.
std::optional<PileSettling> read_pile_settling(const std::filesystem::path& folder);

/// Measures the observables of a finished case folder (pile: angle of repose and pile height; oedometer:
/// settlements per load after the first; a pile also stores k_settled and k_removed_off_pedestal from
/// pile_settling.txt). Throws postprocess::ParseError / InputError on a dump or plate file
/// that cannot be measured.
std::map<std::string, double> measure_case(const study::StudyConfig& config, const std::filesystem::path& folder);

}  // namespace demsa::exec
