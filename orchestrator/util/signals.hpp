#pragma once
// SIGINT and SIGTERM as a flag that long loops poll (the study runner, the analysis).
#include <csignal>
#include <stdexcept>

namespace demsa::util {

/// Set by SIGINT/SIGTERM once install() has been called. The only process-wide state of demsa: a signal handler
/// can reach nothing else.
class StopFlag {
 public:
  /// Installs handlers for SIGINT and SIGTERM that set the flag (first signal) and restore the default action
  /// (so a second Ctrl-C ends demsa at once).
  static void install();
  static bool raised();
  static int signal_number();  ///< the signal received, 0 if none
  static void reset();         ///< for tests
};

/// Thrown by a long loop of case writing (drawing an assembly, a mesh, a data file) once StopFlag is raised: what it
/// wrote is removed on the way out (cases/case_writer.cpp), and run_cli() returns 128 + the signal.
class StopRequested : public std::runtime_error {
 public:
  StopRequested() : std::runtime_error("stopped by a signal") {}
};

/// Throws StopRequested when StopFlag is raised; polled every `every` iterations by `counter`'s owner (cheap enough
/// to call on every iteration).
inline void throw_if_stop_raised() {
  if (StopFlag::raised()) throw StopRequested();
}

}  // namespace demsa::util
