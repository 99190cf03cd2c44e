#include "orchestrator/analysis/analysis_json.hpp"

#include "orchestrator/analysis/sobol_json.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <stdexcept>

namespace demsa::analysis {

using nlohmann::json;

namespace {
/// A number as sobol_json writes it: null for NaN or infinity.
json number_to_json(double value) { return std::isfinite(value) ? json(value) : json(); }
}  // namespace

std::string analysis_to_json(const AnalysisSummary& summary) {
  json all{{"study", summary.study},
           {"parameters", summary.parameters},
           {"samples_used", summary.samples_used},
           {"samples_left_out", summary.samples_left_out},
           {"samples_unsettled", summary.samples_unsettled},
           {"unsettled", summary.unsettled},
           {"seed", summary.seed},
           {"bootstrap", summary.bootstrap},
           {"base_samples", summary.base_samples},
           {"second_order", summary.second_order},
           {"confidence", summary.confidence}};
  json observables = json::array();
  for (const ObservableAnalysis& o : summary.observables) {
    json models = json::array();
    for (const ModelAnalysis& m : o.models) {
      json entry{{"model", m.model}, {"ok", m.ok}};
      if (m.ok) {
        entry["quality"] = metamodel_summary_json(m.quality);
        entry["sobol"] = sobol_result_json(m.indices, summary.parameters);
      } else {
        entry["error"] = m.error;
        if (m.fitted) entry["quality"] = metamodel_summary_json(m.quality);
      }
      models.push_back(entry);
    }
    json entry{{"name", o.name}, {"samples", o.samples}, {"mean", o.mean}, {"sd", o.sd}, {"models", models}};
    if (!o.error.empty()) entry["error"] = o.error;
    if (o.noise) {
      entry["noise"] = noise_json(*o.noise);
    }
    observables.push_back(entry);
  }
  all["observables"] = observables;
  return all.dump(2) + "\n";
}

bool noise_dominates(double share, double largest_s1) {
  return share > 0.5 || (!std::isnan(largest_s1) && share > largest_s1);
}

json noise_json(const NoiseAnalysis& n) {
  return {{"variance", number_to_json(n.estimate.variance)},
          {"lower", number_to_json(n.estimate.lower)},
          {"upper", number_to_json(n.estimate.upper)},
          {"confidence", n.estimate.confidence},
          {"points", n.estimate.points},
          {"values", n.estimate.values},
          {"dof", n.estimate.dof},
          {"share", number_to_json(n.share)},
          {"share_lower", number_to_json(n.share_lower)},
          {"share_upper", number_to_json(n.share_upper)},
          {"largest_s1", number_to_json(n.largest_s1)},
          {"dominates", n.dominates},
          {"nugget_share", number_to_json(n.nugget_share)}};
}

AnalysisSummary read_analysis(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw util::UserError(fmt::format("{}: cannot read", file.string()));
  AnalysisSummary summary;
  summary.out_dir = file.parent_path();
  try {
    const json j = json::parse(in);
    summary.study = j.at("study").get<std::string>();
    summary.parameters = j.at("parameters").get<std::vector<std::string>>();
    summary.samples_used = j.at("samples_used").get<std::vector<int>>();
    summary.samples_left_out = j.at("samples_left_out").get<std::vector<int>>();
    // Written since the pile in time; an older analysis.json has neither.
    summary.samples_unsettled = j.value("samples_unsettled", std::vector<int>{});
    summary.unsettled = j.value("unsettled", std::string());
    summary.seed = j.at("seed").get<std::uint64_t>();
    summary.bootstrap = j.at("bootstrap").get<int>();
    summary.base_samples = j.at("base_samples").get<int>();
    summary.second_order = j.at("second_order").get<bool>();
    summary.confidence = number_from_json(j.at("confidence"));
    for (const json& o : j.at("observables")) {
      ObservableAnalysis observable;
      observable.name = o.at("name").get<std::string>();
      observable.samples = o.at("samples").get<int>();
      observable.mean = number_from_json(o.at("mean"));
      observable.sd = number_from_json(o.at("sd"));
      observable.error = o.value("error", std::string());
      if (o.contains("noise")) {
        const json& n = o.at("noise");
        NoiseAnalysis noise;
        noise.estimate.variance = number_from_json(n.at("variance"));
        noise.estimate.lower = number_from_json(n.at("lower"));
        noise.estimate.upper = number_from_json(n.at("upper"));
        noise.estimate.confidence = number_from_json(n.at("confidence"));
        noise.estimate.points = n.at("points").get<int>();
        noise.estimate.values = n.at("values").get<int>();
        noise.estimate.dof = n.at("dof").get<int>();
        noise.share = number_from_json(n.at("share"));
        noise.share_lower = number_from_json(n.at("share_lower"));
        noise.share_upper = number_from_json(n.at("share_upper"));
        noise.largest_s1 = number_from_json(n.at("largest_s1"));
        noise.dominates = n.at("dominates").get<bool>();
        noise.nugget_share = number_from_json(n.at("nugget_share"));
        observable.noise = noise;
      }
      for (const json& m : o.at("models")) {
        ModelAnalysis model;
        model.model = m.at("model").get<std::string>();
        model.ok = m.at("ok").get<bool>();
        model.fitted = model.ok || m.contains("quality");
        if (model.fitted) model.quality = metamodel_summary_from_json(m.at("quality"));
        if (model.ok)
          model.indices = sobol_result_from_json(m.at("sobol"), summary.parameters);
        else
          model.error = m.value("error", std::string());
        observable.models.push_back(std::move(model));
      }
      summary.observables.push_back(std::move(observable));
    }
  } catch (const json::exception& e) {
    throw util::UserError(fmt::format("{}: not an analysis file ({})", file.string(), e.what()));
  } catch (const std::invalid_argument& e) {
    throw util::UserError(fmt::format("{}: not an analysis file ({})", file.string(), e.what()));
  }
  return summary;
}

}  // namespace demsa::analysis
