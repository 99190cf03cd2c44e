#include "orchestrator/analysis/sobol_json.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace demsa::analysis {

namespace {

nlohmann::json number(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(); }

}  // namespace

nlohmann::json index_estimate_json(const sobol::IndexEstimate& estimate, IntervalJson bounds) {
  if (bounds == IntervalJson::null_without)
    return {{"value", number(estimate.value)}, {"lower", nullptr}, {"upper", nullptr}};
  return {{"value", number(estimate.value)}, {"lower", number(estimate.lower)}, {"upper", number(estimate.upper)}};
}

nlohmann::json sobol_result_json(const sobol::SobolResult& result, const std::vector<std::string>& inputs,
                                 IntervalJson bounds) {
  assert(inputs.size() >= result.first.size() && result.first.size() == result.total.size());
  nlohmann::json j{{"method", result.method},
                   {"dimension", result.dimension},
                   {"base", result.base},
                   {"evaluations", result.evaluations},
                   {"mean", number(result.mean)},
                   {"variance", number(result.variance)},
                   {"residual", index_estimate_json(result.residual, bounds)},
                   {"bootstrap", result.bootstrap},
                   {"confidence", result.confidence},
                   {"seed", result.seed}};
  nlohmann::json first = nlohmann::json::object(), total = nlohmann::json::object();
  for (std::size_t k = 0; k < result.first.size(); ++k) {
    first[inputs[k]] = index_estimate_json(result.first[k], bounds);
    total[inputs[k]] = index_estimate_json(result.total[k], bounds);
  }
  j["S1"] = first;
  j["ST"] = total;
  nlohmann::json second = nlohmann::json::array();
  for (const sobol::SecondOrderIndex& s : result.second)
    second.push_back({{"i", inputs.at(static_cast<std::size_t>(s.i))},
                      {"j", inputs.at(static_cast<std::size_t>(s.j))},
                      {"S2", index_estimate_json(s.s, bounds)}});
  j["S2"] = second;
  if (result.replicates > 0) j["replicates"] = result.replicates;
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

double number_from_json(const nlohmann::json& value) {
  if (value.is_null()) return std::numeric_limits<double>::quiet_NaN();
  return value.get<double>();
}

sobol::IndexEstimate index_estimate_from_json(const nlohmann::json& j) {
  return {number_from_json(j.at("value")), number_from_json(j.at("lower")), number_from_json(j.at("upper"))};
}

sobol::SobolResult sobol_result_from_json(const nlohmann::json& j, const std::vector<std::string>& inputs) {
  sobol::SobolResult r;
  r.method = j.at("method").get<std::string>();
  r.dimension = j.at("dimension").get<int>();
  r.base = j.at("base").get<int>();
  r.evaluations = j.at("evaluations").get<int>();
  r.mean = number_from_json(j.at("mean"));
  r.variance = number_from_json(j.at("variance"));
  const nlohmann::json& first = j.at("S1");
  const nlohmann::json& total = j.at("ST");
  for (const std::string& input : inputs) {
    r.first.push_back(index_estimate_from_json(first.at(input)));
    r.total.push_back(index_estimate_from_json(total.at(input)));
  }
  const auto index_of = [&inputs](const nlohmann::json& name) {
    const std::string n = name.get<std::string>();
    const auto it = std::find(inputs.begin(), inputs.end(), n);
    if (it == inputs.end()) throw std::invalid_argument(fmt::format("S2: '{}' is not one of the inputs", n));
    return static_cast<int>(it - inputs.begin());
  };
  for (const nlohmann::json& s : j.at("S2"))
    r.second.push_back({index_of(s.at("i")), index_of(s.at("j")), index_estimate_from_json(s.at("S2"))});
  r.residual = index_estimate_from_json(j.at("residual"));
  r.bootstrap = j.at("bootstrap").get<int>();
  r.confidence = number_from_json(j.at("confidence"));
  r.seed = j.at("seed").get<std::uint64_t>();
  r.note = j.value("note", std::string());
  r.replicates = j.value("replicates", 0);
  return r;
}

sobol::MetamodelSummary metamodel_summary_from_json(const nlohmann::json& j) {
  sobol::MetamodelSummary s;
  s.name = j.at("name").get<std::string>();
  s.samples = j.at("samples").get<int>();
  s.dimension = j.at("dimension").get<int>();
  s.terms = j.at("terms").get<int>();
  s.r2 = number_from_json(j.at("r2"));
  s.adjusted_r2 = number_from_json(j.at("adjusted_r2"));
  s.q2 = number_from_json(j.at("q2"));
  s.rmse_loo = number_from_json(j.at("rmse_loo"));
  s.mean = number_from_json(j.at("mean"));
  s.sd = number_from_json(j.at("sd"));
  for (const auto& [name, value] : j.at("parameters").items()) s.parameters.push_back({name, number_from_json(value)});
  return s;
}

}  // namespace demsa::analysis
