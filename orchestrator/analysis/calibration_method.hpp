#pragma once
// Which calibration a front end's request asks for (`demsa calibrate --method`), the combinations each method
// refuses, and whether a finished calibration passed its checks:
//   bayes:    the posterior (calibration_posterior.hpp) of one or several studies; --verify K runs the MAP and K draws.
//   optimize: the one point that best matches (calibration.hpp) in one study; verify runs it.
//   auto:     bayes when the measurements carry an uncertainty (a target with ±, a target file) or several studies
//             are given, optimize otherwise: a likelihood needs the measurement's spread, and a target without one
//             states no more than the point it asks for.
// The errors name the fields ("CalibrationMethodOptions.method optimize: ..."), which a command line writes as its
// own options (cli::name_options).
#include "orchestrator/analysis/calibration.hpp"
#include "orchestrator/analysis/calibration_posterior.hpp"
#include "orchestrator/analysis/measured_target.hpp"

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace demsa::analysis {

enum class CalibrationMethod { optimize, bayes };

/// What the method is chosen from.
struct CalibrationMethodOptions {
  std::string method = "auto";               ///< auto, bayes or optimize
  std::size_t studies = 0;                   ///< study folders given
  std::vector<MeasuredTarget> targets;       ///< the values given one by one (NAME=V[±E])
  std::vector<MeasuredTarget> target_files;  ///< the values read from curve files (bayes only)
  int verify = -1;                           ///< -1: no verification; 0: the optimum or the MAP; K: and K draws
  std::map<std::string, double> weights;     ///< by target label
  /// The method `method` names, auto resolved; throws util::UserError naming the field when that method refuses
  /// the combination (optimize: several studies, verify K > 0, a target with an uncertainty; bayes: no target).
  CalibrationMethod choose() const;
};

/// The measured values and weights as text (target_syntax.hpp) in the options: `targets` "NAME=V[±E]",
/// `target_files` "NAME=FILE.csv", `weights` "NAME=W"; errors name CalibrationMethodOptions.targets, .target_files
/// and .weights with the item. The method, the studies and verify keep their defaults.
CalibrationMethodOptions read_calibration_targets(const std::vector<std::string>& targets,
                                                  const std::vector<std::string>& target_files,
                                                  const std::vector<std::string>& weights);

/// A target the study cannot produce, or a verification that was asked for (`verify`) and did not give
/// measurements, fails the check of an optimization.
bool calibration_failed(const CalibrationOutcome& outcome, bool verify);

/// A chain that has not converged, a measurement the posterior cannot produce, or a verification run that failed,
/// fails the check of a posterior.
bool posterior_failed(const PosteriorOutcome& outcome);

}  // namespace demsa::analysis
