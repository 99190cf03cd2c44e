#pragma once
// Cancellation of the long loops of demsa::sobol (bootstrap resamples, metamodel refits, QMC evaluation): the caller
// hands in a check that the loops poll between steps; once it returns true they throw Stopped. The library knows
// nothing of signals: the caller's check may read a signal flag, a deadline or a test's counter.
#include <functional>
#include <stdexcept>

namespace demsa::sobol {

/// Polled between steps of a long loop; true asks the loop to stop. An empty function never stops.
using StopCheck = std::function<bool()>;

/// Thrown by a loop whose StopCheck returned true. No result is returned, and nothing was written.
class Stopped : public std::runtime_error {
 public:
  Stopped() : std::runtime_error("stopped on request") {}
};

/// Throws Stopped when `stop` is set and returns true.
inline void throw_if_stopped(const StopCheck& stop) {
  if (stop && stop()) throw Stopped();
}

}  // namespace demsa::sobol
