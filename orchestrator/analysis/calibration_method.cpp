#include "orchestrator/analysis/calibration_method.hpp"

#include "orchestrator/analysis/target_syntax.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <algorithm>

namespace demsa::analysis {

using util::UserError;

CalibrationMethod CalibrationMethodOptions::choose() const {
  const auto uncertain = [](const std::vector<MeasuredTarget>& ts) {
    return std::any_of(ts.begin(), ts.end(), [](const MeasuredTarget& t) { return t.sd > 0; });
  };
  std::string chosen = method;
  if (chosen == "auto") chosen = studies > 1 || uncertain(targets) || uncertain(target_files) ? "bayes" : "optimize";
  if (chosen == "optimize") {
    if (studies != 1)
      throw UserError(
          fmt::format("CalibrationMethodOptions.method optimize: one study folder, not {} (several "
                      "studies: CalibrationMethodOptions.method bayes)",
                      studies));
    if (verify > 0)
      throw UserError(
          fmt::format("CalibrationMethodOptions.verify {}: CalibrationMethodOptions.method optimize "
                      "verifies its one optimum (give CalibrationMethodOptions.verify alone)",
                      verify));
    for (const MeasuredTarget& t : targets)
      if (t.sd > 0)
        throw UserError(
            fmt::format("CalibrationMethodOptions.targets '{}': CalibrationMethodOptions.method optimize "
                        "matches a value; an uncertainty is for CalibrationMethodOptions.method bayes",
                        t.text()));
    return CalibrationMethod::optimize;
  }
  if (chosen == "bayes") {
    if (targets.empty() && target_files.empty())
      throw UserError(
          "calibrate CalibrationMethodOptions.method bayes: give the measured values with "
          "CalibrationMethodOptions.targets NAME=V±E or CalibrationMethodOptions.target_files");
    return CalibrationMethod::bayes;
  }
  throw UserError(fmt::format("CalibrationMethodOptions.method '{}': expected auto, bayes or optimize", method));
}

CalibrationMethodOptions read_calibration_targets(const std::vector<std::string>& targets,
                                                  const std::vector<std::string>& target_files,
                                                  const std::vector<std::string>& weights) {
  CalibrationMethodOptions options;
  for (const std::string& text : targets)
    for (const MeasuredTarget& t : parse_measured("CalibrationMethodOptions.targets", text))
      options.targets.push_back(t);
  for (const std::string& text : weights) {
    const auto [label, weight] = parse_weight("CalibrationMethodOptions.weights", text);
    options.weights[label] = weight;
  }
  for (const std::string& text : target_files)
    for (const MeasuredTarget& t : read_target_file("CalibrationMethodOptions.target_files", text))
      options.target_files.push_back(t);
  return options;
}

bool calibration_failed(const CalibrationOutcome& outcome, bool verify) {
  return (verify && !outcome.verified) || !outcome.problems.empty();
}

bool posterior_failed(const PosteriorOutcome& outcome) {
  bool failed = !outcome.problems.empty();
  for (const VerifyPoint& v : outcome.verification) failed = failed || !v.errors.empty();
  return failed;
}

}  // namespace demsa::analysis
