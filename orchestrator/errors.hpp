#pragma once
// Errors a user can cause (STYLE.md §4). The message already names the user's file, line and value; the one
// top-level catch in run_cli() prints it as "demsa: error: ..." and exits with k_exit_usage.
#include <stdexcept>
#include <string>

namespace demsa {

/// Exit statuses of every demsa command (DESIGN.md §3).
inline constexpr int k_exit_ok = 0;
inline constexpr int k_exit_check_failed = 1;  ///< compare beyond tolerance, failures left in a study
inline constexpr int k_exit_usage = 2;         ///< usage or input error

/// A mistake in the user's input: a study file, a CSV, a dump, a command-line value.
class UserError : public std::runtime_error {
 public:
  explicit UserError(const std::string& message) : std::runtime_error(message) {}
  /// "file:line: message" (line 0 = no line).
  UserError(const std::string& file, int line, const std::string& message)
      : std::runtime_error(line > 0 ? file + ":" + std::to_string(line) + ": " + message : file + ": " + message) {}
};

}  // namespace demsa
