#include "orchestrator/study/observables.hpp"

#include "orchestrator/study/parameters.hpp"

#include <cmath>
#include <cstdlib>

namespace demsa::study {

std::optional<TimedName> timed_name(std::string_view name) {
  const std::size_t at = name.rfind('@');
  if (at == std::string_view::npos || at == 0) return std::nullopt;
  TimedName timed{std::string(name.substr(0, at)), std::string(name.substr(at + 1)), 0.0};
  char* end = nullptr;
  timed.time = std::strtod(timed.text.c_str(), &end);
  if (timed.text.empty() || end != timed.text.c_str() + timed.text.size() || !(timed.time >= 0) ||
      !std::isfinite(timed.time))
    return std::nullopt;
  return timed;
}

std::vector<int> unsettled_samples(const std::map<int, std::map<std::string, double>>& observables) {
  std::vector<int> samples;
  for (const auto& [sample, values] : observables) {
    const auto it = values.find(std::string(k_settled));
    if (it != values.end() && it->second == 0.0) samples.push_back(sample);
  }
  return samples;
}

}  // namespace demsa::study
