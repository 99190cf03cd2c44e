#pragma once
// The LIGGGHTS templates of liggghts_templates/, compiled into demsa (see orchestrator/CMakeLists.txt), so that
// cases are written from the templates of the demsa that writes them.
#include <map>
#include <string>

namespace demsa::experiments {

/// File name (e.g. "pile.liggghts") -> text.
const std::map<std::string, std::string>& embedded_templates();

}  // namespace demsa::experiments
