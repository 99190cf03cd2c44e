#pragma once
// `demsa calibrate DIR` (the next step the paper's conclusion names): the contact parameters whose
// metamodel predictions best match measured values.
//
//   1. the done samples of the study (unit-cube points and observables, from DIR/study.db);
//   2. per target observable, every candidate metamodel (the study's [analysis] metamodels, or --model) is fitted
//      and the one with the best leave-one-out Q² is kept;
//   3. NLopt (sobol/calibration.hpp: a global DIRECT-L pass, then BOBYQA from its best point) minimises
//        J(u) = Σ_k w_k ((m_k(u) − t_k) / s_k)²,  u ∈ [0,1]^d,
//      with s_k = |t_k| (a relative misfit, so that an angle in degrees and a settlement in metres weigh alike;
//      the observable's standard deviation over the samples when t_k = 0);
//   4. with verify, the case at the optimum is written (case_writer.hpp) to DIR/calibration/verify and run with
//      the study's local executor settings, and the measured observables are set against the predictions.
// The result goes to DIR/analysis/calibration.json (read back by the report).
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/observables.hpp"
#include "sobol/calibration.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace demsa::analysis {

struct CalibrateOptions {
  std::filesystem::path dir;  ///< study folder (study.toml and study.db)
  /// "NAME=VALUE" per target observable (names as in DIR/analysis/observables.csv). "settlement=V1,V2,..." sets
  /// settlement_1, settlement_2, ... in turn. Empty: the study's own targets (pile: [pile] target_angle;
  /// oedometer: [oedometer] measured_settlements).
  std::vector<std::string> targets;
  std::vector<std::string> weights;  ///< "NAME=W", W >= 0; a target without one has weight 1
  std::string model;                 ///< one metamodel for every target; empty: the best Q² per observable
  bool verify = false;               ///< run the real case at the optimum
  /// How the verification case is run (the CLI passes exec::run_point): writes the case for `unit` into
  /// `folder`, runs it and measures it. Analysis never runs LIGGGHTS itself.
  std::function<study::PointRun(const study::StudyConfig& config, const std::filesystem::path& folder,
                                const std::vector<double>& unit)>
      run_point;
  std::string global = "direct-l";  ///< NLopt global pass (sobol::global_algorithm_from_string)
  std::string local = "bobyqa";     ///< NLopt local pass (sobol::local_algorithm_from_string)
  int global_evaluations = 4000;    ///< budget of the global pass, >= 1
  int local_evaluations = 2000;     ///< budget of the local pass, >= 1
  /// Throws util::UserError naming the option and the value.
  void validate() const;
};

/// One target of a calibration.
struct CalibratedTarget {
  std::string name;                ///< observable
  std::string model;               ///< metamodel used for it
  double q2 = 0.0;                 ///< that metamodel's leave-one-out Q²
  double r2 = 0.0;                 ///< and its R²
  double target = 0.0;             ///< t_k
  double weight = 1.0;             ///< w_k
  double scale = 1.0;              ///< s_k
  double predicted = 0.0;          ///< m_k at the optimum
  std::optional<double> measured;  ///< from the verification run
};

/// Plain data; written to DIR/analysis/calibration.json.
struct CalibrationOutcome {
  std::string study;                    ///< study name
  std::vector<std::string> parameters;  ///< varied parameters, in the study's order
  std::vector<double> low, high;        ///< their ranges (physical)
  std::vector<double> unit;             ///< optimum on the unit cube
  std::vector<double> physical;         ///< optimum in physical units
  std::vector<CalibratedTarget> targets;
  double misfit = 0.0;  ///< J at the optimum
  int samples = 0;      ///< done samples the metamodels were fitted to
  int evaluations = 0;  ///< misfit evaluations
  std::string global_algorithm, local_algorithm;
  std::uint64_t seed = 0;  ///< NLopt's seed (the study seed)
  // verification run
  bool verified = false;             ///< a verification run was made and measured
  std::filesystem::path verify_dir;  ///< its case folder
  std::string verify_error;          ///< why the run or its measurement failed ("" when verified)
  double verify_seconds = 0.0;       ///< wall time of the run [s]
};

/// Runs the calibration (and the verification when asked) and writes DIR/analysis/calibration.json. Throws
/// util::UserError for a folder that is not a study, an unknown observable, a malformed target or weight, too few done
/// samples, or no metamodel that fits.
CalibrationOutcome calibrate_study(const CalibrateOptions& options);

/// calibration.json text of an outcome, and back. read_calibration throws util::UserError naming the file.
std::string calibration_to_json(const CalibrationOutcome& outcome);
CalibrationOutcome read_calibration(const std::filesystem::path& file);

/// A human-readable summary (optimum, predictions against targets, misfit, verification).
std::string calibration_text(const CalibrationOutcome& outcome);

}  // namespace demsa::analysis
