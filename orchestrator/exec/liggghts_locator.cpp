#include "orchestrator/exec/liggghts_locator.hpp"

#include "orchestrator/util/process.hpp"

#include <unistd.h>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>

namespace demsa::exec {

namespace fs = std::filesystem;

std::optional<std::string> find_on_path(const std::string& name) {
  if (name.find('/') != std::string::npos) {
    if (::access(name.c_str(), X_OK) == 0) return fs::absolute(name).string();
    return std::nullopt;
  }
  const char* path = std::getenv("PATH");
  if (path == nullptr) return std::nullopt;
  std::stringstream ss(path);
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    if (dir.empty()) continue;
    const fs::path candidate = fs::path(dir) / name;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return std::nullopt;
}

std::optional<std::string> find_liggghts_executable() {
  if (const char* env = std::getenv("DEMSA_LIGGGHTS"); env != nullptr && *env != '\0') return find_on_path(env);
  return find_on_path("liggghts");
}

std::optional<LiggghtsInfo> query_liggghts() {
  const auto exe = find_liggghts_executable();
  if (!exe) return std::nullopt;
  LiggghtsInfo info{*exe, ""};
  // `liggghts -h` prints its banner and exits 1 (stdin is /dev/null: it never waits for input). Run from its argv,
  // not through a shell, so that any path works; a LIGGGHTS that hangs is not worth waiting for.
  util::CaptureOptions options;
  options.merge_stderr = true;
  options.timeout = std::chrono::seconds(30);
  const util::CaptureResult r = util::run_capture({*exe, "-h"}, options);
  const std::string head = r.out.substr(0, 4096);
  static const std::regex version_re(R"(LIGGGHTS[^\n]*?Version[^\n]*?([0-9]+\.[0-9]+(\.[0-9]+)?))");
  std::smatch m;
  if (std::regex_search(head, m, version_re)) info.version = m[1].str();
  return info;
}

}  // namespace demsa::exec
