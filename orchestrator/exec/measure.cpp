#include "orchestrator/exec/measure.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

namespace demsa::exec {

std::map<std::string, double> measure_case(const std::filesystem::path& folder) {
  const nlohmann::json doc = experiments::read_case_json(folder);
  return experiments::of_case(doc, folder / study::k_case_json).measure(folder, doc);
}

CaseMeasurement measure_case_described(const std::filesystem::path& folder) {
  const nlohmann::json doc = experiments::read_case_json(folder);
  const experiments::Experiment& experiment = experiments::of_case(doc, folder / study::k_case_json);
  CaseMeasurement m;
  m.experiment = std::string(experiment.name);
  for (const auto& [name, value] : experiment.measure(folder, doc))
    m.values.push_back({experiments::describe_observable(name), value});
  return m;
}

experiments::LabComparison compare_case_with_lab_file(const std::filesystem::path& folder,
                                                      const std::filesystem::path& file,
                                                      std::filesystem::path picture) {
  const nlohmann::json doc = experiments::read_case_json(folder);
  const experiments::Experiment& experiment = experiments::of_case(doc, folder / study::k_case_json);
  const experiments::Experiment* kind = experiments::for_lab_file(file);
  if (!experiment.compare_with_lab_file || kind != &experiment)
    throw util::UserError(fmt::format("{}: not a laboratory file of a {} case (the case {})", file.string(),
                                      experiment.name, folder.string()));
  if (picture.empty()) picture = folder / "lab_overlay.png";
  return experiment.compare_with_lab_file(folder, doc, file, picture);
}

}  // namespace demsa::exec
