#pragma once
// A measured value of one observable, with its uncertainty: what `demsa calibrate` matches (its targets) and what
// `demsa plan` draws its truths near. Typed: its text syntax "NAME=V±E" is target_syntax.hpp's.
#include <filesystem>
#include <string>
#include <vector>

namespace demsa::analysis {

struct MeasuredTarget {
  /// The study's `[study] name` the value belongs to; empty: the one study of the calibration that measures `name`.
  std::string study{};
  std::string name{};  ///< observable, as DIR/analysis/observables.csv names it (settlement_2, not settlement)
  double value = 0.0;  ///< in the units demsa stores it (SI, angles in degrees)
  /// The measurement's standard deviation, same units; 0: none given (a value to match, `calibrate_study`; the
  /// posterior refuses it).
  double sd = 0.0;
  /// "NAME" or "STUDY:NAME": how messages, the weights and the plan's `near` name the target.
  std::string label() const;
  /// "LABEL=VALUE" or "LABEL=VALUE±SD", the values to 12 significant digits: the target in messages.
  std::string text() const;
};

/// NAME_k, the k-th point (from 1) of a measured curve NAME: settlement_2 of an oedometer's settlement curve.
std::string curve_point_name(const std::string& name, std::size_t k);

/// A measured curve from a CSV file (`calibrate --target-file`): one row per point, a column `mean` and either `sd`,
/// or `low`, `high` and `tests` (the extremes over that many tests, 2..20: σ = (high - low) / d₂(tests)). One row is
/// the observable `name`; several are its points name_1, name_2, ... Throws util::UserError naming the file, its line
/// and the value.
std::vector<MeasuredTarget> read_measured_curve(const std::string& study, const std::string& name,
                                                const std::filesystem::path& file);

}  // namespace demsa::analysis
