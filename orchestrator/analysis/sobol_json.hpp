#pragma once
// The one JSON form of Sobol' results and metamodel summaries, shared by `demsa sensitivity --json`, the study
// analysis (analysis.json, sobol_<model>.json, metamodels.json) and the report that reads them back:
//
//   index estimate:  {"value": v, "lower": l, "upper": u}          (lower = upper = value without an interval, or
//                                                                   null by IntervalJson::null_without)
//   Sobol' result:   {"method", "dimension", "base", "evaluations", "mean", "variance",
//                     "S1": {input: estimate, ...}, "ST": {input: estimate, ...},
//                     "S2": [{"i": input, "j": input, "S2": estimate}, ...],      (i before j in input order)
//                     "residual": estimate (1 - Σ S1), "bootstrap", "confidence", "seed",
//                     "replicates": R (only for Student-t intervals from R independently scrambled replicates),
//                     "note": "..." (only when there is something to say: what bootstrap intervals on a QMC design
//                     assume, or why intervals asked for could not be computed)}
//   metamodel:       {"name", "samples", "dimension", "terms", "r2", "adjusted_r2", "q2" (leave-one-out),
//                     "rmse_loo", "mean", "sd", "parameters": {name: value, ...}}
// Non-finite numbers are written as null and read back as NaN. The readers throw nlohmann::json::exception for a
// missing or mistyped field and std::invalid_argument for an S2 entry naming an unknown input.
#include "sobol/metamodel.hpp"
#include "sobol/saltelli.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace demsa::analysis {

/// How a result without intervals writes its bounds: as the estimate (what the analysis files hold), or as null
/// (`demsa sensitivity --saltelli`: no zero-width interval that is not one).
enum class IntervalJson { as_estimated, null_without };

nlohmann::json index_estimate_json(const sobol::IndexEstimate& estimate,
                                   IntervalJson bounds = IntervalJson::as_estimated);

/// `inputs` names the result's inputs in order (at least `result.first.size()` names).
nlohmann::json sobol_result_json(const sobol::SobolResult& result, const std::vector<std::string>& inputs,
                                 IntervalJson bounds = IntervalJson::as_estimated);

nlohmann::json metamodel_summary_json(const sobol::MetamodelSummary& summary);

/// A number written by the functions above: null is NaN.
double number_from_json(const nlohmann::json& value);

sobol::IndexEstimate index_estimate_from_json(const nlohmann::json& j);

/// The inverse of sobol_result_json with the same `inputs`.
sobol::SobolResult sobol_result_from_json(const nlohmann::json& j, const std::vector<std::string>& inputs);

sobol::MetamodelSummary metamodel_summary_from_json(const nlohmann::json& j);

}  // namespace demsa::analysis
