#include "orchestrator/analysis/sobol_json.hpp"

#include <cassert>
#include <cmath>

namespace demsa::analysis {

namespace {

nlohmann::json number(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(); }

}  // namespace

nlohmann::json index_estimate_json(const sobol::IndexEstimate& estimate) {
  return {{"value", number(estimate.value)}, {"lower", number(estimate.lower)}, {"upper", number(estimate.upper)}};
}

nlohmann::json sobol_result_json(const sobol::SobolResult& result, const std::vector<std::string>& inputs) {
  assert(inputs.size() >= result.first.size() && result.first.size() == result.total.size());
  nlohmann::json j{{"method", result.method},
                   {"dimension", result.dimension},
                   {"base", result.base},
                   {"evaluations", result.evaluations},
                   {"mean", number(result.mean)},
                   {"variance", number(result.variance)},
                   {"residual", index_estimate_json(result.residual)},
                   {"bootstrap", result.bootstrap},
                   {"confidence", result.confidence},
                   {"seed", result.seed}};
  nlohmann::json first = nlohmann::json::object(), total = nlohmann::json::object();
  for (std::size_t k = 0; k < result.first.size(); ++k) {
    first[inputs[k]] = index_estimate_json(result.first[k]);
    total[inputs[k]] = index_estimate_json(result.total[k]);
  }
  j["S1"] = first;
  j["ST"] = total;
  nlohmann::json second = nlohmann::json::array();
  for (const sobol::SecondOrderIndex& s : result.second)
    second.push_back({{"i", inputs.at(static_cast<std::size_t>(s.i))},
                      {"j", inputs.at(static_cast<std::size_t>(s.j))},
                      {"S2", index_estimate_json(s.s)}});
  j["S2"] = second;
  if (!result.note.empty()) j["note"] = result.note;
  return j;
}

nlohmann::json metamodel_summary_json(const sobol::MetamodelSummary& summary) {
  nlohmann::json parameters = nlohmann::json::object();
  for (const sobol::NamedValue& v : summary.parameters) parameters[v.name] = number(v.value);
  return {{"name", summary.name},           {"samples", summary.samples},
          {"dimension", summary.dimension}, {"terms", summary.terms},
          {"r2", number(summary.r2)},       {"adjusted_r2", number(summary.adjusted_r2)},
          {"q2", number(summary.q2)},       {"rmse_loo", number(summary.rmse_loo)},
          {"mean", number(summary.mean)},   {"sd", number(summary.sd)},
          {"parameters", parameters}};
}

}  // namespace demsa::analysis
