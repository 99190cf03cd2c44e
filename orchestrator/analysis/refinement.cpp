#include "orchestrator/analysis/refinement.hpp"

#include "orchestrator/analysis/fit.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/analysis/training_data.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/design_file.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/observables.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "sobol/augment.hpp"
#include "sobol/gp.hpp"
#include "sobol/scaling.hpp"
#include "sobol/stop.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace demsa::analysis {

using namespace demsa::study;

namespace {

double half_width(const sobol::IndexEstimate& e) { return 0.5 * (e.upper - e.lower); }

nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json estimates_json(const std::vector<sobol::IndexEstimate>& estimates,
                              const std::vector<std::string>& parameters) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < estimates.size() && i < parameters.size(); ++i)
    j[parameters[i]] = {finite_or_null(estimates[i].value), finite_or_null(estimates[i].lower),
                        finite_or_null(estimates[i].upper)};
  return j;
}

}  // namespace

bool RefinementCheck::reached(double target) const {
  if (max_half_width.empty()) return false;
  for (const auto& [name, w] : max_half_width)
    if (!(std::isfinite(w) && w <= target)) return false;
  return true;
}

double RefinementCheck::worst() const {
  double worst = 0.0;
  for (const auto& [name, w] : max_half_width) {
    if (!std::isfinite(w)) return std::numeric_limits<double>::quiet_NaN();
    worst = std::max(worst, w);
  }
  return worst;
}

RefinementCheck check_refinement(const AnalysisSummary& summary) {
  RefinementCheck check;
  nlohmann::ordered_json all = nlohmann::ordered_json::object();
  for (const ObservableAnalysis& o : summary.observables) {
    // The model with the largest Q² among those with intervals (a non-finite Q² ranks last, as in best_by_q2).
    const ModelAnalysis* best = nullptr;
    for (const ModelAnalysis& m : o.models) {
      if (!m.ok || m.indices.bootstrap <= 0) continue;
      const double q2 = std::isfinite(m.quality.q2) ? m.quality.q2 : -std::numeric_limits<double>::infinity();
      const double best_q2 = best == nullptr                   ? -std::numeric_limits<double>::max()
                             : std::isfinite(best->quality.q2) ? best->quality.q2
                                                               : -std::numeric_limits<double>::infinity();
      if (best == nullptr || q2 > best_q2) best = &m;
    }
    if (best == nullptr) {
      check.max_half_width[o.name] = std::numeric_limits<double>::quiet_NaN();
      check.model[o.name] = "";
      all[o.name] = {{"model", nullptr}, {"max_half_width", nullptr}};
      continue;
    }
    double worst = 0.0;
    for (const sobol::IndexEstimate& e : best->indices.first) worst = std::max(worst, half_width(e));
    for (const sobol::IndexEstimate& e : best->indices.total) worst = std::max(worst, half_width(e));
    check.max_half_width[o.name] = worst;
    check.model[o.name] = best->model;
    all[o.name] = {{"model", best->model},
                   {"q2", finite_or_null(best->quality.q2)},
                   {"max_half_width", worst},
                   {"S1", estimates_json(best->indices.first, summary.parameters)},
                   {"ST", estimates_json(best->indices.total, summary.parameters)}};
  }
  check.indices_json = all.dump();
  return check;
}

