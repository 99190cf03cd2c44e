#include "orchestrator/exec/liggghts_locator.hpp"

#include <unistd.h>
#include <array>
#include <cstdio>
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
  // `liggghts -h` prints its banner and exits 1; stdin from /dev/null so that it never waits for input.
  const std::string command = "'" + *exe + "' -h </dev/null 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return info;
  std::array<char, 512> buffer{};
  std::string head;
  while (head.size() < 4096 && std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) head += buffer.data();
  ::pclose(pipe);
  static const std::regex version_re(R"(LIGGGHTS[^\n]*?Version[^\n]*?([0-9]+\.[0-9]+(\.[0-9]+)?))");
  std::smatch m;
  if (std::regex_search(head, m, version_re)) info.version = m[1].str();
  return info;
}

}  // namespace demsa::exec
