#pragma once
// docs/reference/study-file.md's key-by-key reference is settings_table().markdown() between two markers: the one
// splice that the build's generator (orchestrator/study_file_docs.cpp) writes and the test of the docs checks.
#include <optional>
#include <string>

namespace demsa::experiments {

/// `docs` (the text of docs/reference/study-file.md) with what lies between `<!-- settings-table:begin -->` and
/// `<!-- settings-table:end -->` replaced by the settings table's markdown; nothing when a marker is missing.
std::optional<std::string> with_settings_table(const std::string& docs);

}  // namespace demsa::experiments
