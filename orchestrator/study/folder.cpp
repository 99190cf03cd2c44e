#include "orchestrator/study/folder.hpp"

#include <fmt/core.h>

namespace demsa::study {

using namespace demsa::util;

std::filesystem::path case_dir(const std::filesystem::path& study_dir, int sample) {
  return study_dir / k_cases_folder / fmt::format("{:06d}", sample);
}

}  // namespace demsa::study
