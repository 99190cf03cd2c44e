// DIR/calibration/posterior.json, both ways (calibration_posterior.hpp: posterior_to_json, read_posterior).
#include "orchestrator/analysis/calibration_posterior.hpp"

#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace demsa::analysis {

using namespace demsa::util;
using namespace demsa::study;
namespace fs = std::filesystem;
using nlohmann::json;

std::string posterior_to_json(const PosteriorOutcome& o) {
  json j;
  j["method"] = "bayes";
  j["studies"] = o.studies;
  json parameters = json::array();
  for (const PosteriorParameter& p : o.parameters) {
    parameters.push_back(json{{"name", p.name},
                              {"low", p.low},
                              {"high", p.high},
                              {"log", p.log},
                              {"mean", p.mean},
                              {"map", p.map},
                              {"q05", p.q05},
                              {"q50", p.q50},
                              {"q95", p.q95},
                              {"width_ratio", p.width_ratio},
                              {"identified", p.identified},
                              {"at_bound", p.at_bound},
                              {"bound_share", p.bound_share},
                              {"tau", p.tau},
                              {"rhat", p.rhat},
                              {"ess", p.ess}});
    if (!p.tied.empty()) parameters.back()["tied"] = p.tied;
  }
  j["parameters"] = parameters;
  j["correlation"] = o.correlation;
  json targets = json::array();
  for (const PosteriorTarget& t : o.targets)
    targets.push_back(json{{"name", t.name},
                           {"study", t.study},
                           {"model", t.model},
                           {"q2", std::isfinite(t.q2) ? json(t.q2) : json(nullptr)},
                           {"value", t.value},
                           {"sd", t.sd},
                           {"weight", t.weight},
                           {"model_sd", t.model_sd},
                           {"predicted_map", t.predicted_map},
                           {"predictive_q05", t.predictive_q05},
                           {"predictive_q50", t.predictive_q50},
                           {"predictive_q95", t.predictive_q95},
                           {"tail_probability", t.tail_probability},
                           {"contradicted", t.contradicted},
                           {"observed_low", t.observed_low},
                           {"observed_high", t.observed_high},
                           {"samples", t.samples}});
  j["targets"] = targets;
  j["sampler"] = json{{"walkers", o.walkers}, {"steps", o.steps},
                      {"burn_in", o.burn_in}, {"draws", o.draws},
                      {"seed", o.seed},       {"evaluations", o.evaluations},
                      {"seconds", o.seconds}, {"acceptance", o.acceptance}};
  j["sampler"]["auto_steps"] = o.auto_steps;
  j["diagnostics"] = json{{"converged", o.converged}, {"advice", o.advice}};
  json verification = json::array();
  for (const VerifyPoint& v : o.verification) {
    json measured = json::array();
    for (const VerifyPoint::Measured& m : v.measured)
      measured.push_back(json{{"target", m.target},
                              {"study", m.study},
                              {"value", m.value ? json(*m.value) : json(nullptr)},
                              {"predicted", m.predicted},
                              {"low", m.low},
                              {"high", m.high}});
    verification.push_back(
        json{{"label", v.label}, {"physical", v.physical}, {"measured", measured}, {"errors", v.errors}});
  }
  j["verification"] = verification;
  j["checks"] = json{{"passed", o.problems.empty()}, {"problems", o.problems}, {"warnings", o.warnings}};
  return j.dump(2) + "\n";
}

PosteriorOutcome read_posterior(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw UserError(fmt::format("{}: cannot read", file.string()));
  PosteriorOutcome o;
  try {
    const json j = json::parse(in);
    o.studies = j.at("studies").get<std::vector<std::string>>();
    for (const json& e : j.at("parameters")) {
      PosteriorParameter p;
      p.name = e.at("name");
      p.low = e.at("low");
      p.high = e.at("high");
      p.log = e.at("log");
      p.mean = e.at("mean");
      p.map = e.at("map");
      p.q05 = e.at("q05");
      p.q50 = e.at("q50");
      p.q95 = e.at("q95");
      p.width_ratio = e.at("width_ratio");
      p.identified = e.at("identified");
      p.tau = e.at("tau");
      p.rhat = e.at("rhat");
      p.ess = e.at("ess");
      p.at_bound = e.value("at_bound", std::string());
      p.bound_share = e.value("bound_share", 0.0);
      p.tied = e.value("tied", std::vector<std::string>());
      o.parameters.push_back(p);
    }
    o.correlation = j.at("correlation").get<std::vector<std::vector<double>>>();
    for (const json& e : j.at("targets")) {
      PosteriorTarget t;
      t.name = e.at("name");
      t.study = e.at("study");
      t.model = e.at("model");
      t.q2 = e.at("q2").is_number() ? e.at("q2").get<double>() : std::nan("");
      t.value = e.at("value");
      t.sd = e.at("sd");
      t.weight = e.at("weight");
      t.model_sd = e.at("model_sd");
      t.predicted_map = e.at("predicted_map");
      t.predictive_q05 = e.at("predictive_q05");
      t.predictive_q50 = e.at("predictive_q50");
      t.predictive_q95 = e.at("predictive_q95");
      // Written since the checks (docs/reference/checks.md); an older file has none.
      t.tail_probability = e.value("tail_probability", 1.0);
      t.contradicted = e.value("contradicted", false);
      t.observed_low = e.value("observed_low", 0.0);
      t.observed_high = e.value("observed_high", 0.0);
      t.samples = e.value("samples", 0);
      o.targets.push_back(t);
    }
    const json& s = j.at("sampler");
    o.walkers = s.at("walkers");
    o.steps = s.at("steps");
    o.burn_in = s.at("burn_in");
    o.draws = s.at("draws");
    o.seed = s.at("seed");
    o.evaluations = s.at("evaluations");
    o.seconds = s.at("seconds");
    o.acceptance = s.at("acceptance");
    if (s.contains("auto_steps")) o.auto_steps = s.at("auto_steps").get<std::vector<int>>();
    o.converged = j.at("diagnostics").at("converged");
    o.advice = j.at("diagnostics").at("advice");
    for (const json& e : j.at("verification")) {
      VerifyPoint v;
      v.label = e.at("label");
      v.physical = e.at("physical").get<std::vector<double>>();
      v.errors = e.at("errors").get<std::vector<std::string>>();
      for (const json& m : e.at("measured")) {
        VerifyPoint::Measured x;
        x.target = m.at("target");
        x.study = m.at("study");
        if (!m.at("value").is_null()) x.value = m.at("value").get<double>();
        x.predicted = m.at("predicted");
        x.low = m.at("low");
        x.high = m.at("high");
        v.measured.push_back(x);
      }
      o.verification.push_back(v);
    }
    if (j.contains("checks")) {
      o.problems = j.at("checks").at("problems").get<std::vector<std::string>>();
      o.warnings = j.at("checks").at("warnings").get<std::vector<std::string>>();
    }
  } catch (const json::exception& e) {
    throw UserError(fmt::format("{}: not a posterior file: {}", file.string(), e.what()));
  }
  o.out = file.parent_path();
  return o;
}

}  // namespace demsa::analysis
