#include "orchestrator/util/log.hpp"

#include <cstdio>

namespace demsa::util::log {

void write(const char* level, const std::string& message) {
  // One fputs per line: lines of concurrent writers (the runner and a signal-time message) do not interleave.
  const std::string line = fmt::format("demsa: {}: {}\n", level, message);
  std::fputs(line.c_str(), stderr);
  std::fflush(stderr);
}

}  // namespace demsa::util::log
