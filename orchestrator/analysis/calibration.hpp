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
#include "orchestrator/analysis/measured_target.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/observables.hpp"
#include "sobol/calibration.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace demsa::analysis {

struct CalibrateOptions {
  std::filesystem::path dir;  ///< study folder (study.toml and study.db)
  /// The values to match, one per observable (a curve: one per point, settlement_1, settlement_2, ...); their `sd`
  /// is not used, their `study` must be empty or the study's name. Empty: the study's own targets (pile: [pile]
  /// target_angle; oedometer: [oedometer] measured_settlements).
  std::vector<MeasuredTarget> targets;
  /// Weight w_k >= 0 of a target, by observable name; a target without one has weight 1.
  std::map<std::string, double> weights;
  std::string model;    ///< one metamodel for every target; empty: the best Q² per observable
  bool verify = false;  ///< run the real case at the optimum
  /// How the verification case is run (the CLI passes exec::run_point): writes the case for `unit` into
  /// `folder`, runs it and measures it. Analysis never runs LIGGGHTS itself.
  std::function<study::PointRun(const study::StudyConfig& config, const std::filesystem::path& folder,
                                const std::vector<double>& unit)>
      run_point;
  std::string global = "direct-l";  ///< NLopt global pass (sobol::global_algorithm_from_string)
  std::string local = "bobyqa";     ///< NLopt local pass (sobol::local_algorithm_from_string)
  int global_evaluations = 4000;    ///< budget of the global pass, >= 1
  int local_evaluations = 2000;     ///< budget of the local pass, >= 1
  /// Throws util::UserError naming the field ("CalibrateOptions.weights") and the value.
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
  double rmse_loo = 0.0;           ///< the metamodel's leave-one-out RMS error
  /// The observable's range over the done samples (what the study can produce).
  double observed_low = 0.0, observed_high = 0.0;
  int samples = 0;  ///< done samples that measure it
  /// The target lies outside that range and the optimum misses it by more than k_miss_rmse leave-one-out errors:
  /// no parameters in the study's ranges produce it.
  bool contradicted = false;
};

/// How far (in the metamodel's leave-one-out RMS errors, and at least k_miss_span of the observed range) an optimum's
/// prediction may miss a target outside the observed range before the calibration fails its check.
inline constexpr double k_miss_rmse = 3.0;
inline constexpr double k_miss_span = 0.01;

/// Plain data; written to DIR/analysis/calibration.json.
struct CalibrationOutcome {
  std::string study;                    ///< study name
  std::vector<std::string> parameters;  ///< varied parameters, in the study's order
  std::vector<double> low, high;        ///< their ranges (physical)
  std::vector<double> unit;             ///< optimum on the unit cube
  std::vector<double> physical;         ///< optimum in physical units
  /// Parameters tied to one of `parameters` (`same_as`): they take its value.
  std::vector<study::ParameterTie> ties;
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
  /// Failed checks, in words (a target the study cannot produce): `demsa calibrate` exits 1.
  std::vector<std::string> problems;
};

/// Runs the calibration (and the verification when asked) and writes DIR/analysis/calibration.json. Throws
/// util::UserError for a folder that is not a study, an unknown observable, a malformed target or weight, too few done
/// samples, or no metamodel that fits.
CalibrationOutcome calibrate_study(const CalibrateOptions& options);

/// calibration.json text of an outcome, and back. read_calibration throws util::UserError naming the file.
std::string calibration_to_json(const CalibrationOutcome& outcome);
CalibrationOutcome read_calibration(const std::filesystem::path& file);

/// What a study can produce of one observable, in words, against a measured value (stored units; shown in the
/// observable's unit): "study pile: angle of repose spans 21.2 to 33.2 ° over its 30 done samples; 60 ° is above
/// it". The "is above/below it" part only when the value lies outside the span.
std::string observed_span_text(const std::string& study, const std::string& observable, double low, double high,
                               int samples, double value);

/// A human-readable summary (optimum, predictions against targets, misfit, verification).
std::string calibration_text(const CalibrationOutcome& outcome);

}  // namespace demsa::analysis
