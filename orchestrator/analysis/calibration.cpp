#include "orchestrator/analysis/calibration.hpp"

#include "orchestrator/analysis/fit.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/analysis/training_data.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/parameters.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"
#include "sobol/metamodel.hpp"
#include "sobol/scaling.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <set>

namespace demsa::analysis {

using namespace demsa::util;
using namespace demsa::study;

namespace fs = std::filesystem;
using nlohmann::json;
using util::UserError;
using util::write_file_atomically;

namespace {

struct TargetSpec {
  std::string name;
  double value = 0.0;
  double weight = 1.0;
};

/// Targets from the options, or the study's own ones.
std::vector<TargetSpec> resolve_targets(const CalibrateOptions& options, const StudyConfig& config,
                                        const std::vector<std::string>& available) {
  std::vector<TargetSpec> targets;
  const auto known = [&](const std::string& name) {
    return std::find(available.begin(), available.end(), name) != available.end();
  };
  for (const MeasuredTarget& t : options.targets) {
    if (!t.study.empty() && t.study != config.name)
      throw UserError(fmt::format("CalibrateOptions.targets '{}': the study is named '{}', not '{}'", t.text(),
                                  config.name, t.study));
    if (!known(t.name))
      throw UserError(fmt::format("CalibrateOptions.targets '{}': unknown observable '{}' (observables: {})", t.text(),
                                  t.name, join(available)));
    targets.push_back({t.name, t.value, 1.0});
  }
  if (options.targets.empty()) {
    for (const auto& [name, value] : experiments::of(config).default_targets(config))
      targets.push_back({name, value, 1.0});
    for (const TargetSpec& t : targets)
      if (!known(t.name))
        throw UserError(fmt::format("{}: the study's target {} has no measured values yet (observables: {})",
                                    config.file.string(), t.name, join(available)));
  }
  std::set<std::string> seen;
  for (const TargetSpec& t : targets)
    if (!seen.insert(t.name).second)
      throw UserError(fmt::format("CalibrateOptions.targets: {} is given twice", t.name));
  for (const auto& [name, weight] : options.weights) {
    const auto it =
        std::find_if(targets.begin(), targets.end(), [&name = name](const TargetSpec& t) { return t.name == name; });
    if (it == targets.end()) throw UserError(fmt::format("CalibrateOptions.weights: {} is not a target", name));
    it->weight = weight;
  }
  return targets;
}

}  // namespace

void CalibrateOptions::validate() const {
  if (dir.empty()) throw UserError("calibrate: a study folder is required");
  for (const MeasuredTarget& t : targets)
    if (!std::isfinite(t.value))
      throw UserError(fmt::format("CalibrateOptions.targets '{}': the value must be a finite number", t.text()));
  for (const auto& [name, weight] : weights)
    if (!(weight >= 0) || !std::isfinite(weight))
      throw UserError(fmt::format("CalibrateOptions.weights '{}={}': one value >= 0 expected", name, weight));
  if (global_evaluations < 1)
    throw UserError(fmt::format("CalibrateOptions.global_evaluations {}: must be >= 1", global_evaluations));
  if (local_evaluations < 1)
    throw UserError(fmt::format("CalibrateOptions.local_evaluations {}: must be >= 1", local_evaluations));
  // CalibrateOptions promises a UserError naming the option; sobol's error names the value and the valid ones.
  try {
    sobol::global_algorithm_from_string(global);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("CalibrateOptions.global: {}", e.what()));
  }
  try {
    sobol::local_algorithm_from_string(local);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("CalibrateOptions.local: {}", e.what()));
  }
  try {
    if (!model.empty()) sobol::metamodel_kind_from_string(model);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("CalibrateOptions.model: {}", e.what()));
  }
}

