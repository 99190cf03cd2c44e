#include "orchestrator/analysis/fit.hpp"

#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <cmath>
#include <limits>

namespace demsa::analysis {

FittedMetamodel fit_metamodel(sobol::MetamodelKind kind, const sobol::MetamodelOptions& options,
                              const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  FittedMetamodel fit;
  fit.kind = kind;
  try {
    std::unique_ptr<sobol::Metamodel> model = sobol::make_metamodel(kind, options);
    model->fit(x, y);
    fit.quality = model->summary();
    fit.model = std::move(model);
  } catch (const std::exception& e) {
    // Every failure of a fit is a property of this data (sobol::DataError, InputError, NumericalError): the
    // caller decides whether the other kinds still give an answer.
    fit.error = e.what();
    fit.exception = std::current_exception();
  }
  return fit;
}

std::vector<FittedMetamodel> fit_metamodels(const std::vector<sobol::MetamodelKind>& kinds,
                                            const sobol::MetamodelOptions& options, const Eigen::MatrixXd& x,
                                            const Eigen::VectorXd& y) {
  std::vector<FittedMetamodel> fits;
  fits.reserve(kinds.size());
  for (const sobol::MetamodelKind kind : kinds) fits.push_back(fit_metamodel(kind, options, x, y));
  return fits;
}

std::vector<sobol::MetamodelKind> metamodel_kinds(const std::vector<std::string>& names) {
  std::vector<sobol::MetamodelKind> kinds;
  kinds.reserve(names.size());
  for (const std::string& name : names) kinds.push_back(sobol::metamodel_kind_from_string(name));
  return kinds;
}

std::optional<std::size_t> best_by_q2(const std::vector<FittedMetamodel>& fits) {
  const auto rank = [](double q2) { return std::isfinite(q2) ? q2 : -std::numeric_limits<double>::infinity(); };
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < fits.size(); ++i) {
    if (!fits[i].ok()) continue;
    if (!best || rank(fits[i].quality.q2) > rank(fits[*best].quality.q2)) best = i;
  }
  return best;
}

std::string unmeasurable_error(const sobol::MetamodelSummary& quality) {
  if (std::isfinite(quality.q2) && std::isfinite(quality.rmse_loo)) return "";
  if (quality.terms == quality.samples)
    return fmt::format(
        "leave-one-out Q² is not finite on {} samples: as many as its terms, so its error cannot be "
        "measured",
        quality.samples);
  if (quality.name.rfind("rsm", 0) == 0 && quality.terms < quality.samples)
    return fmt::format(
        "leave-one-out Q² is not finite on {} samples for its {} terms: a sample of leverage 1 (the "
        "only one that determines some term) is passed through whatever its value, so its error cannot be "
        "measured",
        quality.samples, quality.terms);
  return fmt::format("leave-one-out Q² is not finite on {} samples, so its error cannot be measured", quality.samples);
}

std::size_t best_measurable(const std::vector<FittedMetamodel>& fits, const std::string& where,
                            const std::string& observable) {
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < fits.size(); ++i) {
    if (!fits[i].ok() || !unmeasurable_error(fits[i].quality).empty()) continue;
    if (!best || fits[i].quality.q2 > fits[*best].quality.q2) best = i;
  }
  if (best) return *best;
  std::string reasons;
  bool fewest = false;  // rsm1, the metamodel of fewest terms, was among them: naming it would not help
  for (const FittedMetamodel& f : fits) {
    fewest = fewest || f.name() == "rsm1";
    reasons += fmt::format("\n  {}: {}", f.name(), f.ok() ? unmeasurable_error(f.quality) : f.error);
  }
  throw util::UserError(
      fmt::format("{}: no metamodel of {} whose error can be measured:{}\nrun more cases of the "
                  "study{}",
                  where, observable, reasons, fewest ? "" : ", or name a metamodel with fewer terms (--model rsm1)"));
}

}  // namespace demsa::analysis
