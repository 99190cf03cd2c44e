#include "orchestrator/study/design_file.hpp"

#include <fmt/core.h>

namespace demsa::study {

std::string design_csv(const StudyConfig& config, const std::vector<SampleRow>& samples) {
  std::string text = "sample";
  for (const ParameterRange& p : config.parameters) text += ",u_" + p.name;
  for (const ParameterRange& p : config.parameters) text += "," + p.name;
  text += "\n";
  for (const SampleRow& s : samples) {
    text += std::to_string(s.sample);
    for (double u : s.unit) text += fmt::format(",{:.17g}", u);
    for (double x : s.physical) text += fmt::format(",{:.17g}", x);
    text += "\n";
  }
  return text;
}

}  // namespace demsa::study
