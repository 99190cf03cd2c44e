#include "orchestrator/util/process.hpp"

namespace demsa::util {

std::filesystem::path self_executable() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path("demsa") : exe;
}

}  // namespace demsa::util
