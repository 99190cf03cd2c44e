#pragma once
// The store of a study folder opened for its study file (runner.cpp's run_study, open_study.cpp's extend_study).
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"

#include <filesystem>

namespace demsa::exec {

/// Opens the store of `dir` for `config` (read from `study_file`): creates design, samples and design.csv on a new
/// study (`new_study`: the folder's earlier files removed first), adds the points of a grown design or grown
/// replicates, refuses a changed design-relevant setting; the study file becomes the folder's frozen copy.
study::Store open_study(const study::StudyConfig& config, const std::filesystem::path& study_file,
                        const std::filesystem::path& dir, bool new_study);

}  // namespace demsa::exec
