#pragma once
// One case run outside the design, at a unit-cube point, through the study's local executor settings: the
// verification of a calibration.
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/observables.hpp"

#include <filesystem>
#include <vector>

namespace demsa::exec {

/// Writes the case for `unit` (ordered as config.parameters) into `folder` (emptied first, so that no dump of an
/// earlier run is measured by mistake), runs it with the local executor and measures it. A failed run or
/// measurement is reported in study::PointRun::error, not thrown.
study::PointRun run_point(const study::StudyConfig& config, const std::filesystem::path& folder,
                          const std::vector<double>& unit);

}  // namespace demsa::exec
