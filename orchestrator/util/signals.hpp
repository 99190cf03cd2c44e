#pragma once
// SIGINT and SIGTERM as a flag that long loops poll (the study runner, the analysis).
#include <csignal>

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

}  // namespace demsa::util
