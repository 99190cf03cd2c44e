#include "orchestrator/study/observables.hpp"

#include <fmt/core.h>

namespace demsa::study {

std::vector<std::string> observable_names(const StudyConfig& config) {
  if (config.experiment == Experiment::pile) return {"angle", "pile_height"};
  std::vector<std::string> names;
  for (std::size_t i = 1; i < config.oedometer.loads.size(); ++i) names.push_back(fmt::format("settlement_{}", i));
  if (!config.oedometer.measured_settlements.empty()) names.push_back("settlement_error");
  return names;
}

}  // namespace demsa::study
