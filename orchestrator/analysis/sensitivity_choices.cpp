#include "orchestrator/analysis/sensitivity_choices.hpp"

#include "orchestrator/analysis/fit.hpp"
#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"
#include "sobol/error.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cstdlib>

namespace demsa::analysis {

using util::UserError;

void check_sensitivity_choices(const SensitivityChoiceOptions& options) {
  if (options.design.empty() == options.data.empty())
    throw UserError(
        "give exactly one of SensitivityChoiceOptions.design DESIGN.csv (with "
        "SaltelliSensitivityOptions.responses_file) or SensitivityChoiceOptions.data DATA.csv");
  if (!options.interval.empty() && !options.data.empty())
    throw UserError(
        "SensitivityChoiceOptions.interval goes with SensitivityChoiceOptions.design: the intervals of "
        "SensitivityChoiceOptions.data are design-bootstrap refits of each metamodel "
        "(SensitivityChoiceOptions.bootstrap)");
  if (!options.repeats.empty() && options.data.empty())
    throw UserError(
        "SensitivityChoiceOptions.repeats goes with SensitivityChoiceOptions.data: the noise sets the nugget of the "
        "metamodels fitted to the data");
  if (options.bootstrap && *options.bootstrap < 0)
    throw UserError(
        fmt::format("SensitivityChoiceOptions.bootstrap {}: must be >= 0 (0: no intervals)", *options.bootstrap));
  if (!(options.confidence > 0.0 && options.confidence < 1.0))
    throw UserError(fmt::format("SensitivityChoiceOptions.confidence {}: must be strictly between 0 and 1 (e.g. 0.95)",
                                options.confidence));
  if (options.base < 16)
    throw UserError(
        fmt::format("SensitivityChoiceOptions.base {}: must be at least 16 (a power of two, e.g. 16384, balances best)",
                    options.base));
  // The indices' QMC design is held whole in memory.
  if (options.base > sobol::k_max_base_samples)
    throw UserError(
        fmt::format("SensitivityChoiceOptions.base {}: at most 2^20 = {} (the indices' QMC design holds N (2d + 2) "
                    "points in memory)",
                    options.base, sobol::k_max_base_samples));
  if (!options.design.empty()) {
    saltelli_interval_choice(options);
    if (!options.save_model.empty())
      throw UserError(
          "SensitivityChoiceOptions.save_model: a Saltelli design gives indices without a metamodel: nothing to save "
          "(use SensitivityChoiceOptions.data)");
  }
}

sobol::SaltelliInterval saltelli_interval_choice(const SensitivityChoiceOptions& options) {
  if (options.interval.empty())
    return options.bootstrap ? sobol::SaltelliInterval::bootstrap : sobol::SaltelliInterval::replicates;
  sobol::SaltelliInterval interval;
  try {
    interval = sobol::saltelli_interval_from_string(options.interval);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("SensitivityChoiceOptions.interval: {}", e.what()));
  }
  if (options.bootstrap && interval != sobol::SaltelliInterval::bootstrap)
    throw UserError(
        fmt::format("SensitivityChoiceOptions.bootstrap {} gives the resamples of SensitivityChoiceOptions.interval "
                    "bootstrap, not of SensitivityChoiceOptions.interval {}",
                    *options.bootstrap, options.interval));
  return interval;
}

std::map<std::string, sobol::Bounds> parse_input_bounds(const std::string& text,
                                                        const std::vector<std::string>& inputs) {
  std::map<std::string, sobol::Bounds> bounds;
  for (const std::string& item : util::split_list(text)) {
    const std::size_t eq = item.find('=');
    const std::string name = eq == std::string::npos ? "" : item.substr(0, eq);
    if (eq == std::string::npos || std::find(inputs.begin(), inputs.end(), name) == inputs.end())
      throw UserError(
          fmt::format("DataSensitivityOptions.bounds '{}': expected NAME=LOW:HIGH[:log] with NAME one of "
                      "DataSensitivityOptions.inputs",
                      item));
    const std::vector<std::string> parts = util::split(std::string_view(item).substr(eq + 1), ':');
    if (parts.size() < 2 || parts.size() > 3)
      throw UserError(fmt::format("DataSensitivityOptions.bounds '{}': expected NAME=LOW:HIGH[:log]", item));
    auto number = [&](const std::string& s) {
      char* end = nullptr;
      const double v = std::strtod(s.c_str(), &end);
      if (s.empty() || *end != '\0')
        throw UserError(fmt::format("DataSensitivityOptions.bounds '{}': '{}' is not a number", item, s));
      return v;
    };
    sobol::Bounds b;
    b.low = number(parts[0]);
    b.high = number(parts[1]);
    if (parts.size() == 3) {
      try {
        b.scale = sobol::scale_from_string(parts[2]);
      } catch (const sobol::InputError& e) {
        throw UserError(fmt::format("DataSensitivityOptions.bounds '{}': {}", item, e.what()));
      }
    }
    if (!bounds.emplace(name, b).second)
      throw UserError(fmt::format("DataSensitivityOptions.bounds: '{}' is given twice", name));
  }
  return bounds;
}

std::vector<sobol::MetamodelKind> choose_metamodels(const std::vector<std::string>& names) {
  try {
    return metamodel_kinds(names);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("DataSensitivityOptions.metamodels: {}", e.what()));
  }
}

void choose_gp(const GpChoiceOptions& options, sobol::GpOptions& gp) {
  try {
    gp.kernel = sobol::gp_kernel_from_string(options.kernel);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("GpChoiceOptions.kernel: {}", e.what()));
  }
  try {
    gp.trend = sobol::gp_trend_from_string(options.trend);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("GpChoiceOptions.trend: {}", e.what()));
  }
}

}  // namespace demsa::analysis
