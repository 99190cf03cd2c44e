#pragma once
// The one list of experiments (experiment.hpp): the rest of demsa finds an experiment here, by its name, and asks its
// descriptor. The full settings table of the study file (the core sections of study/settings.hpp and every
// experiment's own) is built here too, so reading a study file goes through this header.
#include "orchestrator/experiments/experiment.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/parameters.hpp"
#include "orchestrator/study/settings.hpp"

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::experiments {

/// Every experiment, in the order the docs list them.
const std::vector<const Experiment*>& all();

/// The experiment named `name`, or nullptr.
const Experiment* find(std::string_view name);

/// The experiment of a study: the one its `[study] experiment` names (the parser accepts no other).
const Experiment& of(const study::StudyConfig& config);

/// The experiment a case.json names; throws util::UserError naming the file when it names none demsa knows.
const Experiment& of_case(const nlohmann::json& case_json, const std::filesystem::path& file);

/// The experiment that measures laboratory files with the extension of `file` (case-insensitive), or nullptr.
const Experiment* for_lab_file(const std::filesystem::path& file);

/// The settings table of the study file: the core sections and every experiment's own.
const study::SettingsTable& settings_table();

/// Reads and validates a study file through settings_table() (study::SettingsTable::load).
study::StudyConfig load_study(const std::filesystem::path& file);
/// Parses study text through settings_table(); `file` names it in messages.
study::StudyConfig parse_study(const std::string& text, const std::filesystem::path& file);

/// The observables a study analyses, in table order (its experiment's observables()).
std::vector<std::string> observable_names(const study::StudyConfig& config);

/// The label, unit and display factor of an observable name of any experiment; a name no experiment knows is its own
/// label, without unit.
study::Observable describe_observable(std::string_view name);

/// The unsettled samples of `observables` (study::unsettled_samples) as a list for people: "3 (angle_drift −4.21 °/s),
/// 7", each with the drifts it stored (study::k_drift_suffix) and their units; "" when there are none.
std::string unsettled_text(const std::map<int, std::map<std::string, double>>& observables);

}  // namespace demsa::experiments
