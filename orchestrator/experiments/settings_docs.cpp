#include "orchestrator/experiments/settings_docs.hpp"

#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/settings.hpp"

namespace demsa::experiments {

std::optional<std::string> with_settings_table(const std::string& docs) {
  const std::string begin = "<!-- settings-table:begin -->\n";
  const std::string end = "\n<!-- settings-table:end -->";
  const std::size_t b = docs.find(begin);
  const std::size_t e = docs.find(end);
  if (b == std::string::npos || e == std::string::npos || e < b) return std::nullopt;
  return docs.substr(0, b + begin.size()) + settings_table().markdown() + docs.substr(e);
}

}  // namespace demsa::experiments
