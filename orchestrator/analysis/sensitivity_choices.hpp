#pragma once
// The choices of `demsa sensitivity` as a front end reads them, by name and number (sensitivity.hpp takes them typed):
// the bounds of the inputs as "NAME=LOW:HIGH[:log],...", the metamodels and the GP's kernel and trend by name, the
// interval method, the bootstrap and the confidence. Each function checks what it reads and throws util::UserError
// naming the field and the value ("SensitivityChoiceOptions.base 8: must be at least 16 ..."), which a command line
// writes as its own option (cli::name_options).
#include "sobol/metamodel.hpp"
#include "sobol/saltelli.hpp"
#include "sobol/scaling.hpp"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace demsa::analysis {

/// The bootstrap when none is chosen: resamples of a Saltelli design's rows, design refits of each metamodel.
inline constexpr int k_default_saltelli_bootstrap = 200;
inline constexpr int k_default_data_refits = 100;

/// The settings of the indices as chosen, before the defaults of the path (Saltelli design or data) fill them.
struct SensitivityChoiceOptions {
  std::optional<int> bootstrap;  ///< >= 0 (0: no intervals); empty: the path's default
  /// Saltelli path: sobol::SaltelliInterval by name; "": replicates, or bootstrap when `bootstrap` is given.
  std::string interval;
  double confidence = 0.95;  ///< in (0, 1)
  int base = 16384;          ///< QMC base sample size of the metamodels' indices, 16 .. sobol::k_max_base_samples
  /// The path, exactly one of the two: a Saltelli design's file (SaltelliSensitivityOptions.design) or the data's
  /// (DataSensitivityOptions.data).
  std::string design, data;
  std::string repeats;     ///< the data's repeated runs (DataSensitivityOptions.repeats): data path only
  std::string save_model;  ///< where fitted metamodels go (DataSensitivityOptions.save_model): data path only
};

/// Checks which options go together (one path of design and data; interval with the design, repeats and save_model
/// with the data), the numbers (bootstrap, confidence, base) and the design's interval (saltelli_interval_choice).
void check_sensitivity_choices(const SensitivityChoiceOptions& options);

/// The interval method of a Saltelli design: `interval` by name; without it the replicates', or the bootstrap when
/// `bootstrap` gives its resamples. A bootstrap with another interval named is an error.
sobol::SaltelliInterval saltelli_interval_choice(const SensitivityChoiceOptions& options);

/// "NAME=LOW:HIGH[:log],..." -> the bounds of the inputs named, each one of `inputs` and named once (the others keep
/// the data's range). Errors name DataSensitivityOptions.bounds and the item.
std::map<std::string, sobol::Bounds> parse_input_bounds(const std::string& text,
                                                        const std::vector<std::string>& inputs);

/// Metamodels by name (fit.hpp's metamodel_kinds); errors name DataSensitivityOptions.metamodels.
std::vector<sobol::MetamodelKind> choose_metamodels(const std::vector<std::string>& names);

/// The GP's correlation and trend by name (sobol::gp_kernel_from_string, gp_trend_from_string).
struct GpChoiceOptions {
  std::string kernel = "squared-exponential";
  std::string trend = "constant";
};

/// Sets the kernel and trend the options name into `gp`; errors name GpChoiceOptions.kernel and .trend.
void choose_gp(const GpChoiceOptions& options, sobol::GpOptions& gp);

}  // namespace demsa::analysis
