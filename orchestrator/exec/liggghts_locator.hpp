#pragma once
// Finding the LIGGGHTS executable and asking it for its version at run time.
#include <optional>
#include <string>

namespace demsa::exec {

struct LiggghtsInfo {
  std::string executable;  ///< absolute path of the executable found
  std::string version;     ///< e.g. "3.8.0", from the first line of `liggghts -h`; empty if it could not be read
};

/// The executable named by $DEMSA_LIGGGHTS, else `liggghts` on $PATH; nullopt when neither exists.
std::optional<std::string> find_liggghts_executable();

/// Runs `<exe> -h` (util::run_capture, no shell) and reads "LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, ...)".
/// nullopt when LIGGGHTS is missing; an empty version when it could not be read. Throws util::InternalError when
/// the program cannot be started (fork).
std::optional<LiggghtsInfo> query_liggghts();

/// Absolute path of `name` on $PATH (or `name` itself when it contains a '/' and is executable).
std::optional<std::string> find_on_path(const std::string& name);

}  // namespace demsa::exec
