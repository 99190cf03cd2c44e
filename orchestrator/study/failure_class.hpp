#pragma once
// Why a case failed: the classes exec/failure.hpp assigns and the store keeps (runs.failure), with their names
// (the enum <-> string pairs of one table, after Ceres's types.cc).
#include <string>

namespace demsa::study {

enum class FailureClass {
  none,                 ///< ran cleanly
  nonzero_exit,         ///< run.sh exited with a status other than 0, no more specific cause found
  signal,               ///< run.sh killed by a signal, or exit status 128+N (a shell reporting a killed child)
  timeout,              ///< exceeded the per-case time limit
  liggghts_error,       ///< an `ERROR:` line in the LIGGGHTS log or screen output
  lost_particles,       ///< more particles lost than RunSettings::lost_fraction allows
  energy_blowup,        ///< kinetic energy NaN, infinite or above the limit
  missing_dump,         ///< the final dump (or plate states) is missing or truncated
  plate_not_converged,  ///< oedometer: a load step was not reached
  measurement,          ///< ran cleanly, but the observable could not be measured from the dump
};

/// "none", "nonzero-exit", "signal", "timeout", "liggghts-error", "lost-particles", "energy-blowup",
/// "missing-dump", "plate-not-converged", "measurement".
std::string to_string(FailureClass value);
/// Inverse of to_string(); throws std::invalid_argument listing the valid names.
FailureClass failure_class_from_string(const std::string& name);

}  // namespace demsa::study
