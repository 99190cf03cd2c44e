#include "orchestrator/study/observables.hpp"

#include "orchestrator/study/parameters.hpp"

namespace demsa::study {

std::vector<int> unsettled_samples(const std::map<int, std::map<std::string, double>>& observables) {
  std::vector<int> samples;
  for (const auto& [sample, values] : observables) {
    const auto it = values.find(std::string(k_settled));
    if (it != values.end() && it->second == 0.0) samples.push_back(sample);
  }
  return samples;
}

std::vector<std::string> observable_names(const StudyConfig& config) {
  if (config.experiment == Experiment::pile) return {std::string(k_angle), std::string(k_pile_height)};
  std::vector<std::string> names;
  for (std::size_t i = 1; i < config.oedometer.loads.size(); ++i) names.push_back(settlement_name(i));
  if (!config.oedometer.measured_settlements.empty()) names.emplace_back(k_settlement_error);
  return names;
}

}  // namespace demsa::study
