#pragma once
// The observables of a finished case folder (paper §3.3 for the pile, §4 for the oedometer).
#include "orchestrator/study/config.hpp"

#include <filesystem>
#include <map>
#include <string>

namespace demsa::exec {

/// Measures the observables of a finished case folder (pile: angle of repose and pile height; oedometer:
/// settlements per load after the first). Throws postprocess::ParseError / InputError on a dump or plate file
/// that cannot be measured.
std::map<std::string, double> measure_case(const study::StudyConfig& config, const std::filesystem::path& folder);

}  // namespace demsa::exec
