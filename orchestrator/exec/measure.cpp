#include "orchestrator/exec/measure.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"

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

}  // namespace demsa::exec
