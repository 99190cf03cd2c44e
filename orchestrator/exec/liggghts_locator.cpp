#include "orchestrator/exec/liggghts_locator.hpp"

#include "orchestrator/experiments/physics.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "orchestrator/util/process.hpp"

#include <fmt/core.h>

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
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

LiggghtsInfo parse_liggghts_help(const std::string& executable, const std::string& help) {
  LiggghtsInfo info{executable, "", {}};
  const std::string head = help.substr(0, 4096);
  static const std::regex version_re(R"(LIGGGHTS[^\n]*?Version[^\n]*?([0-9]+\.[0-9]+(\.[0-9]+)?))");
  std::smatch m;
  if (std::regex_search(head, m, version_re)) info.version = m[1].str();
  // "* Rolling models for pair gran:", a blank line, then names in columns up to the next blank line.
  const std::string heading = "* Rolling models for pair gran:";
  const std::size_t at = help.find(heading);
  if (at == std::string::npos) return info;
  std::istringstream in(help.substr(at + heading.size(), 4096));
  std::string line;
  bool started = false;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string word;
    bool any = false;
    while (words >> word) {
      any = true;
      info.rolling_models.push_back(word);
    }
    if (any)
      started = true;
    else if (started)
      break;
  }
  return info;
}

LiggghtsInfo query_liggghts_at(const std::string& executable) {
  static std::mutex mutex;
  static std::map<std::string, LiggghtsInfo> known;
  const std::lock_guard lock(mutex);
  if (const auto it = known.find(executable); it != known.end()) return it->second;
  // `liggghts -h` prints its banner and the compiled styles and models, and exits 1 (stdin is /dev/null: it never
  // waits for input). Run from its argv, not through a shell, so that any path works; a LIGGGHTS that hangs is not
  // worth waiting for. LAMMPS, and LIGGGHTS with it, opens its log file before it reads -h: `-log none` (LAMMPS's
  // "Command-line options": no log file) keeps it from leaving log.liggghts where demsa was started.
  util::CaptureOptions options;
  options.merge_stderr = true;
  options.timeout = std::chrono::seconds(30);
  const util::CaptureResult r = util::run_capture({executable, "-log", "none", "-h"}, options);
  return known[executable] = parse_liggghts_help(executable, r.out);
}

std::optional<LiggghtsInfo> query_liggghts() {
  const auto exe = find_liggghts_executable();
  if (!exe) return std::nullopt;
  return query_liggghts_at(*exe);
}

fs::path liggghts_cache_dir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg == '/') return fs::path(xdg) / "demsa";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return fs::path(home) / ".cache" / "demsa";
  return {};
}

std::optional<std::string> cached_liggghts_executable() {
  const fs::path dir = liggghts_cache_dir();
  std::error_code ec;
  if (dir.empty() || !fs::is_directory(dir, ec)) return std::nullopt;
  std::optional<std::string> newest;
  fs::file_time_type newest_time{};
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    // A build in progress (".tmp") and the bench's build without the compiled viscous kernel ("-generic") are skipped.
    if (name.rfind("liggghts-", 0) != 0 || name.find(".tmp") != std::string::npos ||
        name.find("-generic") != std::string::npos)
      continue;
    const fs::path stamp = e.path() / "demsa-liggghts.txt";
    const fs::path exe = e.path() / "bin" / "liggghts";
    if (!fs::exists(stamp, ec) || ::access(exe.c_str(), X_OK) != 0) continue;
    const fs::file_time_type t = fs::last_write_time(stamp, ec);
    if (!newest || t > newest_time) {
      newest = exe.string();
      newest_time = t;
    }
  }
  return newest;
}

void resolve_liggghts(study::StudyConfig& config, bool refuse) {
  using study::RollingModel;
  const study::RunSettings defaults;
  const RollingModel model = config.contact.rolling_model;
  const std::string name(study::rolling_model_name(model));
  // `cdt` is in every LIGGGHTS 3.x: nothing to ask. The build of scripts/build-liggghts.sh runs it by the same
  // trajectories as Debian's, bit for bit, and faster (docs/explanation/benchmarks.md, "Profile-guided and link-time
  // optimisation": about 1.29x on the quickstart's cases), so it is the default when it is built; else the `liggghts`
  // on PATH, as before.
  if (model == RollingModel::cdt) {
    if (config.run.liggghts == defaults.liggghts)
      if (const std::optional<std::string> built = cached_liggghts_executable()) config.run.liggghts = *built;
    return;
  }
  std::optional<std::string> exe;
  std::string source;
  if (config.run.liggghts != defaults.liggghts) {
    exe = find_on_path(config.run.liggghts);
    source = "[run] liggghts";
  } else if (const char* env = std::getenv("DEMSA_LIGGGHTS"); env != nullptr && *env != '\0') {
    exe = find_on_path(env);
    source = "$DEMSA_LIGGGHTS";
  } else if ((exe = cached_liggghts_executable())) {
    source = "the cache " + liggghts_cache_dir().string();
  } else {
    exe = find_on_path("liggghts");
    source = "PATH";
  }
  if (!exe) return;  // the run reports a missing executable as it always did
  config.run.liggghts = *exe;

  const std::string how =
      "build LIGGGHTS with it by scripts/build-liggghts.sh (docs/how-to/viscous-liggghts.md); "
      "demsa then finds it in " +
      liggghts_cache_dir().string() + ", or name it by [run] liggghts or $DEMSA_LIGGGHTS";
  std::string problem;
  const LiggghtsInfo info = query_liggghts_at(*exe);
  if (!info.rolling_models.empty() &&
      std::find(info.rolling_models.begin(), info.rolling_models.end(), name) == info.rolling_models.end()) {
    std::string models;
    for (const std::string& m : info.rolling_models) models += (models.empty() ? "" : ", ") + m;
    problem = fmt::format(
        "[contact] rolling_model = \"{}\": the LIGGGHTS found through {} ({}) has only the rolling "
        "models {}; {}",
        name, source, *exe, models, how);
  } else if (const std::string driver = experiments::of(config).driver_command(config);
             model == RollingModel::viscous && !driver.empty() && !experiments::liggghts_library_dir(*exe)) {
    problem = fmt::format(
        "[contact] rolling_model = \"viscous\" with a case that demsa runs in-process (`demsa {}`, the {}'s "
        "settings): it needs the LIGGGHTS library of the same build, which {} ({}) does not come with; {}",
        driver, config.experiment, source, *exe, how);
  }
  if (problem.empty()) return;
  if (refuse) throw util::UserError(config.file.string(), 0, problem);
  util::log::warn("{}", problem);
}

}  // namespace demsa::exec