std::vector<SampleRow> choose_refinement_points(const StudyConfig& config, const Store& store, int batch,
                                                std::uint64_t seed) {
  const std::vector<SampleRow> samples = store.samples();
  const auto observables = store.observables();
  const auto d = static_cast<Eigen::Index>(config.parameters.size());
  Eigen::MatrixXd existing(static_cast<Eigen::Index>(samples.size()), d);
  for (std::size_t i = 0; i < samples.size(); ++i)
    for (Eigen::Index k = 0; k < d; ++k)
      existing(static_cast<Eigen::Index>(i), k) = samples[i].unit.at(static_cast<std::size_t>(k));

  std::vector<FittedMetamodel> fits;
  for (const std::string& name : experiments::observable_names(config)) {
    const TrainingData data = training_data(config, samples, observables, name);
    if (data.size() < 3) continue;
    FittedMetamodel fit =
        fit_metamodel(sobol::MetamodelKind::gp, config.analysis.metamodel_options(), data.unit, data.y);
    if (fit.ok()) fits.push_back(std::move(fit));
  }
  std::vector<const sobol::GaussianProcess*> gps;
  for (const FittedMetamodel& f : fits) gps.push_back(dynamic_cast<const sobol::GaussianProcess*>(f.model.get()));
  Eigen::MatrixXd unit;
  if (gps.empty()) {
    unit = sobol::extend_lhs(existing, batch, seed);
  } else {
    sobol::VarianceSelectionOptions options;
    options.batch = batch;
    options.candidates = std::max(1000, 50 * batch);
    options.seed = seed;
    unit = sobol::select_by_variance(gps, existing, options);
  }
  std::vector<sobol::Bounds> bounds;
  for (const ParameterRange& p : config.parameters) bounds.push_back(p.bounds);
  const Eigen::MatrixXd physical = sobol::to_physical(unit, bounds);
  std::vector<SampleRow> rows;
  const int next = samples.empty() ? 0 : samples.back().sample + 1;
  for (Eigen::Index i = 0; i < unit.rows(); ++i) {
    SampleRow row;
    row.sample = next + static_cast<int>(i);
    for (Eigen::Index k = 0; k < d; ++k) {
      row.unit.push_back(unit(i, k));
      row.physical.push_back(physical(i, k));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

std::string refine_history_csv(const std::vector<RefineStep>& steps) {
  std::set<std::string> names;
  for (const RefineStep& s : steps)
    for (const auto& [name, w] : s.max_half_width) names.insert(name);
  std::string text = "iteration,samples,decision,target";
  for (const std::string& n : names) text += ",max_half_width_" + n;
  text += "\n";
  for (const RefineStep& s : steps) {
    text += fmt::format("{},{},{},{:.6g}", s.iteration, s.samples, s.decision, s.target);
    for (const std::string& n : names) {
      const auto it = s.max_half_width.find(n);
      text += ",";
      if (it != s.max_half_width.end() && std::isfinite(it->second)) text += fmt::format("{:.6g}", it->second);
    }
    text += "\n";
  }
  return text;
}

std::string refine_history_json(const std::vector<RefineStep>& steps) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const RefineStep& s : steps) {
    nlohmann::ordered_json widths = nlohmann::ordered_json::object();
    for (const auto& [name, w] : s.max_half_width) widths[name] = finite_or_null(w);
    j.push_back({{"iteration", s.iteration},
                 {"samples", s.samples},
                 {"decision", s.decision},
                 {"target", s.target},
                 {"time", s.time},
                 {"max_half_width", widths},
                 {"indices", s.indices_json.empty() ? nlohmann::ordered_json::object()
                                                    : nlohmann::ordered_json::parse(s.indices_json)}});
  }
  return j.dump(2) + "\n";
}

std::string half_width_text(double width) {
  return std::isfinite(width) ? fmt::format("{:.4f}", width) : std::string("none");
}

namespace {

void write_refine_history(const std::filesystem::path& dir, const std::vector<study::RefineStep>& steps) {
  const std::filesystem::path out = dir / study::k_analysis_folder;
  std::filesystem::create_directories(out);
  util::write_file_atomically(out / study::k_refine_csv, refine_history_csv(steps));
  util::write_file_atomically(out / study::k_refine_json, refine_history_json(steps));
}

}  // namespace

RefineSummary refine_study(const RefineOptions& options) {
  using study::RefineStep;
  using study::SampleRow;
  using study::Store;
  const std::filesystem::path& dir = options.dir;
  const std::filesystem::path study_file = dir / study::k_frozen_study;
  const auto should_stop = [&options] { return options.should_stop && options.should_stop(); };
  RefineSummary result;
  result.max_samples = options.max_samples;
  if (result.max_samples == 0)
    result.max_samples = 2L * Store::open_read_only((dir / study::k_store_file).string()).design_samples();
  if (options.on_start) options.on_start(result.max_samples);

  for (;;) {
    const RefineRun ran = options.run_cases();
    if (ran.interrupted) {
      result.end = RefineEnd::stopped_in_runs;
      return result;
    }
    if (ran.done < 2)
      throw util::UserError(
          fmt::format("{}: {} of {} samples done; the indices need at least 2", dir.string(), ran.done, ran.samples));
    result.done = ran.done;

    // The analysis and the new samples hold the study as `demsa analyze` does (no `demsa run` in between).
    const auto lock = study::hold_study_for_results(dir);
    AnalyzeOptions analyze;
    analyze.dir = dir;
    analyze.second_order = 0;  // the stop rule reads S1 and ST; the last step computes S2 if the study asks
    analyze.should_stop = should_stop;
    try {
      result.analysis = analyze_study(analyze);
    } catch (const sobol::Stopped&) {
      result.end = RefineEnd::stopped_in_analysis;
      return result;
    }
    const RefinementCheck check = check_refinement(result.analysis);
    result.worst = check.worst();

    Store store((dir / study::k_store_file).string());
    const study::StudyConfig config = experiments::load_study(study_file);
    const std::vector<SampleRow> samples = store.samples();
    std::vector<RefineStep> history = store.refine_history();
    RefineStep step;
    step.iteration = static_cast<int>(history.size()) + 1;
    for (const RefineStep& h : history)
      if (h.samples == ran.done) step.iteration = h.iteration;
    step.samples = ran.done;
    step.target = options.target;
    step.time = study::unix_now();
    step.max_half_width = check.max_half_width;
    step.indices_json = check.indices_json;
    const bool reached = check.reached(options.target);
    const long room = result.max_samples - static_cast<long>(samples.size());
    std::vector<SampleRow> added;
    if (reached) {
      step.decision = "reached";
    } else if (room <= 0) {
      step.decision = "budget";
    } else {
      const int batch = static_cast<int>(std::min<long>(options.batch, room));
      // One seed per step: the study's, mixed with the number of samples it starts from.
      const std::uint64_t seed = config.seed ^ (0xD1B54A32D192ED03ULL * static_cast<std::uint64_t>(samples.size()));
      added = choose_refinement_points(config, store, batch, seed);
      step.decision = fmt::format("added {}", added.size());
    }
    store.record_refine_step(step);
    if (!added.empty())
      store.add_samples(
          added, "refined",
          fmt::format("{} samples added by refine step {} (samples {} to {}; worst half-width {})", added.size(),
                      step.iteration, added.front().sample, added.back().sample, half_width_text(check.worst())));
    util::write_file_atomically(dir / study::k_design_file, study::design_csv(config, store.samples()));
    history = store.refine_history();
    write_refine_history(dir, history);
    if (options.on_step) options.on_step(step);
    if (added.empty()) {
      if (config.analysis.second_order) {
        analyze.second_order = -1;
        try {
          result.analysis = analyze_study(analyze);
        } catch (const sobol::Stopped&) {
          result.end = RefineEnd::stopped;
          return result;
        }
        write_refine_history(dir, history);  // the analysis folder was rewritten
      }
      result.end = reached ? RefineEnd::reached : RefineEnd::budget;
      return result;
    }
    if (should_stop()) {
      result.end = RefineEnd::stopped;
      return result;
    }
  }
}

std::string refine_start_text(const RefineOptions& options, long max_samples) {
  return fmt::format("refine {}: target half-width {}, batches of {}, at most {} samples\n", options.dir.string(),
                     options.target, options.batch, max_samples);
}

std::string refine_step_text(const study::RefineStep& step) {
  std::string widths;
  for (const auto& [name, w] : step.max_half_width) widths += fmt::format("  {} {}", name, half_width_text(w));
  return fmt::format("refine: step {:>3}  {:>5} samples  max half-width:{}  -> {}\n", step.iteration, step.samples,
                     widths, step.decision);
}

std::string refine_end_text(const RefineSummary& refined, const RefineOptions& options) {
  const std::string dir = options.dir.string();
  switch (refined.end) {
    case RefineEnd::stopped_in_runs:
      return fmt::format("interrupted: `demsa refine {} --target-ci {}` resumes\n", dir, options.target);
    case RefineEnd::stopped_in_analysis:
      return fmt::format("interrupted during the analysis: `demsa refine {} --target-ci {}` resumes\n", dir,
                         options.target);
    case RefineEnd::stopped:
      return "";
    case RefineEnd::reached:
      return analysis_tables_text(refined.analysis) +
             fmt::format("refine: every S1 and ST half-width is at most {} with {} samples\n", options.target,
                         refined.done);
    case RefineEnd::budget:
      return analysis_tables_text(refined.analysis) +
             fmt::format("refine: the budget of {} samples is spent; worst half-width {} > {}\n", refined.max_samples,
                         half_width_text(refined.worst), options.target);
  }
  return "";
}

}  // namespace demsa::analysis
