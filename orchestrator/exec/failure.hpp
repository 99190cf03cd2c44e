#pragma once
// Why a case failed, from how its process ended (CaseExit) and the files it left in its folder. Shared by every
// executor's user, the study runner: one classification for local and SLURM runs alike.
//
// The checks run in this order and the first that applies wins, so a class names the most specific cause:
//   timeout, cancelled/lost (not failures: `none` with requeue), signal, LIGGGHTS ERROR line, kinetic-energy
//   blow-up or NaN in the thermo output, non-zero exit, missing or truncated dump, lost particles above the
//   threshold, then the experiment's own output checks (an oedometer's plate not converged).
// The files are read by the postprocess readers, the ones the measurement uses (liggghts_log.hpp, dump.hpp,
// oedometer.hpp): a final dump or plate_states.txt they refuse, or that was cut, is `missing_dump` here rather
// than `measurement` later.
// `measurement` is set by the runner when the case ran cleanly but its observable could not be measured.
#include "orchestrator/exec/executor.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/failure_class.hpp"

#include <filesystem>
#include <string>

namespace demsa::exec {

using study::FailureClass;

struct FailureOptions {
  /// The case's study: its experiment (experiments/registry.hpp) names the final dump, counts the particles removed
  /// on purpose and checks its other outputs (an oedometer's plate_states.txt). Must not be null.
  const study::StudyConfig* config = nullptr;
  long expected_particles = 0;        ///< particles the case creates; 0 = do not check lost particles
  double lost_fraction = 0.01;        ///< lost / expected above this fails the case, [0, 1]
  double kinetic_energy_limit = 0.0;  ///< kinetic energy above this [J] is a blow-up; 0 = only NaN/inf
  int tail_lines = 30;                ///< lines of log kept in the report, >= 1
  void validate() const;              ///< throws std::invalid_argument naming the field
};

struct FailureReport {
  FailureClass failure = FailureClass::none;
  bool requeue = false;  ///< cancelled or lost: not a failure, the case must run again (same attempt)
  /// The case's own check of its settings stopped it (a `demsa: ...` stop of its input script, such as "the pile has
  /// reached the insertion height (raise fill_height)"): it follows from the settings, so a retry ends the same way.
  /// Retries are for crashes and time-outs.
  bool final = false;
  std::string message;   ///< one line for humans ("" when none)
  std::string log_tail;  ///< last lines of log.liggghts (or run.out/screen.txt when that says more)
};

/// Classifies one finished case. Reads log.liggghts, screen.txt, run.out, the final dump and what the experiment
/// checks (an oedometer's plate_states.txt) in `folder`. A missing or malformed file is a failure class, not an
/// exception.
FailureReport classify_case(const CaseExit& exit, const std::filesystem::path& folder, const FailureOptions& options);

/// The last `lines` lines of a text file ("" when it does not exist).
std::string file_tail(const std::filesystem::path& file, int lines);

}  // namespace demsa::exec
