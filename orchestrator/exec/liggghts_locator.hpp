#pragma once
// Finding the LIGGGHTS executable and asking it for its version and rolling models at run time.
#include "orchestrator/study/config.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demsa::exec {

struct LiggghtsInfo {
  std::string executable;  ///< absolute path of the executable found
  std::string version;     ///< e.g. "3.8.0", from the first line of `liggghts -h`; empty if it could not be read
  /// The names under "* Rolling models for pair gran:" of `liggghts -h` (the models compiled in; LIGGGHTS's
  /// Make.sh registers every ROLLING_MODEL of src/rolling_model_*.h there); empty if the list could not be read.
  std::vector<std::string> rolling_models;
};

/// The executable named by $DEMSA_LIGGGHTS, else `liggghts` on $PATH; nullopt when neither exists.
std::optional<std::string> find_liggghts_executable();

/// Runs `<exe> -h` (util::run_capture, no shell) and reads "LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, ...)".
/// nullopt when LIGGGHTS is missing; an empty version when it could not be read. Throws util::InternalError when
/// the program cannot be started (fork).
std::optional<LiggghtsInfo> query_liggghts();

/// The same for one executable (asked once per process: the answer is remembered).
LiggghtsInfo query_liggghts_at(const std::string& executable);

/// Reads the version and the rolling models from the text of `liggghts -h`.
LiggghtsInfo parse_liggghts_help(const std::string& executable, const std::string& help);

/// Absolute path of `name` on $PATH (or `name` itself when it contains a '/' and is executable).
std::optional<std::string> find_on_path(const std::string& name);

/// Where scripts/build-liggghts.sh builds: ${XDG_CACHE_HOME:-$HOME/.cache}/demsa.
std::filesystem::path liggghts_cache_dir();

/// bin/liggghts of the newest complete build in liggghts_cache_dir() (a `liggghts-*` prefix holding
/// `demsa-liggghts.txt`, which the script writes last); nullopt when there is none.
std::optional<std::string> cached_liggghts_executable();

/// The LIGGGHTS a study runs: `[run] liggghts` when set (not the default "liggghts"), else (but for `cdt`, which
/// every LIGGGHTS has) $DEMSA_LIGGGHTS, else the cached build of scripts/build-liggghts.sh (the faster, with the same
/// trajectories: docs/explanation/benchmarks.md), else `liggghts` on $PATH. Sets config.run.liggghts to it (an absolute
/// path when found). With `refuse`, throws util::UserError naming the study file and `[contact] rolling_model` when the
/// executable's `-h` lists rolling models without the study's (or when a `viscous` study would drive the trial-step
/// plate in-process without the library of that build), saying how to get one (scripts/build-liggghts.sh); without it,
/// logs a warning instead.
void resolve_liggghts(study::StudyConfig& config, bool refuse);

}  // namespace demsa::exec
