#pragma once
// demsa's one error hierarchy (after ccache's core/exceptions.hpp), caught once, in cli::run_cli():
//
//   Error                 everything demsa throws on purpose
//   ├── UserError         a mistake in the user's input: a study file, a CSV, a dump, a plate file, a
//   │                     command-line value. The message names the file, the line and the value. Exit status 2.
//   └── InternalError     the machine failed demsa: I/O (a full disk, a folder that cannot be written), SQLite,
//       └── IoError       starting a process. Exit status 3.
//
// sobol::InputError and postprocess::ParseError / InputError (libraries that know nothing of demsa's CLI) are
// user errors too; run_cli() maps them once, and any other std::exception is an internal failure.
#include <stdexcept>
#include <string>

namespace demsa::util {

/// Exit statuses of every demsa command (docs/reference/command-line.md, "Exit status").
inline constexpr int k_exit_ok = 0;
inline constexpr int k_exit_check_failed = 1;   ///< compare beyond tolerance, failures left in a study
inline constexpr int k_exit_usage = 2;          ///< usage or input error: the user can fix it
inline constexpr int k_exit_internal = 3;       ///< I/O, SQLite or process failure: the machine failed demsa
inline constexpr int k_exit_signal_base = 128;  ///< 128 + N: stopped by signal N

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// A mistake in the user's input: a study file, a CSV, a dump, a command-line value.
class UserError : public Error {
 public:
  explicit UserError(const std::string& message) : Error(message) {}
  /// "file:line: message" (line 0 = no line).
  UserError(const std::string& file, long line, const std::string& message)
      : Error(line > 0 ? file + ":" + std::to_string(line) + ": " + message : file + ": " + message) {}
};

/// A failure of the machine rather than of the input: SQLite, a process that cannot be started.
class InternalError : public Error {
 public:
  explicit InternalError(const std::string& message) : Error(message) {}
};

/// A file or folder that cannot be read or written; the message names it and says why (strerror).
class IoError : public InternalError {
 public:
  explicit IoError(const std::string& message) : InternalError(message) {}
};

}  // namespace demsa::util
