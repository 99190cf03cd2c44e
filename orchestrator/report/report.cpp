#include "orchestrator/report/report.hpp"

#include "orchestrator/experiments/case_record.hpp"

#include "orchestrator/report/posterior_plots.hpp"

#include "orchestrator/analysis/analysis_json.hpp"
#include "orchestrator/analysis/calibration.hpp"
#include "orchestrator/analysis/calibration_posterior.hpp"
#include "orchestrator/analysis/experiment_plan.hpp"
#include "orchestrator/analysis/fit.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/analysis/training_data.hpp"
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/observables.hpp"
#include "orchestrator/study/parameters.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"
#include "postprocess/error.hpp"
#include "sobol/metamodel.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <exception>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>
#include <type_traits>
#include <variant>

namespace demsa::report {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::analysis;

namespace fs = std::filesystem;

namespace {

/// A number with 3 significant digits, small ones in scientific notation (as the paper's tables: 3.7E-5).
std::string short_number(double v) {
  if (!std::isfinite(v)) return "n/a";
  // Below 1e-6 an index is round-off of a zero (exact RSM indices come out as 1e-31).
  if (std::abs(v) < 1e-6) return "0";
  if (std::abs(v) < 1e-3 || std::abs(v) >= 1e5) return fmt::format("{:.2e}", v);
  return fmt::format("{:.3g}", v);
}

}  // namespace

std::string format_interval(double value, double low, double high) {
  // One format for every cell of an index column: three decimals (an index of 3.7e-5 is 0.000 at the precision its
  // interval has), no "-0.000" for round-off of a zero.
  const auto fixed = [](double v) {
    if (!std::isfinite(v)) return std::string("n/a");
    return fmt::format("{:.3f}", std::abs(v) < 5e-4 ? 0.0 : v);
  };
  std::string text = fixed(value);
  // An interval that rounds onto the value (exact indices) is left out.
  const bool has = std::isfinite(low) && std::isfinite(high) && !(fixed(low) == text && fixed(high) == text);
  // An index lies in [0, 1]: a lower bound below 0 (estimator noise) is shown clipped at 0 and marked; the raw bound
  // stays in analysis.json.
  if (has) text += fmt::format(" [{}, {}]", low <= -5e-4 ? std::string(k_clipped_low) : fixed(low), fixed(high));
  return text;
}

void ReportOptions::validate() const {
  if (dir.empty()) throw UserError("report: a study folder is required");
  if (sample < -1) throw UserError(fmt::format("ReportOptions.sample {}: must be a sample index >= 0", sample));
  plot.validate();
}

// ------------------------------------------------------------------------------------------ the study report

namespace {

/// The paragraph of a failed calibration check: what failed, then each problem found.
std::string check_failed(const std::string& what, const std::vector<std::string>& problems) {
  std::string text = "**Check failed: " + what + ".**";
  for (const std::string& problem : problems) text += " " + problem + ".";
  return text;
}

constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();

/// A parameter's symbol for tables ("μ_R,PP"), in gnuplot's enhanced text ("μ_{R,PP}") and its unit, from
/// study::contact_parameters(); a name that is not a contact parameter (an edited analysis.json) stands for itself.
struct ParameterText {
  std::string symbol;
  std::string gnuplot;
  std::string unit;
};

/// With `ties`, a parameter that others are tied to names them: "μ_PP = μ_PW".
ParameterText parameter_text(const std::string& name, const std::vector<ParameterTie>& ties = {}) {
  if (const ContactParameter* p = find_contact_parameter(name))
    return {symbol_with_ties(name, ties), symbol_with_ties(name, ties, true), std::string(p->unit)};
  return {name, name, "-"};
}

/// "angle of repose [°]", or the bare label of an observable without a unit.
std::string axis_label(const std::string& observable) {
  const Observable o = experiments::describe_observable(observable);
  return o.unit.empty() ? o.label : fmt::format("{} [{}]", o.label, o.unit);
}

std::string model_title(const std::string& model) {
  static const std::map<std::string, std::string> titles{{"rsm1", "RSM linear"},     {"rsm2", "RSM quad."},
                                                         {"rsm3", "RSM cub."},       {"rbf-cubic", "RBF cub."},
                                                         {"rbf-tps", "RBF th. pl."}, {"gp", "Gaussian process"}};
  const auto it = titles.find(model);
  return it == titles.end() ? model : it->second;
}

std::string hours(double seconds) {
  return seconds >= 3600 * 10 ? fmt::format("{:.1f} h", seconds / 3600) : fmt::format("{:.3f} h", seconds / 3600);
}

/// "0.9871", or "n/a" for NaN.
std::string fixed4(double v) { return std::isfinite(v) ? fmt::format("{:.4f}", v) : "n/a"; }

IntervalValue interval(const sobol::IndexEstimate& e) { return {e.value, e.lower, e.upper}; }

std::string interval_text(const IntervalValue& v) { return format_interval(v.value, v.low, v.high); }

struct StudyData {
  StudyConfig config;
  std::vector<SampleRow> samples;
  std::map<int, std::map<std::string, double>> observables;
  std::vector<RunRow> runs;
  StoreCounts counts;
  std::vector<RefineStep> refine;  ///< `demsa refine`'s steps (empty when never refined)
  std::vector<CaseCostRow> costs;  ///< predicted against actual per done case (exec/cost.hpp); empty before the bill
};

/// What the done cases cost against what the bill predicted before each ran (the store's case_costs, written by
/// `demsa run`): the totals and the ratios, then one row per case. Nothing when no case was recorded.
std::optional<ReportSection> cost_section(const std::vector<CaseCostRow>& rows) {
  if (rows.empty()) return std::nullopt;
  ReportSection section;
  section.heading = "What the cases cost";
  double predicted_steps = 0, steps = 0, predicted_cpu = 0, cpu_with_prediction = 0, cpu = 0;
  for (const CaseCostRow& r : rows) {
    predicted_steps += r.predicted_atom_steps;
    steps += r.atom_steps;
    cpu += r.cpu_seconds;
    if (r.predicted_cpu_seconds > 0) {
      predicted_cpu += r.predicted_cpu_seconds;
      cpu_with_prediction += r.cpu_seconds;
    }
  }
  section.paragraphs.push_back(fmt::format(
      "{} done cases: {:.3g} atom-steps against {:.3g} predicted before each ran (actual / predicted {:.2f}); {:.0f} "
      "CPU-s{}. A prediction is the case's schedule (its cap, times the ratio actual / cap of the cases done before "
      "it) at the rate known then: the standard run's of this LIGGGHTS (`demsa --version`), then the study's own "
      "(docs/how-to/cost.md).",
      rows.size(), steps, predicted_steps, predicted_steps > 0 ? steps / predicted_steps : k_nan, cpu,
      predicted_cpu > 0 ? fmt::format(" against {:.0f} predicted for the cases that had a rate (actual / predicted "
                                      "{:.2f})",
                                      predicted_cpu, cpu_with_prediction / predicted_cpu)
                        : std::string(", with no rate known before they ran")));
  ReportTable table;
  table.caption = "Predicted against actual, per done case";
  table.header = {
      "sample",         "cap atom-steps",        "predicted atom-steps", "actual atom-steps", "predicted CPU [s]",
      "actual CPU [s]", "actual / predicted CPU"};
  for (const CaseCostRow& r : rows)
    table.rows.push_back(
        {std::to_string(r.sample), fmt::format("{:.3g}", r.cap_atom_steps),
         fmt::format("{:.3g}", r.predicted_atom_steps), fmt::format("{:.3g}", r.atom_steps),
         r.predicted_cpu_seconds > 0 ? fmt::format("{:.1f}", r.predicted_cpu_seconds) : "—",
         fmt::format("{:.1f}", r.cpu_seconds),
         r.predicted_cpu_seconds > 0 ? fmt::format("{:.2f}", r.cpu_seconds / r.predicted_cpu_seconds) : "—"});
  section.tables.push_back(table);
  return section;
}

ReportSection summary_section(const StudyData& s) {
  ReportSection section;
  section.heading = "Study";
  const StudyConfig& c = s.config;
  const std::string experiment = fmt::format("{} ({})", c.experiment, experiments::of(c).summary);
  section.paragraphs.push_back(fmt::format("Study {}: {} experiment, design `{}` of {} samples, seed {}.",
                                           code_span(c.name), experiment, c.design, c.samples, c.seed));
  double cpu = 0;
  double wall = 0;
  std::map<std::string, int> failed_attempts;
  std::map<int, std::string> last_failure;
  std::map<int, bool> done;
  for (const RunRow& r : s.runs) {
    cpu += r.cpu_seconds;
    wall += r.wall_seconds;
    if (r.state == RunState::done) done[r.sample] = true;
    if (r.state == RunState::failed) {
      ++failed_attempts[to_string(r.failure)];
      last_failure[r.sample] = to_string(r.failure);
    }
  }
  std::map<std::string, int> failed_samples;
  for (const auto& [sample, cls] : last_failure)
    if (!done.count(sample)) ++failed_samples[cls];
  section.paragraphs.push_back(
      fmt::format("Samples: {} in the design, {} done, {} failed, {} running, {} pending; {} run attempts in all. "
                  "CPU time of all attempts: {} (wall time {}, mean {:.1f} s per done case).",
                  s.counts.samples, s.counts.done, s.counts.failed, s.counts.running, s.counts.pending,
                  s.counts.attempts, hours(cpu), hours(wall), s.counts.mean_done_wall));

  ReportTable parameters;
  parameters.caption = "Varied parameters (paper Table 3)";
  parameters.header = {"parameter", "symbol", "low", "high", "scale", "unit"};
  for (const ParameterRange& p : c.parameters) {
    const ParameterText l = parameter_text(p.name, c.ties);
    parameters.rows.push_back({p.name, l.symbol, fmt::format("{:g}", p.bounds.low), fmt::format("{:g}", p.bounds.high),
                               sobol::to_string(p.bounds.scale), l.unit});
  }
  for (const ParameterTie& t : c.ties)  // no range of its own: its partner's value in every case
    parameters.rows.push_back({t.name, symbol_with_ties(t.partner, c.ties), "same as " + t.partner, "", "", ""});
  section.tables.push_back(parameters);

  ReportTable failures;
  failures.caption = "Failures by class (samples not done whose last attempt failed; all failed attempts)";
  failures.header = {"failure class", "samples", "attempts"};
  for (const auto& [cls, n] : failed_attempts)
    failures.rows.push_back(
        {cls, std::to_string(failed_samples.count(cls) ? failed_samples.at(cls) : 0), std::to_string(n)});
  if (failures.rows.empty())
    section.paragraphs.push_back("No failed attempts.");
  else
    section.tables.push_back(failures);
  // Piles that reached settle_time still moving are measured and counted, but said here.
  const std::vector<int> unsettled = unsettled_samples(s.observables);
  if (!unsettled.empty())
    section.paragraphs.push_back(fmt::format(
        "**Unsettled: {} of {} done samples** (sample {}) were still moving at the end of settling: more particles "
        "moving than the settling criterion allows at the cap, or an angle that still drifted by more than `[pile] "
        "drift_limit`; they are measured and counted in the analysis.",
        unsettled.size(), s.counts.done, experiments::unsettled_text(s.observables)));
  return section;
}

/// Tables and plots of one observable.
ReportSection observable_section(const StudyData& s, const ObservableAnalysis& observable,
                                 const std::vector<std::string>& names, const Plotter& plotter, const fs::path& out,
                                 ReportSummary& summary) {
  const std::string& name = observable.name;
  const Observable label = experiments::describe_observable(name);
  ReportSection section;
  section.heading = fmt::format("Observable `{}`: {}", name, label.label);
  section.paragraphs.push_back(fmt::format("{} samples; mean {} {}, standard deviation {} {}.", observable.samples,
                                           short_number(observable.mean * label.factor), label.unit,
                                           short_number(observable.sd * label.factor), label.unit));
  if (!observable.error.empty()) {
    section.paragraphs.push_back(fmt::format("Not analysed: {}", observable.error));
    return section;
  }
  const TrainingData data = training_data(s.config, s.samples, s.observables, name);
  if (data.y.size() < 2) {
    section.paragraphs.push_back("Too few done samples measure it: no tables and no plots.");
    return section;
  }
  const std::vector<ModelAnalysis>& models = observable.models;
  std::vector<std::string> symbols;
  for (const std::string& p : names) symbols.push_back(parameter_text(p, s.config.ties).symbol);

  ReportTable quality;
  quality.caption = "Metamodel quality: R² on the samples, adjusted R², leave-one-out Q² and RMSE";
  quality.header = {"metamodel", "terms", "R²", "adj. R²", "Q²", "RMSE_LOO"};
  for (const ModelAnalysis& m : models) {
    if (!m.fitted) {
      quality.rows.push_back({model_title(m.model), "", "", "", "", "not fitted: " + m.error});
      continue;
    }
    // Fitted without indices (Q² not computable): the reason in the RMSE_LOO column it lacks.
    quality.rows.push_back({model_title(m.model), std::to_string(m.quality.terms), fixed4(m.quality.r2),
                            fixed4(m.quality.adjusted_r2), fixed4(m.quality.q2),
                            m.ok ? short_number(m.quality.rmse_loo * label.factor) : m.error});
  }
  section.tables.push_back(quality);

  ReportTable first;
  ReportTable total;
  first.caption =
      "First-order Sobol' indices S1 and residual 1 − ΣS1 (the layout of the paper's Tables 4–7), with "
      "confidence intervals";
  total.caption = "Total-effect Sobol' indices ST, with confidence intervals";
  first.header = {"metamodel"};
  total.header = {"metamodel"};
  for (const std::string& sym : symbols) {
    first.header.push_back(sym);
    total.header.push_back(sym);
  }
  first.header.push_back("Res");
  // DEM noise ([design] replicates): its share of the observable's variance over the design, beside the indices.
  const std::optional<NoiseAnalysis>& noise = observable.noise;
  if (noise) {
    first.header.push_back("noise");
    first.caption += "; noise: the DEM noise's share of the variance over the design (from the replicate cases)";
    const sobol::NoiseEstimate& e = noise->estimate;
    section.paragraphs.push_back(fmt::format(
        "DEM noise, measured from {} replicated points ({} cases, {} degrees of freedom; another particle packing "
        "at the same parameters): noise variance {} {}² ({:.0f} % chi-square interval {} to {}), standard deviation "
        "{} {}; {:.1f} % of the variance over the design (interval {:.1f} % to {:.1f} %). The GP's nugget is set "
        "from it.{}",
        e.points, e.values, e.dof, short_number(e.variance * label.factor * label.factor), label.unit,
        100.0 * e.confidence, short_number(e.lower * label.factor * label.factor),
        short_number(e.upper * label.factor * label.factor), short_number(std::sqrt(e.variance) * label.factor),
        label.unit, 100.0 * noise->share, 100.0 * noise->share_lower, 100.0 * noise->share_upper,
        noise->dominates
            ? fmt::format(
                  " **The noise dominates**: its share {:.2f} exceeds {}. The indices describe less of this "
                  "observable than the noise does; more particles, a longer settling or the mean of "
                  "repeats reduce it.",
                  noise->share,
                  noise->share > 0.5 ? std::string("0.5") : fmt::format("the largest S1 ({:.2f})", noise->largest_s1))
            : std::string()));
  }
  std::vector<ReportTable> second_tables;
  for (const ModelAnalysis& m : models) {
    if (!m.ok) continue;
    std::vector<std::string> row1{model_title(m.model)};
    std::vector<std::string> rowt{model_title(m.model)};
    SobolBarChart chart;
    chart.title = fmt::format("{}, {}: Sobol' indices ({})", label.label, model_title(m.model), m.indices.method);
    for (size_t k = 0; k < names.size(); ++k) {
      const IntervalValue s1 = interval(m.indices.first.at(k));
      const IntervalValue st = interval(m.indices.total.at(k));
      row1.push_back(interval_text(s1));
      rowt.push_back(interval_text(st));
      chart.parameters.push_back(parameter_text(names[k], s.config.ties).gnuplot);
      chart.first_order.push_back(s1);
      chart.total_effect.push_back(st);
    }
    row1.push_back(interval_text(interval(m.indices.residual)));
    if (noise)
      row1.push_back(fmt::format("{:.3f} [{:.3f}, {:.3f}]{}", noise->share, noise->share_lower, noise->share_upper,
                                 noise->dominates ? " (dominates)" : ""));
    first.rows.push_back(row1);
    bool clipped = false;
    for (size_t k = 0; k < names.size(); ++k)
      clipped = clipped || m.indices.first.at(k).lower <= -5e-4 || m.indices.total.at(k).lower <= -5e-4;
    for (const sobol::SecondOrderIndex& e : m.indices.second) clipped = clipped || e.s.lower <= -5e-4;
    clipped = clipped || m.indices.residual.lower <= -5e-4;
    if (clipped)
      section.paragraphs.push_back(
          fmt::format("{}: {} marks an interval whose lower bound is below 0, shown clipped "
                      "at 0 (an index lies in [0, 1]; the raw bound is in analysis.json).",
                      model_title(m.model), k_clipped_low));
    if (!m.indices.note.empty())
      section.paragraphs.push_back(fmt::format("{}: {}.", model_title(m.model), m.indices.note));
    total.rows.push_back(rowt);
    if (!m.indices.second.empty()) {
      ReportTable s2;
      s2.caption =
          fmt::format("Second-order indices S2 ({}): row parameter with column parameter", model_title(m.model));
      s2.header = {""};
      for (size_t j = 1; j < names.size(); ++j) s2.header.push_back(symbols[j]);
      std::map<std::pair<int, int>, std::string> cells;
      for (const sobol::SecondOrderIndex& e : m.indices.second) cells[{e.i, e.j}] = interval_text(interval(e.s));
      for (size_t i = 0; i + 1 < names.size(); ++i) {
        std::vector<std::string> row{symbols[i]};
        for (size_t j = 1; j < names.size(); ++j) {
          const auto it = cells.find({static_cast<int>(i), static_cast<int>(j)});
          row.push_back(j > i && it != cells.end() ? it->second : "");
        }
        s2.rows.push_back(row);
      }
      second_tables.push_back(s2);
    }
    const std::string stem = fmt::format("sobol_{}_{}", name, m.model);
    section.figures.push_back({fmt::format("Sobol' indices of {} from the {} metamodel; whiskers: confidence "
                                           "interval",
                                           label.label, model_title(m.model)),
                               plot_sobol_bars(plotter, chart, out / stem)});
    summary.images.push_back(section.figures.back().files.png);
  }
  section.tables.push_back(first);
  section.tables.push_back(total);
  for (const ReportTable& t : second_tables) section.tables.push_back(t);

  // Leave-one-out predictions: the metamodels are refitted to the same samples as the analysis.
  for (const ModelAnalysis& m : models) {
    if (!m.ok) continue;
    try {
      const FittedMetamodel fit = fit_metamodel(
          sobol::metamodel_kind_from_string(m.model),
          with_measured_noise(s.config.analysis.metamodel_options(), observable.noise, data.y), data.unit, data.y);
      if (!fit.ok()) std::rethrow_exception(fit.exception);
      const Eigen::VectorXd residuals = fit.model->loo_residuals();
      PredictedVsObserved p;
      p.title = fmt::format("{}, {}: leave-one-out prediction", label.label, model_title(m.model));
      p.response_label = label.unit.empty() ? "" : fmt::format("[{}]", label.unit);
      for (Eigen::Index i = 0; i < data.y.size(); ++i) {
        p.observed.push_back(data.y(i) * label.factor);
        p.predicted.push_back((data.y(i) - residuals(i)) * label.factor);
      }
      p.r2 = m.quality.r2;
      p.q2 = m.quality.q2;
      const std::string stem = fmt::format("loo_{}_{}", name, m.model);
      section.figures.push_back({fmt::format("{}: each sample predicted by the {} metamodel fitted without it",
                                             label.label, model_title(m.model)),
                                 plot_predicted_vs_observed(plotter, p, out / stem)});
      summary.images.push_back(section.figures.back().files.png);
    } catch (const std::exception& e) {
      summary.notes.push_back(fmt::format("{} / {}: no leave-one-out plot: {}", name, m.model, e.what()));
    }
  }

  ResponseScatter scatter;
  scatter.title = fmt::format("{} against each parameter", label.label);
  scatter.response_label = axis_label(name);
  scatter.physical = data.physical;
  for (Eigen::Index i = 0; i < data.y.size(); ++i) scatter.response.push_back(data.y(i) * label.factor);
  for (const ParameterRange& p : s.config.parameters) {
    const ParameterText l = parameter_text(p.name, s.config.ties);
    scatter.parameter_labels.push_back(fmt::format("{} [{}]", l.gnuplot, l.unit));
    scatter.log_scale.push_back(p.bounds.scale == sobol::Scale::log_uniform);
  }
  section.figures.push_back({fmt::format("{} of every done sample against each varied parameter", label.label),
                             plot_response_scatter(plotter, scatter, out / fmt::format("response_{}", name))});
  summary.images.push_back(section.figures.back().files.png);
  return section;
}

/// The done sample shown in the figures of one case.
int choose_sample(const StudyData& s, int requested) {
  if (requested >= 0) {
    if (!s.observables.count(requested))
      throw UserError(fmt::format("ReportOptions.sample {}: not a done sample of this study", requested));
    return requested;
  }
  if (s.observables.empty()) return -1;
  const experiments::ReportFocus focus = experiments::of(s.config).report_focus(s.config);
  const std::string& key = focus.observable;
  double goal = 0;
  if (focus.value) {
    goal = *focus.value;
  } else {
    // No value aimed at: the median of the study's values.
    std::vector<double> values;
    for (const auto& [sample, v] : s.observables)
      if (v.count(key)) values.push_back(v.at(key));
    if (values.empty()) return s.observables.begin()->first;
    std::nth_element(values.begin(), values.begin() + static_cast<long>(values.size() / 2), values.end());
    goal = values[values.size() / 2];
  }
  int best = s.observables.begin()->first;
  double distance = std::numeric_limits<double>::infinity();
  for (const auto& [sample, v] : s.observables) {
    const auto it = v.find(key);
    if (it == v.end()) continue;
    if (std::abs(it->second - goal) < distance) {
      distance = std::abs(it->second - goal);
      best = sample;
    }
  }
  return best;
}

/// The photograph given as ReportOptions::lab_file cannot be set against the case: the report asked for is not written
/// without it (exit 2), unlike a case whose own figures fail, which is a note.
class PhotographError : public UserError {
 public:
  using UserError::UserError;
};

/// The experiment's section on one case, its figures drawn (experiments::CaseReport).
ReportSection case_section(const StudyData& s, int sample, const Plotter& plotter, const fs::path& out,
                           const fs::path& dir, const fs::path& lab_file, ReportSummary& summary) {
  const fs::path folder = case_dir(dir, sample);
  const experiments::CaseReport r =
      experiments::of(s.config).case_report(folder, fs::relative(folder, dir).generic_string(), sample, s.config);
  ReportSection section;
  section.heading = r.heading;
  section.paragraphs = r.paragraphs;
  section.tables = r.tables;
  for (const experiments::CaseFigure& f : r.figures) {
    const fs::path stem = out / f.stem;
    const PlotFiles files = std::visit(
        [&](const auto& data) -> PlotFiles {
          using T = std::decay_t<decltype(data)>;
          if constexpr (std::is_same_v<T, PileSideView>)
            return plot_pile_side(plotter, data, stem);
          else if constexpr (std::is_same_v<T, SettlementCurve>)
            return plot_settlement_curve(plotter, data, stem);
          else if constexpr (std::is_same_v<T, PlateHistoryPlot>)
            return plot_plate_history(plotter, data, stem);
          else if constexpr (std::is_same_v<T, ImageFigure>)
            return plot_image(data, stem);
          else {
            static_assert(std::is_same_v<T, LinePlot>, "a figure kind of experiments/case_report.hpp without a plot");
            return plot_lines(plotter, data, stem);
          }
        },
        f.data);
    section.figures.push_back({f.caption, files});
    summary.images.push_back(files.png);
  }
  for (const std::string& note : r.notes) summary.notes.push_back(note);
  if (!lab_file.empty()) {
    // The case against the laboratory's own picture of the setup: where the two disagree, and by how much.
    const experiments::Experiment& experiment = experiments::of(s.config);
    const fs::path overlay = out / "lab_overlay.png";
    experiments::LabComparison c;
    try {
      c = experiment.compare_with_lab_file(folder, experiments::read_case_json(folder), lab_file, overlay);
    } catch (const UserError& e) {
      throw PhotographError(
          fmt::format("ReportOptions.lab_file {}: against sample {}: {}", lab_file.string(), sample, e.what()));
    } catch (const postprocess::ParseError& e) {
      throw PhotographError(
          fmt::format("ReportOptions.lab_file {}: against sample {}: {}", lab_file.string(), sample, e.what()));
    } catch (const postprocess::InputError& e) {
      throw PhotographError(
          fmt::format("ReportOptions.lab_file {}: against sample {}: {}", lab_file.string(), sample, e.what()));
    }
    section.paragraphs.push_back(fmt::format(
        "Against the photograph `{}`: the case and the photograph disagree about material over {:.1f} mm² {} (below: "
        "the photograph in grey, the case's bed in blue over it, light where the photograph has no material).",
        lab_file.filename().string(), c.mismatch_m2 * 1e6, c.region));
    PlotFiles files;
    files.png = overlay;
    section.figures.push_back({fmt::format("Sample {} superimposed on the photograph {}: mismatch area {:.1f} mm² {}",
                                           sample, lab_file.filename().string(), c.mismatch_m2 * 1e6, c.region),
                               files});
    summary.images.push_back(overlay);
    if (!c.lab_picture.empty()) {
      PlotFiles lab;
      lab.png = c.lab_picture;
      section.figures.push_back(
          {fmt::format("The photograph {} measured on its own, as demsa measure reads it: its material in grey (the "
                       "bed black), its free surface (red), the surface's band (yellow), the dynamic angle's line "
                       "(green), the stations (magenta) and the judged circle (cyan)",
                       lab_file.filename().string()),
           lab});
      summary.images.push_back(c.lab_picture);
    }
  }
  return section;
}

/// The observables measured at several times, NAME@T (the pile's angle@0.6 of [pile] measure_times), by family: NAME
/// -> (T, its analysis), in order of T. A family of one time is left out.
std::map<std::string, std::vector<std::pair<double, const ObservableAnalysis*>>> timed_families(
    const AnalysisSummary& analysis) {
  std::map<std::string, std::vector<std::pair<double, const ObservableAnalysis*>>> families;
  for (const ObservableAnalysis& o : analysis.observables)
    if (const std::optional<TimedName> timed = timed_name(o.name))
      families[timed->family].emplace_back(timed->time, &o);
  for (auto it = families.begin(); it != families.end();) {
    std::sort(it->second.begin(), it->second.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    it = it->second.size() < 2 ? families.erase(it) : std::next(it);
  }
  return families;
}

/// "0.63 [0.55, 0.70]"; "n/a" for NaN.
std::string index_text(const sobol::IndexEstimate& e) {
  if (!std::isfinite(e.value)) return "n/a";
  if (!std::isfinite(e.lower) || !std::isfinite(e.upper)) return fmt::format("{:.2f}", e.value);
  return fmt::format("{:.2f} [{:.2f}, {:.2f}]", e.value, e.lower, e.upper);
}

/// One family of timed observables (timed_families): S1 and ST of each parameter against time, from the metamodel
/// fitted at every time with the best mean Q², as tables with their intervals and as two plots.
ReportSection timed_section(const std::string& family,
                            const std::vector<std::pair<double, const ObservableAnalysis*>>& times,
                            const std::vector<std::string>& names, const Plotter& plotter, const fs::path& out,
                            ReportSummary& summary) {
  ReportSection section;
  section.heading = fmt::format("`{}` against time: which parameter matters when", family);
  // The metamodel fitted at every time, with the best mean Q² over the times (a Q² that is not finite, of a model with
  // as many terms as samples, counts as the worst).
  std::map<std::string, std::pair<int, double>> q2;  // model -> (times fitted, sum of Q²)
  for (const auto& [t, o] : times)
    for (const ModelAnalysis& m : o->models)
      if (m.ok) {
        q2[m.model].first += 1;
        q2[m.model].second += std::isfinite(m.quality.q2) ? m.quality.q2 : -1e300;
      }
  std::string model;
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& [name, fitted] : q2)
    if (fitted.first == static_cast<int>(times.size()) && (model.empty() || fitted.second / fitted.first > best)) {
      best = fitted.second / fitted.first;
      model = name;
    }
  if (best < -1e299) best = k_nan;
  if (model.empty()) {
    section.paragraphs.push_back("No metamodel was fitted at every time: no indices against time.");
    return section;
  }
  const Observable label = experiments::describe_observable(times.front().second->name);
  double confidence = k_nan;
  for (const ModelAnalysis& m : times.front().second->models)
    if (m.model == model) confidence = m.indices.confidence;
  section.paragraphs.push_back(fmt::format(
      "The same runs measured at {} times (the observables `{}@T`); indices of the {} metamodel ({}), with their "
      "{:.0f}% intervals. Where the ranking changes with time, the answer to \"which parameter matters\" depends on "
      "when the pile is measured.",
      times.size(), family, model_title(model),
      std::isfinite(best)
          ? fmt::format("mean Q² {:.3f} over the times, the best of the metamodels fitted at every time", best)
          : std::string("fitted at every time; Q² not defined"),
      confidence * 100));
  std::vector<std::string> symbols;
  for (const std::string& p : names) symbols.push_back(parameter_text(p).symbol);
  ReportTable first;
  ReportTable total;
  first.caption = fmt::format("S1 of `{}` against time ({})", family, model_title(model));
  total.caption = fmt::format("ST of `{}` against time ({})", family, model_title(model));
  first.header = {"time [s]", fmt::format("mean ± sd [{}]", label.unit)};
  for (const std::string& sym : symbols) first.header.push_back(sym);
  total.header = first.header;
  LinePlot s1_plot;
  LinePlot st_plot;
  s1_plot.title = fmt::format("S1 of {} against time ({})", family, model_title(model));
  st_plot.title = fmt::format("ST of {} against time ({})", family, model_title(model));
  s1_plot.x_label = st_plot.x_label = "time after the last disc [s]";
  s1_plot.y_label = "S1";
  st_plot.y_label = "ST";
  // matplotlib's tab10: one distinct colour per parameter.
  static const char* const colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                        "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  for (std::size_t k = 0; k < symbols.size(); ++k) {
    s1_plot.series.push_back({symbols[k], {}, {}, colours[k % std::size(colours)], false});
    st_plot.series.push_back({symbols[k], {}, {}, colours[k % std::size(colours)], false});
  }
  for (const auto& [t, o] : times) {
    const auto m =
        std::find_if(o->models.begin(), o->models.end(), [&](const ModelAnalysis& a) { return a.model == model; });
    std::vector<std::string> row1{short_number(t), fmt::format("{} ± {}", short_number(o->mean * label.factor),
                                                               short_number(o->sd * label.factor))};
    std::vector<std::string> row2 = row1;
    for (std::size_t k = 0; k < names.size(); ++k) {
      const bool have = k < m->indices.first.size() && k < m->indices.total.size();
      const sobol::IndexEstimate s1 = have ? m->indices.first[k] : sobol::IndexEstimate{k_nan, k_nan, k_nan};
      const sobol::IndexEstimate st = have ? m->indices.total[k] : sobol::IndexEstimate{k_nan, k_nan, k_nan};
      row1.push_back(index_text(s1));
      row2.push_back(index_text(st));
      s1_plot.series[k].x.push_back(t);
      s1_plot.series[k].y.push_back(s1.value);
      st_plot.series[k].x.push_back(t);
      st_plot.series[k].y.push_back(st.value);
    }
    first.rows.push_back(row1);
    total.rows.push_back(row2);
  }
  section.tables.push_back(first);
  section.tables.push_back(total);
  for (const auto& [plot, suffix] : {std::pair{&s1_plot, "s1"}, std::pair{&st_plot, "st"}}) {
    const PlotFiles files = plot_lines(plotter, *plot, out / fmt::format("time_{}_{}", family, suffix));
    section.figures.push_back({plot->title, files});
    summary.images.push_back(files.png);
  }
  return section;
}

ReportSection calibration_section(const CalibrationOutcome& c, const Plotter& plotter, const fs::path& out,
                                  ReportSummary& summary) {
  ReportSection section;
  section.heading = "Calibration";
  section.paragraphs.push_back(fmt::format(
      "NLopt ({} then {}, {} evaluations) on the metamodel with the best Q² per observable, fitted to {} done "
      "samples; misfit J = Σ w_k ((m_k − t_k)/s_k)² = {:.4g}.",
      c.global_algorithm, c.local_algorithm, c.evaluations, c.samples, c.misfit));
  ReportTable optimum;
  optimum.caption = "Optimum";
  optimum.header = {"parameter", "value", "low", "high", "position in range"};
  CalibrationPlot plot;
  plot.title = "calibration";
  for (size_t i = 0; i < c.parameters.size(); ++i) {
    const ParameterText l = parameter_text(c.parameters[i], c.ties);
    optimum.rows.push_back({l.symbol, fmt::format("{:.6g}", c.physical[i]), fmt::format("{:g}", c.low[i]),
                            fmt::format("{:g}", c.high[i]), fmt::format("{:.3f}", c.unit[i])});
    plot.parameter_labels.push_back(fmt::format("{} [{}]", l.gnuplot, l.unit));
    plot.optimum_unit.push_back(c.unit[i]);
    plot.optimum_physical.push_back(c.physical[i]);
  }
  section.tables.push_back(optimum);
  ReportTable targets;
  targets.caption = "Targets";
  targets.header = {"observable", "metamodel", "Q²", "target", "predicted", "measured (verification)"};
  bool any_measured = false;
  for (const CalibratedTarget& t : c.targets) {
    const Observable l = experiments::describe_observable(t.name);
    targets.rows.push_back({t.name, model_title(t.model), fixed4(t.q2),
                            fmt::format("{:.5g} {}", t.target * l.factor, l.unit),
                            fmt::format("{:.5g} {}", t.predicted * l.factor, l.unit),
                            t.measured ? fmt::format("{:.5g} {}", *t.measured * l.factor, l.unit) : ""});
    plot.observable_labels.push_back(axis_label(t.name));
    plot.target.push_back(t.target * l.factor);
    plot.predicted.push_back(t.predicted * l.factor);
    plot.measured.push_back(t.measured ? *t.measured * l.factor : k_nan);
    any_measured = any_measured || t.measured.has_value();
  }
  if (!any_measured) plot.measured.clear();
  section.tables.push_back(targets);
  if (!c.problems.empty())
    section.paragraphs.push_back(
        check_failed("the targets contradict what the study can produce; this optimum is not an "
                     "answer",
                     c.problems));
  if (!c.verify_dir.empty())
    section.paragraphs.push_back(
        c.verified ? fmt::format("Verified by a real run at the optimum ({:.0f} s).", c.verify_seconds)
                   : fmt::format("The verification run failed: {}", c.verify_error));
  section.figures.push_back(
      {"The calibrated parameters in their ranges, and target against predicted (and "
       "measured) values",
       plot_calibration(plotter, plot, out / "calibration")});
  summary.images.push_back(section.figures.back().files.png);
  return section;
}

/// The Bayesian calibration written by `demsa calibrate --method bayes` into DIR/calibration/.
ReportSection posterior_section(const PosteriorOutcome& p, const fs::path& samples, const Plotter& plotter,
                                const fs::path& out, ReportSummary& summary) {
  ReportSection section;
  section.heading = "Posterior calibration";
  section.paragraphs.push_back(fmt::format(
      "Studies {}; affine-invariant ensemble sampler, {} walkers × {} steps after {} burn-in (seed {}); acceptance "
      "{:.2f}; {}. Width: 90 % posterior width over the prior's width on the design scale (about 0.9: the "
      "measurements do not determine the parameter).",
      join(p.studies), p.walkers, p.steps, p.burn_in, p.seed, p.acceptance,
      p.converged ? "converged (steps ≥ 50 τ, every split R̂ < 1.05)" : k_unconverged + ": " + p.advice));
  ReportTable parameters;
  parameters.caption = "Posterior per parameter";
  parameters.header = {"parameter", "mean", "MAP", "5 %", "50 %", "95 %", "width", "identified", "τ", "R̂", "ESS"};
  for (const PosteriorParameter& q : p.parameters)
    parameters.rows.push_back({fmt::format("{}{}", q.name, q.tied.empty() ? "" : " = " + util::join(q.tied, " = ")),
                               fmt::format("{:.5g}", q.mean), fmt::format("{:.5g}", q.map),
                               fmt::format("{:.5g}", q.q05), fmt::format("{:.5g}", q.q50), fmt::format("{:.5g}", q.q95),
                               fmt::format("{:.3f}", q.width_ratio), q.identified, fmt::format("{:.1f}", q.tau),
                               fmt::format("{:.3f}", q.rhat), fmt::format("{:.0f}", q.ess)});
  section.tables.push_back(parameters);
  ReportTable targets;
  targets.caption = "Targets: measured against the posterior predictive";
  targets.header = {"observable", "study",          "metamodel",       "measured", "sd",
                    "at MAP",     "predictive 5 %", "predictive 95 %", "tail p",   "study's range"};
  for (const PosteriorTarget& t : p.targets)
    targets.rows.push_back({t.name, t.study, t.model, fmt::format("{:.5g}", t.value), fmt::format("{:.3g}", t.sd),
                            fmt::format("{:.5g}", t.predicted_map), fmt::format("{:.5g}", t.predictive_q05),
                            fmt::format("{:.5g}", t.predictive_q95),
                            fmt::format("{:.2g}{}", t.tail_probability, t.contradicted ? " (contradicted)" : ""),
                            t.samples > 0 ? fmt::format("{:.5g} to {:.5g}", t.observed_low, t.observed_high) : ""});
  section.tables.push_back(targets);
  if (!p.problems.empty()) section.paragraphs.push_back(check_failed(posterior_check_headline(p), p.problems));
  for (const std::string& warning : p.warnings) section.paragraphs.push_back("Warning: " + warning + ".");
  for (const VerifyPoint& v : p.verification)
    for (const VerifyPoint::Measured& m : v.measured)
      section.paragraphs.push_back(
          fmt::format("Verification at {}: {} measured {} against predicted {:.5g} (90 % "
                      "[{:.5g}, {:.5g}]).",
                      v.label, m.target, m.value ? fmt::format("{:.5g}", *m.value) : "-", m.predicted, m.low, m.high));
  const PosteriorFigures f = plot_posterior(plotter, p, samples, out);
  section.figures.push_back({"Posterior marginals (red: MAP; dotted: 5 and 95 %; dashed: the prior)", f.marginals});
  section.figures.push_back({"Corner plot of the posterior", f.corner});
  section.figures.push_back({"Posterior predictive against the measured targets", f.predictive});
  for (const ReportFigure& figure : section.figures) summary.images.push_back(figure.files.png);
  return section;
}

/// `demsa plan`: the expected widths per set of experiments, the sd each observable was given, the recommendation.
ReportSection plan_section(const PlanOutcome& p, const Plotter& plotter, const fs::path& out, ReportSummary& summary) {
  ReportSection section;
  section.heading = "Which experiments to run";
  section.paragraphs.push_back(fmt::format(
      "`demsa plan` over {} studies: {} parameter points (truths) drawn from the prior, each measured with the sd "
      "below and calibrated on the metamodels, for every set of the experiments. Width: the 90 % posterior width "
      "over the prior width, the mean over the truths (about 0.9: the set leaves the parameter free). Outside: how "
      "often a truth fell outside its 90 % interval (about 10 % when the planner is calibrated).",
      p.studies.size(), p.truths));
  ReportTable observables;
  observables.caption = "Measured observables";
  observables.header = {"study", "observable", "sd", "from", "metamodel", "Q²"};
  for (const PlanObservable& o : p.observables) {
    const Observable l = experiments::describe_observable(o.name);
    observables.rows.push_back({o.study, o.name,
                                fmt::format("{:.3g}{}", o.sd * l.factor, l.unit.empty() ? "" : " " + l.unit), o.source,
                                o.model, fmt::format("{:.3f}", o.q2)});
  }
  section.tables.push_back(observables);
  ReportTable widths;
  widths.caption = "Expected 90 % posterior width / prior width per set of experiments";
  widths.header = {"experiments"};
  for (const std::string& name : p.parameters) widths.header.push_back(name);
  widths.header.push_back("outside");
  widths.header.push_back("CPU-hours");
  for (size_t i = 0; i < p.subsets.size(); ++i) {
    const PlanSubset& s = p.subsets[i];
    const std::string mark = plan_mark(p, i);
    std::vector<std::string> row{join(s.studies, " + ") + (mark.empty() ? "" : " (" + mark + ")")};
    for (const double w : s.width) row.push_back(fmt::format("{:.2f}", w));
    row.push_back(fmt::format("{:.0f} %", 100 * s.outside_all));
    row.push_back(std::isfinite(s.cpu_seconds) ? fmt::format("{:.3f}", s.cpu_seconds / 3600) : "-");
    widths.rows.push_back(row);
  }
  section.tables.push_back(widths);
  section.paragraphs.push_back(fmt::format("Recommendation: {}.", p.recommendation));
  if (!p.wide_reasons.empty())
    section.paragraphs.push_back(fmt::format("Why they stay wide: {}.", join(p.wide_reasons, "; ")));
  section.figures.push_back(
      {"Expected posterior width per parameter, one bar per set of experiments", plot_plan(plotter, p, out)});
  summary.images.push_back(section.figures.back().files.png);
  return section;
}

/// `demsa refine`'s steps: a table and the half-widths against the samples, with the target as a line.
ReportSection refine_section(const std::vector<RefineStep>& steps, const Plotter& plotter, const fs::path& out,
                             ReportSummary& summary) {
  ReportSection section;
  section.heading = "Refinement";
  RefineHistoryPlot plot;
  plot.target = steps.back().target;
  plot.title = fmt::format("demsa refine: largest Sobol' interval half-width, target {}", short_number(plot.target));
  for (const RefineStep& step : steps)
    for (const auto& [name, w] : step.max_half_width)
      if (std::find(plot.observables.begin(), plot.observables.end(), name) == plot.observables.end())
        plot.observables.push_back(name);
  plot.half_width.assign(plot.observables.size(), {});
  ReportTable table;
  table.caption = "Steps of `demsa refine`: largest S1/ST interval half-width per observable (its best metamodel)";
  table.header = {"step", "samples", "decision"};
  for (const std::string& o : plot.observables) table.header.push_back(o);
  for (const RefineStep& step : steps) {
    plot.samples.push_back(step.samples);
    std::vector<std::string> row{std::to_string(step.iteration), std::to_string(step.samples), step.decision};
    for (std::size_t o = 0; o < plot.observables.size(); ++o) {
      const auto it = step.max_half_width.find(plot.observables[o]);
      const double w = it == step.max_half_width.end() ? k_nan : it->second;
      plot.half_width[o].push_back(w);
      row.push_back(fixed4(w));
    }
    table.rows.push_back(row);
  }
  section.paragraphs.push_back(
      fmt::format("{} refinement step(s), the last with {} done samples ({}); target half-width {}.", steps.size(),
                  steps.back().samples, steps.back().decision, short_number(plot.target)));
  section.tables.push_back(table);
  section.figures.push_back({"Largest S1/ST interval half-width against the done samples (dashed: the target)",
                             plot_refine_history(plotter, plot, out / "refine_history")});
  summary.images.push_back(section.figures.back().files.png);
  return section;
}

}  // namespace

