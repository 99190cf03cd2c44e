#pragma once
// The store of a study folder opened for its study file (runner.cpp's run_study, open_study.cpp's extend_study).
#include "orchestrator/exec/remeasure.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"

#include <filesystem>
#include <optional>

namespace demsa::exec {

/// Opens the store of `dir` for `config` (read from `study_file`): creates design, samples and design.csv on a new
/// study (`new_study`: the folder's earlier files removed first), adds the points of a grown design or grown
/// replicates, measures the finished cases again when only measurement settings changed (remeasure_study; the
/// summary in `remeasured`; a `dry_run` measures and writes nothing, the summary lists the changed keys), refuses
/// any other changed design-relevant setting; the study file becomes the folder's frozen copy.
study::Store open_study(const study::StudyConfig& config, const std::filesystem::path& study_file,
                        const std::filesystem::path& dir, bool new_study, bool dry_run = false,
                        std::optional<RemeasureSummary>* remeasured = nullptr);

}  // namespace demsa::exec