CalibrationOutcome calibrate_study(const CalibrateOptions& options) {
  options.validate();
  const fs::path& dir = options.dir;
  require_study_folder(dir);
  const StudyConfig config = experiments::load_study(dir / k_frozen_study);
  const Store store = Store::open_read_only((dir / k_store_file).string());
  const std::vector<SampleRow> samples = store.samples();
  const std::map<int, std::map<std::string, double>> observables = store.observables();

  std::vector<std::string> available;
  for (const auto& [sample, values] : observables)
    for (const auto& [name, value] : values)
      if (std::find(available.begin(), available.end(), name) == available.end()) available.push_back(name);
  const std::vector<TargetSpec> specs = resolve_targets(options, config, available);

  CalibrationOutcome outcome;
  outcome.study = config.name;
  for (const ParameterRange& p : config.parameters) {
    outcome.parameters.push_back(p.name);
    outcome.low.push_back(p.bounds.low);
    outcome.high.push_back(p.bounds.high);
  }
  outcome.ties = config.ties;
  const size_t d = config.parameters.size();
  const std::vector<std::string> candidates =
      options.model.empty() ? config.analysis.metamodels : std::vector<std::string>{options.model};

  // Fit the candidates per target observable; keep the best Q² (docs/reference/command-line.md, `demsa calibrate`).
  std::vector<std::unique_ptr<sobol::Metamodel>> models;
  std::vector<sobol::CalibrationTarget> targets;
  const std::vector<sobol::MetamodelKind> kinds = metamodel_kinds(candidates);
  for (const TargetSpec& spec : specs) {
    const TrainingData data = training_data(config, samples, observables, spec.name);
    outcome.samples = std::max(outcome.samples, static_cast<int>(data.size()));
    if (data.size() < 2)
      throw UserError(
          fmt::format("{}: {} done samples measure {}; calibration needs more", dir.string(), data.size(), spec.name));
    // With replicates, the GP's nugget from the measured noise, as in the analysis.
    const double sd = std::sqrt((data.y.array() - data.y.mean()).square().sum() /
                                std::max<double>(1.0, static_cast<double>(data.size()) - 1.0));
    const std::optional<NoiseAnalysis> noise =
        measured_noise(store.replicates(), observables, spec.name, config.analysis.confidence, sd);
    std::vector<FittedMetamodel> fits = fit_metamodels(
        kinds, with_measured_noise(config.analysis.metamodel_options(), noise, data.y), data.unit, data.y);
    const std::size_t best_index = best_measurable(fits, dir.string(), spec.name);
    std::unique_ptr<sobol::Metamodel> best = std::move(fits[best_index].model);
    const sobol::MetamodelSummary& best_summary = fits[best_index].quality;
    CalibratedTarget t;
    t.name = spec.name;
    t.model = best->name();
    t.q2 = best_summary.q2;
    t.r2 = best_summary.r2;
    t.target = spec.value;
    t.weight = spec.weight;
    t.scale = spec.value != 0.0 ? std::abs(spec.value) : (best_summary.sd > 0 ? best_summary.sd : 1.0);
    t.rmse_loo = best_summary.rmse_loo;
    t.observed_low = data.y.minCoeff();
    t.observed_high = data.y.maxCoeff();
    t.samples = static_cast<int>(data.size());
    outcome.targets.push_back(t);
    models.push_back(std::move(best));
    targets.push_back({t.name, models.back().get(), t.target, t.weight, t.scale});
  }

  sobol::CalibrationOptions nlopt;
  nlopt.global = sobol::global_algorithm_from_string(options.global);
  nlopt.local = sobol::local_algorithm_from_string(options.local);
  nlopt.global_evaluations = options.global_evaluations;
  nlopt.local_evaluations = options.local_evaluations;
  nlopt.seed = config.seed;
  const sobol::CalibrationResult result = sobol::calibrate(targets, nlopt);
  outcome.unit = result.x;
  for (size_t j = 0; j < d; ++j)
    outcome.physical.push_back(sobol::to_physical(result.x[j], config.parameters[j].bounds));
  for (size_t k = 0; k < outcome.targets.size(); ++k) {
    CalibratedTarget& t = outcome.targets[k];
    t.predicted = result.predictions[k];
    // A target outside what the samples produced, and missed by the optimum by more than the metamodel's error:
    // the optimum sits where the metamodel comes closest, not where the measurement would be
    // (docs/reference/checks.md).
    const double tolerance = std::max(k_miss_rmse * t.rmse_loo, k_miss_span * (t.observed_high - t.observed_low));
    const bool outside = t.target < t.observed_low || t.target > t.observed_high;
    t.contradicted = t.weight > 0 && outside && std::abs(t.predicted - t.target) > tolerance;
    if (t.contradicted) {
      const study::Observable l = experiments::describe_observable(t.name);
      const std::string unit = l.unit.empty() ? "" : " " + l.unit;
      outcome.problems.push_back(fmt::format(
          "{} = {:.5g}{}: the optimum predicts {:.5g}{} (the metamodel's leave-one-out error is {:.3g}{}); {}: "
          "the measurement contradicts the study (no parameters in its ranges produce it)",
          t.name, t.target * l.factor, unit, t.predicted * l.factor, unit, t.rmse_loo * l.factor, unit,
          observed_span_text(config.name, t.name, t.observed_low, t.observed_high, t.samples, t.target)));
    }
  }
  outcome.misfit = result.misfit;
  outcome.evaluations = result.evaluations;
  outcome.global_algorithm = result.global_algorithm;
  outcome.local_algorithm = result.local_algorithm;
  outcome.seed = result.seed;

  if (options.verify) {
    if (!options.run_point) throw util::InternalError("calibrate: verification asked for, but no way to run a case");
    const study::PointRun run = options.run_point(config, dir / "calibration" / "verify", outcome.unit);
    outcome.verify_dir = run.folder;
    outcome.verify_seconds = run.seconds;
    outcome.verify_error = run.error;
    outcome.verified = run.error.empty();
    if (outcome.verified) {
      for (CalibratedTarget& t : outcome.targets) {
        const auto it = run.observables.find(t.name);
        if (it != run.observables.end()) t.measured = it->second;
      }
    }
  }

  fs::create_directories(dir / "analysis");
  write_file_atomically(dir / k_analysis_folder / k_calibration_json, calibration_to_json(outcome));
  return outcome;
}