ReportSummary write_study_report(const ReportOptions& options) {
  options.validate();
  const fs::path& dir = options.dir;
  require_study_folder(dir);
  StudyData s;
  s.config = experiments::load_study(dir / k_frozen_study);
  {
    const Store store = Store::open_read_only((dir / k_store_file).string());
    s.samples = store.samples();
    s.observables = store.observables();
    s.runs = store.runs();
    s.counts = store.counts();
    s.refine = store.refine_history();
    s.costs = store.case_costs();
  }
  const fs::path analysis_file = dir / k_analysis_folder / k_analysis_json;
  if (!fs::exists(analysis_file)) {
    AnalyzeOptions analyze;
    analyze.dir = dir;
    analyze_study(analyze);
  }
  AnalysisSummary analysis;
  try {
    analysis = read_analysis(analysis_file);
  } catch (const UserError& e) {
    throw UserError(fmt::format("{}; run `demsa analyze {}` again", e.what(), dir.string()));
  }

  if (!options.lab_file.empty()) {
    const experiments::Experiment& experiment = experiments::of(s.config);
    if (!experiment.compare_with_lab_file || experiments::for_lab_file(options.lab_file) != &experiment)
      throw UserError(fmt::format("ReportOptions.lab_file {}: not a laboratory file of a {} study",
                                  options.lab_file.string(), experiment.name));
  }
  ReportSummary summary;
  summary.sample_shown = choose_sample(s, options.sample);
  summary.out_dir = options.out.empty() ? dir / "report" : options.out;
  fs::create_directories(summary.out_dir);
  const Plotter plotter(options.plot);

  ReportDocument doc;
  doc.title = fmt::format("demsa report: {}", s.config.name);
  doc.sections.push_back(summary_section(s));
  doc.sections.back().paragraphs.push_back(fmt::format(
      "Analysis: {} samples used, {} left out; Sobol' intervals at {:.0f}% from {} bootstrap resamples; QMC base "
      "N = {}.",
      analysis.samples_used.size(), analysis.samples_left_out.size(), analysis.confidence * 100, analysis.bootstrap,
      analysis.base_samples));
  for (const ObservableAnalysis& observable : analysis.observables)
    doc.sections.push_back(observable_section(s, observable, analysis.parameters, plotter, summary.out_dir, summary));

  for (const auto& [family, times] : timed_families(analysis))
    doc.sections.push_back(timed_section(family, times, analysis.parameters, plotter, summary.out_dir, summary));

  if (!s.refine.empty()) doc.sections.push_back(refine_section(s.refine, plotter, summary.out_dir, summary));
  if (std::optional<ReportSection> cost = cost_section(s.costs)) doc.sections.push_back(*cost);

  if (summary.sample_shown >= 0) {
    try {
      doc.sections.push_back(
          case_section(s, summary.sample_shown, plotter, summary.out_dir, dir, options.lab_file, summary));
    } catch (const PhotographError&) {
      throw;
    } catch (const std::exception& e) {
      summary.notes.push_back(fmt::format("sample {}: no case figures: {}", summary.sample_shown, e.what()));
    }
  }

  const fs::path calibration_file = dir / k_analysis_folder / k_calibration_json;
  if (fs::exists(calibration_file))
    doc.sections.push_back(calibration_section(read_calibration(calibration_file), plotter, summary.out_dir, summary));
  else
    doc.sections.back().paragraphs.push_back(
        fmt::format("No calibration yet: `demsa calibrate {}` adds one to this report.", dir.string()));

  const fs::path posterior_file = dir / k_posterior_folder / k_posterior_json;
  if (fs::exists(posterior_file))
    doc.sections.push_back(posterior_section(read_posterior(posterior_file),
                                             dir / "calibration" / "posterior_samples.csv", plotter, summary.out_dir,
                                             summary));

  const fs::path plan_file = dir / "plan" / "plan.json";
  if (fs::exists(plan_file)) {
    try {
      doc.sections.push_back(plan_section(read_plan(plan_file), plotter, summary.out_dir, summary));
    } catch (const std::exception& e) {
      summary.notes.push_back(fmt::format("{}: no plan section: {}", plan_file.string(), e.what()));
    }
  }

  if (!summary.notes.empty()) {
    ReportSection notes;
    notes.heading = "Notes";
    notes.paragraphs = summary.notes;
    doc.sections.push_back(notes);
  }
  summary.markdown = summary.out_dir / "report.md";
  write_file_atomically(summary.markdown, render_markdown(doc, summary.out_dir));
  if (options.html) {
    summary.html = summary.out_dir / "report.html";
    write_file_atomically(summary.html, render_html(doc));
  }
  return summary;
}

nlohmann::json report_summary_json(const ReportSummary& summary) {
  nlohmann::json j{{"dir", summary.out_dir.string()},
                   {"markdown", summary.markdown.string()},
                   {"html", summary.html.string()},
                   {"sample_shown", summary.sample_shown},
                   {"notes", summary.notes}};
  nlohmann::json images = nlohmann::json::array();
  for (const auto& p : summary.images) images.push_back(p.string());
  j["images"] = images;
  return j;
}

std::string report_summary_text(const ReportSummary& summary) {
  std::string text = fmt::format("report: {}\n", summary.markdown.string());
  if (!summary.html.empty()) text += fmt::format("report: {}\n", summary.html.string());
  text += fmt::format("{} plots (PNG and SVG, each with its gnuplot script) in {}\n", summary.images.size(),
                      summary.out_dir.string());
  for (const std::string& note : summary.notes) text += fmt::format("note: {}\n", note);
  return text;
}

}  // namespace demsa::report
