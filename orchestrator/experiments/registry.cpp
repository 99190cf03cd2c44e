#include "orchestrator/experiments/registry.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/drawdown/drawdown.hpp"
#include "orchestrator/experiments/drum/drum.hpp"
#include "orchestrator/experiments/incline/incline.hpp"
#include "orchestrator/experiments/oedometer/oedometer.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/study/observables.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cctype>

namespace demsa::experiments {

const std::vector<const Experiment*>& all() {
  // The one list: an experiment is one entry here and one folder beside this file (ARCHITECTURE.md).
  // One line each: tests/style/experiment_in_one_place.test.sh counts them.
  // clang-format off
  static const std::vector<const Experiment*> experiments{
      &pile::experiment(),
      &oedometer::experiment(),
      &incline::experiment(),
      &drawdown::experiment(),
      &drum::experiment(),
  };
  // clang-format on
  return experiments;
}

const Experiment* find(std::string_view name) {
  for (const Experiment* e : all())
    if (e->name == name) return e;
  return nullptr;
}

const Experiment& of(const study::StudyConfig& config) {
  const Experiment* e = find(config.experiment);
  assert(e && "a study of an experiment the registry does not hold");
  return *e;
}

const Experiment& of_case(const nlohmann::json& case_json, const std::filesystem::path& file) {
  const std::string name = case_experiment(case_json, file);
  if (const Experiment* e = find(name)) return *e;
  std::vector<std::string> names;
  for (const Experiment* e : all()) names.emplace_back(e->name);
  throw util::UserError(
      file.string(), 0,
      fmt::format("experiment = \"{}\": not an experiment this demsa knows (known: {})", name, util::join(names)));
}

const Experiment* for_lab_file(const std::filesystem::path& file) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const Experiment* e : all())
    for (const std::string_view x : e->lab_file_extensions)
      if (e->measure_lab_file && x == extension) return e;
  return nullptr;
}

const study::SettingsTable& settings_table() {
  static const study::SettingsTable table = [] {
    std::vector<study::SettingSection> experiment_sections;
    std::vector<study::Setting> rows = study::core_settings();
    std::vector<study::ExperimentSchema> schemas;
    for (const Experiment* e : all()) {
      study::ExperimentSchema schema;
      schema.name = std::string(e->name);
      schema.summary = std::string(e->summary);
      for (const study::SettingSection& section : e->sections()) {
        experiment_sections.push_back(section);
        schema.sections.push_back(section.name);
      }
      if (e->check) schema.check = e->check;
      schema.retired_keys = e->retired_keys();
      for (study::Setting& s : e->settings()) {
        assert(std::find(schema.sections.begin(), schema.sections.end(), s.section) != schema.sections.end() &&
               "an experiment's row outside its sections");
        rows.push_back(std::move(s));
      }
      schemas.push_back(std::move(schema));
    }
    return study::SettingsTable(study::core_sections(experiment_sections), std::move(rows), std::move(schemas));
  }();
  return table;
}

study::StudyConfig load_study(const std::filesystem::path& file) { return settings_table().load(file); }

study::StudyConfig parse_study(const std::string& text, const std::filesystem::path& file) {
  return settings_table().parse(text, file);
}

std::vector<std::string> observable_names(const study::StudyConfig& config) {
  std::vector<std::string> names;
  for (const study::Observable& o : of(config).observables(config)) names.push_back(o.name);
  return names;
}

std::string unsettled_text(const std::map<int, std::map<std::string, double>>& observables) {
  std::string text;
  for (const int sample : study::unsettled_samples(observables)) {
    std::string drifts;
    for (const auto& [name, value] : observables.at(sample)) {
      if (!name.ends_with(study::k_drift_suffix)) continue;
      const study::Observable o = describe_observable(name);
      drifts += fmt::format("{}{} {:+.3g}{}", drifts.empty() ? "" : ", ", name, value * o.factor,
                            o.unit.empty() ? "" : fmt::format(" {}", o.unit));
    }
    text += fmt::format("{}{}{}", text.empty() ? "" : ", ", sample, drifts.empty() ? "" : fmt::format(" ({})", drifts));
  }
  return text;
}

study::Observable describe_observable(std::string_view name) {
  for (const Experiment* e : all())
    if (const std::optional<study::Observable> o = e->describe(name)) return *o;
  return {std::string(name), std::string(name), "", 1.0, ""};
}

}  // namespace demsa::experiments
