#pragma once
// The observables an experiment produces (paper §3.3 and §4), in table order.
#include "orchestrator/study/config.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::study {

/// Stored with a case's observables by an experiment that judges whether its particles came to rest, not analysed: 1
/// when its settling criterion was met, 0 when the case reached its time cap still moving (absent when the
/// criterion is off). `demsa status` and the report flag the samples stored with 0.
inline constexpr std::string_view k_settled = "settled";

/// Stored beside k_settled by an experiment that follows an observable in time: NAME_drift, the rate at which NAME
/// still changed at the end of the run (the pile's `angle_drift`, °/s). The flags of unsettled samples show it.
inline constexpr std::string_view k_drift_suffix = "_drift";

/// An observable measured at a time after some moment of the run, NAME@T (the pile's "angle@0.6" of [pile]
/// measure_times): NAME, the text of T and T [s].
struct TimedName {
  std::string family;  ///< "angle"
  std::string text;    ///< "0.6"
  double time = 0.0;   ///< 0.6
};
/// `name` read as NAME@T (the last '@'; T a finite number ≥ 0, nothing after it); none for any other name.
std::optional<TimedName> timed_name(std::string_view name);

/// The samples whose done run recorded an unsettled pile (k_settled = 0), from Store::observables().
std::vector<int> unsettled_samples(const std::map<int, std::map<std::string, double>>& observables);

/// A case run at one point outside the design (the verification of a calibration) and what it measured.
struct PointRun {
  std::filesystem::path folder;               ///< the case folder
  std::map<std::string, double> observables;  ///< measured values (empty when error is set)
  std::string error;                          ///< why the run or its measurement failed; "" when measured
  double seconds = 0.0;                       ///< wall time of the run [s]
};

}  // namespace demsa::study
