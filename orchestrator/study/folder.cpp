#include "orchestrator/study/folder.hpp"

#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

namespace demsa::study {

using namespace demsa::util;

void require_study_folder(const std::filesystem::path& dir) {
  if (!std::filesystem::exists(dir / k_frozen_study) || !std::filesystem::exists(dir / k_store_file))
    throw util::UserError(fmt::format("{}: not a study folder (no {} and {}); run `demsa run` first", dir.string(),
                                      k_frozen_study, k_store_file));
}

std::unique_ptr<StudyLock> hold_study_for_results(const std::filesystem::path& dir) {
  require_study_folder(dir);
  try {
    return std::make_unique<StudyLock>(dir);
  } catch (const util::IoError&) {
    if (const long pid = StudyLock::holder(dir))
      throw util::UserError(
          fmt::format("{}: another demsa (pid {}) is running this study; wait for it or stop it", dir.string(), pid));
    return nullptr;
  }
}

std::filesystem::path case_dir(const std::filesystem::path& study_dir, int sample) {
  return study_dir / k_cases_folder / fmt::format("{:06d}", sample);
}

}  // namespace demsa::study