std::string calibration_to_json(const CalibrationOutcome& o) {
  json j;
  j["study"] = o.study;
  json parameters = json::array();
  for (size_t i = 0; i < o.parameters.size(); ++i)
    parameters.push_back(json{{"name", o.parameters[i]},
                              {"low", o.low[i]},
                              {"high", o.high[i]},
                              {"unit", o.unit[i]},
                              {"value", o.physical[i]}});
  j["parameters"] = parameters;
  if (!o.ties.empty()) {
    json ties = json::array();
    for (const ParameterTie& t : o.ties) ties.push_back(json{{"name", t.name}, {"same_as", t.partner}});
    j["ties"] = ties;
  }
  json targets = json::array();
  for (const CalibratedTarget& t : o.targets) {
    const auto finite = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
    json e{{"name", t.name},     {"model", t.model},   {"q2", finite(t.q2)}, {"r2", finite(t.r2)},
           {"target", t.target}, {"weight", t.weight}, {"scale", t.scale},   {"predicted", t.predicted}};
    e["measured"] = t.measured ? json(*t.measured) : json(nullptr);
    e["rmse_loo"] = finite(t.rmse_loo);
    e["observed_low"] = t.observed_low;
    e["observed_high"] = t.observed_high;
    e["samples"] = t.samples;
    e["contradicted"] = t.contradicted;
    targets.push_back(e);
  }
  j["targets"] = targets;
  j["misfit"] = o.misfit;
  j["samples"] = o.samples;
  j["evaluations"] = o.evaluations;
  j["global_algorithm"] = o.global_algorithm;
  j["local_algorithm"] = o.local_algorithm;
  j["seed"] = o.seed;
  j["verification"] = json{{"verified", o.verified},
                           {"dir", o.verify_dir.string()},
                           {"error", o.verify_error},
                           {"seconds", o.verify_seconds}};
  j["checks"] = json{{"passed", o.problems.empty()}, {"problems", o.problems}};
  return j.dump(2) + "\n";
}

