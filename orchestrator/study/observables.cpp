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

}  // namespace demsa::study
