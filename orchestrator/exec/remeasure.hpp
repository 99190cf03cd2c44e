#pragma once
// A study's cases as the runner writes them, and a study measured again after its study file changed only how cases
// are measured (a drum's stations, a pile's angle options): the finished cases' files are measured again instead of
// being run again, since their LIGGGHTS inputs are the same.
#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace demsa::exec {

/// One case of the study: a design sample, or a replicate of one (another assembly seed).
struct StudyCase {
  study::SampleRow sample;                       ///< its id and point
  std::optional<study::ReplicateRow> replicate;  ///< set for a replicate case
};

/// Every case of the store by its id (the design's samples, then the replicate cases); `order` (when given) receives
/// their ids in the order they run.
std::map<int, StudyCase> study_cases(const study::Store& store, std::vector<int>* order = nullptr);

/// What write_case needs to write `study_case` of `config`.
cases::CaseRequest case_request(const study::StudyConfig& config, const StudyCase& study_case);

/// What remeasure_study did.
struct RemeasureSummary {
  int measured = 0;               ///< finished cases measured again
  int failed = 0;                 ///< of them, those whose measurement fails under the new settings
  int recovered = 0;              ///< cases whose measurement had failed and that are measured now
  std::vector<std::string> keys;  ///< the settings that changed, "[section] key: BEFORE -> AFTER"
};

/// Measures again, under `config`, every finished case of the study in `dir` whose latest run is done or failed in its
/// measurement, after checking that `config` writes each of them exactly as it was run (every file but case.json
/// byte-identical), then records the results and `config`'s design hash in one transaction (Store::record_remeasured)
/// and each case's new case.json. `changed` lists the changed settings for the event. Throws util::UserError, with
/// nothing changed, when a case would be written differently or a case that was done can no longer be read (its
/// files removed): those need `demsa run --new`.
RemeasureSummary remeasure_study(const study::StudyConfig& config, study::Store& store,
                                 const std::filesystem::path& dir, const std::vector<std::string>& changed);

}  // namespace demsa::exec
