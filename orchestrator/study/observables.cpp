#include "orchestrator/study/observables.hpp"

#include "orchestrator/study/parameters.hpp"

namespace demsa::study {

std::vector<std::string> observable_names(const StudyConfig& config) {
  if (config.experiment == Experiment::pile) return {std::string(k_angle), std::string(k_pile_height)};
  std::vector<std::string> names;
  for (std::size_t i = 1; i < config.oedometer.loads.size(); ++i) names.push_back(settlement_name(i));
  if (!config.oedometer.measured_settlements.empty()) names.emplace_back(k_settlement_error);
  return names;
}

}  // namespace demsa::study
