#pragma once
// `demsa status` (docs/reference/command-line.md): a study's counts by state, its failures with their class, the ETA,
// the piles still moving, and its bill (exec/cost.hpp; status never runs LIGGGHTS); on a SLURM study that no demsa
// runs, it first collects the tasks that have ended.
#include "orchestrator/exec/cost.hpp"
#include "orchestrator/study/store.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demsa::exec {

struct StudyStatus {
  std::filesystem::path dir;
  std::string study;                           ///< the study's name
  study::StoreCounts counts;                   ///< runs by state, design and replicate cases apart
  long holder = 0;                             ///< pid of the demsa that runs the study (0: none)
  int collected = 0;                           ///< ended SLURM tasks collected first
  std::vector<study::RunRow> failures;         ///< the latest failed run of each sample not done, by sample
  std::vector<int> unsettled;                  ///< done piles still moving at the end of settling
  std::string unsettled_text;                  ///< their samples as experiments::unsettled_text writes them
  double eta = -1.0;                           ///< seconds left (< 0: unknown)
  std::optional<StudyEstimate> bill;           ///< absent when the study file no longer parses here
  std::vector<study::CaseCostRow> case_costs;  ///< predicted against actual, per done run
};

/// Reads the status of the study in `dir` (collecting ended SLURM tasks first when no demsa runs it: a problem
/// there is a warning, and the status is still read). Throws util::UserError when `dir` is not a study folder.
StudyStatus study_status(const std::filesystem::path& dir);

/// The status as `demsa status --json` prints it.
nlohmann::json study_status_json(const StudyStatus& status);

/// The status as `demsa status` prints it (lines ending in a newline).
std::string study_status_text(const StudyStatus& status);

}  // namespace demsa::exec