CalibrationOutcome read_calibration(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw UserError(fmt::format("{}: cannot read", file.string()));
  CalibrationOutcome o;
  try {
    const json j = json::parse(in);
    o.study = j.at("study").get<std::string>();
    for (const json& p : j.at("parameters")) {
      o.parameters.push_back(p.at("name").get<std::string>());
      o.low.push_back(p.at("low").get<double>());
      o.high.push_back(p.at("high").get<double>());
      o.unit.push_back(p.at("unit").get<double>());
      o.physical.push_back(p.at("value").get<double>());
    }
    if (j.contains("ties"))
      for (const json& t : j.at("ties"))
        o.ties.push_back({t.at("name").get<std::string>(), t.at("same_as").get<std::string>(), 0});
    for (const json& e : j.at("targets")) {
      CalibratedTarget t;
      t.name = e.at("name").get<std::string>();
      t.model = e.at("model").get<std::string>();
      t.q2 = e.at("q2").is_number() ? e.at("q2").get<double>() : std::numeric_limits<double>::quiet_NaN();
      t.r2 = e.at("r2").is_number() ? e.at("r2").get<double>() : std::numeric_limits<double>::quiet_NaN();
      t.target = e.at("target").get<double>();
      t.weight = e.at("weight").get<double>();
      t.scale = e.at("scale").get<double>();
      t.predicted = e.at("predicted").get<double>();
      if (!e.at("measured").is_null()) t.measured = e.at("measured").get<double>();
      // Written since the checks (docs/reference/checks.md); an older file has none.
      if (e.contains("rmse_loo") && e.at("rmse_loo").is_number()) t.rmse_loo = e.at("rmse_loo").get<double>();
      t.observed_low = e.value("observed_low", 0.0);
      t.observed_high = e.value("observed_high", 0.0);
      t.contradicted = e.value("contradicted", false);
      t.samples = e.value("samples", 0);
      o.targets.push_back(t);
    }
    o.misfit = j.at("misfit").get<double>();
    o.samples = j.at("samples").get<int>();
    o.evaluations = j.at("evaluations").get<int>();
    o.global_algorithm = j.at("global_algorithm").get<std::string>();
    o.local_algorithm = j.at("local_algorithm").get<std::string>();
    o.seed = j.at("seed").get<std::uint64_t>();
    const json& v = j.at("verification");
    o.verified = v.at("verified").get<bool>();
    o.verify_dir = v.at("dir").get<std::string>();
    o.verify_error = v.at("error").get<std::string>();
    o.verify_seconds = v.at("seconds").get<double>();
    if (j.contains("checks")) o.problems = j.at("checks").at("problems").get<std::vector<std::string>>();
  } catch (const json::exception& e) {
    throw UserError(fmt::format("{}: not a calibration file: {}", file.string(), e.what()));
  }
  return o;
}

std::string calibration_text(const CalibrationOutcome& o) {
  std::string text = fmt::format("calibration of {} on {} done samples ({} + {}, {} evaluations)\n", o.study, o.samples,
                                 o.global_algorithm, o.local_algorithm, o.evaluations);
  text += "optimum:\n";
  for (size_t i = 0; i < o.parameters.size(); ++i)
    text += fmt::format("  {:<8} = {:<12.6g} (range [{:g}, {:g}], position {:.4f})\n", o.parameters[i], o.physical[i],
                        o.low[i], o.high[i], o.unit[i]);
  for (const ParameterTie& t : o.ties) text += fmt::format("  {:<8} = {} (tied, same_as)\n", t.name, t.partner);
  text += fmt::format("  {:<14} {:<10} {:>8} {:>14} {:>14} {:>14}\n", "observable", "model", "Q2", "target",
                      "predicted", o.verified ? "measured" : "");
  for (const CalibratedTarget& t : o.targets)
    text += fmt::format("  {:<14} {:<10} {:>8.4f} {:>14.6g} {:>14.6g} {:>14}\n", t.name, t.model, t.q2, t.target,
                        t.predicted, t.measured ? fmt::format("{:.6g}", *t.measured) : "");
  text += fmt::format("misfit J = {:.6g} (sum of weighted squared relative deviations)\n", o.misfit);
  if (!o.verify_dir.empty()) {
    text += o.verified
                ? fmt::format("verified by a real run in {} ({:.1f} s)\n", o.verify_dir.string(), o.verify_seconds)
                : fmt::format("verification failed: {}\n", o.verify_error);
  }
  if (!o.problems.empty()) {
    text += "CHECK FAILED: the targets contradict what the study can produce; this optimum is not an answer:\n";
    for (const std::string& p : o.problems) text += fmt::format("  {}\n", p);
  }
  return text;
}

std::string observed_span_text(const std::string& study, const std::string& observable, double low, double high,
                               int samples, double value) {
  const study::Observable l = experiments::describe_observable(observable);
  const std::string unit = l.unit.empty() ? "" : " " + l.unit;
  std::string text = fmt::format("in study {}, {} spans {:.4g} to {:.4g}{} over its {} done samples", study, l.label,
                                 low * l.factor, high * l.factor, unit, samples);
  if (value < low || value > high)
    text += fmt::format("; {:.4g}{} is {} it", value * l.factor, unit, value < low ? "below" : "above");
  return text;
}

}  // namespace demsa::analysis
