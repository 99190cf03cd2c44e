#pragma once
// The paper's force-driven load plate for the oedometer (§4), run in-process through LIGGGHTS's library
// interface (library.h, loaded at run time: liggghts_library.hpp): `demsa drive-oedometer CASE_DIR`, started by the
// case's run.sh under mpirun.
//
// For every load L_n: back the state up (write_restart), move the plate down by the trial step δ over n_s steps
// (fix move/mesh), and read the plate force F. While F ≤ L_n the trial is kept and the next one starts. When
// F > L_n the system relaxes for n_L steps; |F − L_n| ≤ R_pr ends the load; F < L_n keeps the trial; F > L_n
// restores the backup (clear + read_restart + oedometer_restore.liggghts) and shrinks the trial step,
// δ ← max(floor·δ_T0, δ · m_T · L_n / (L_n + R)) with R = |F − L_n|: the paper's reduction factor m_T, adjusted
// to the residual so that a large overshoot shrinks the step more.
#include <filesystem>
#include <string>
#include <vector>

namespace demsa::experiments::oedometer {

/// The trial-step settings of a case, as its case.json records them (paper §4 constants by default).
struct TrialStepOptions {
  std::vector<double> loads;  ///< L_n [N]
  double tolerance = 0.03;    ///< R_pr [N]
  long trial_steps = 15000;   ///< n_s
  long relax_steps = 80000;   ///< n_L
  double reduction = 0.95;    ///< m_T
  double step0 = 0.0075e-3;   ///< δ_T0 [m]
  double floor = 0.05;        ///< minimum δ as a fraction of δ_T0
  int max_trials = 2000;      ///< per load
  double dt = 0.0;            ///< time step [s]
};

/// Reads the options from CASE_DIR/case.json; throws util::UserError when it is missing or not a trial-step case.
TrialStepOptions read_trial_step_options(const std::filesystem::path& case_dir);

/// The next trial step after an overshoot with residual `residual` at load `load`.
double reduced_trial_step(const TrialStepOptions& options, double step, double load, double residual);

/// Runs the case in `case_dir` (in.liggghts sets up and settles; then the loop above) and writes
/// plate_history.txt (one row per trial: step load_N plate_z_m force_N trial delta_m accepted, where `step`
/// counts every integration step since loading began, restored ones included), plate_states.txt and
/// oedometer_final.dump. Loads the LIGGGHTS library (load_liggghts_library) and initialises and finalises its MPI.
/// Returns 0 when every load converged, 1 otherwise.
int drive_oedometer(const std::filesystem::path& case_dir);

}  // namespace demsa::experiments::oedometer
