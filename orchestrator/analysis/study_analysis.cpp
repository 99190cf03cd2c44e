#include "orchestrator/analysis/study_analysis.hpp"

#include "orchestrator/analysis/fit.hpp"
#include "orchestrator/analysis/model_file.hpp"
#include "orchestrator/analysis/sobol_json.hpp"
#include "orchestrator/analysis/training_data.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/observables.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "orchestrator/util/text.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/noise.hpp"
#include "sobol/stop.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <stdexcept>

namespace demsa::analysis {

using namespace demsa::util;
using namespace demsa::study;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string csv_number(double value) { return fmt::format("{:.10g}", value); }

void write_text(const fs::path& path, const std::string& text) { write_file_atomically(path, text); }

double mean_of(const Eigen::VectorXd& y) { return y.size() ? y.mean() : 0.0; }

double sd_of(const Eigen::VectorXd& y) {
  if (y.size() < 2) return 0.0;
  const double m = y.mean();
  return std::sqrt((y.array() - m).square().sum() / static_cast<double>(y.size() - 1));
}

}  // namespace

std::string unmeasurable_text(const sobol::MetamodelSummary& quality) {
  const std::string why = unmeasurable_error(quality);
  if (why.empty()) return "";
  // rsm1 has the fewest terms of all: naming a smaller model would not help (as best_measurable's advice).
  return fmt::format(
      "Q² not computable: {}; no Sobol' index from a fit that cannot be judged: run more cases of the "
      "study{}",
      why, quality.name == "rsm1" ? "" : ", or use a metamodel with fewer terms");
}

std::optional<NoiseAnalysis> measured_noise(const std::vector<ReplicateRow>& replicates,
                                            const std::map<int, std::map<std::string, double>>& observables,
                                            const std::string& name, double confidence, double design_sd) {
  if (replicates.empty()) return std::nullopt;
  const auto value = [&](int sample) -> std::optional<double> {
    const auto it = observables.find(sample);
    if (it == observables.end()) return std::nullopt;
    const auto v = it->second.find(name);
    if (v == it->second.end() || !std::isfinite(v->second)) return std::nullopt;
    return v->second;
  };
  // One group per point: its design case (repeat 0) and its replicates, those that measured the observable.
  std::map<int, std::vector<double>> groups;
  for (const ReplicateRow& r : replicates) {
    if (!groups.count(r.point))
      if (const auto v = value(r.point)) groups[r.point].push_back(*v);
    if (const auto v = value(r.sample)) groups[r.point].push_back(*v);
  }
  std::vector<std::vector<double>> values;
  for (auto& [point, group] : groups) values.push_back(std::move(group));
  NoiseAnalysis noise;
  try {
    noise.estimate = sobol::pooled_noise_variance(values, confidence);
  } catch (const sobol::InputError&) {
    return std::nullopt;  // no point has two done cases yet
  }
  const double total = design_sd * design_sd;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  noise.share = total > 0.0 ? noise.estimate.variance / total : nan;
  noise.share_lower = total > 0.0 ? noise.estimate.lower / total : nan;
  noise.share_upper = total > 0.0 ? noise.estimate.upper / total : nan;
  noise.largest_s1 = nan;
  return noise;
}

sobol::MetamodelOptions with_measured_noise(sobol::MetamodelOptions options, const std::optional<NoiseAnalysis>& noise,
                                            const Eigen::VectorXd& y) {
  if (!noise || y.size() < 2) return options;
  // The noise variance in the GP's scaled units: divided by the training outputs' variance (population, as the GP
  // scales them).
  const double variance = (y.array() - y.mean()).square().mean();
  if (!(variance > 0.0)) return options;
  options.gp.nugget = true;
  options.gp.noise_share = noise->estimate.variance / variance;
  return options;
}

void AnalyzeOptions::validate() const {
  if (dir.empty()) throw std::invalid_argument("dir is empty: a study folder is required");
  if (bootstrap < -1) throw std::invalid_argument(fmt::format("bootstrap = {}: must be >= 0 (or -1)", bootstrap));
  if (base_samples != -1 && base_samples < 2)
    throw std::invalid_argument(fmt::format("base_samples = {}: must be >= 2 (or -1)", base_samples));
  if (second_order < -1 || second_order > 1)
    throw std::invalid_argument(fmt::format("second_order = {}: must be -1, 0 or 1", second_order));
}

AnalysisSummary analyze_study(const AnalyzeOptions& options) {
  options.validate();
  const fs::path& dir = options.dir;
  require_study_folder(dir);
  const fs::path study_file = dir / k_frozen_study;
  const fs::path db = dir / k_store_file;
  const StudyConfig config = experiments::load_study(study_file);
  const Store store = Store::open_read_only(db.string());
  const std::vector<SampleRow> samples = store.samples();
  const std::map<int, std::map<std::string, double>> observables = store.observables();
  const std::vector<ReplicateRow> replicates = store.replicates();

  AnalysisSummary summary;
  summary.out_dir = dir / "analysis";
  summary.study = config.name;
  for (const ParameterRange& p : config.parameters) summary.parameters.push_back(p.name);
  summary.seed = config.seed;
  summary.bootstrap = options.bootstrap >= 0 ? options.bootstrap : config.analysis.bootstrap;
  summary.base_samples = options.base_samples >= 0 ? options.base_samples : config.analysis.base_samples;
  summary.second_order = options.second_order >= 0 ? options.second_order == 1 : config.analysis.second_order;
  summary.confidence = config.analysis.confidence;
  const std::vector<std::string> models = options.metamodels.empty() ? config.analysis.metamodels : options.metamodels;
  const std::vector<sobol::MetamodelKind> kinds = metamodel_kinds(models);  // unknown names: error up front

  for (const SampleRow& s : samples) {
    if (observables.count(s.sample))
      summary.samples_used.push_back(s.sample);
    else
      summary.samples_left_out.push_back(s.sample);
  }
  summary.samples_unsettled = unsettled_samples(observables);
  summary.unsettled = experiments::unsettled_text(observables);
  if (summary.samples_used.size() < 2)
    throw UserError(fmt::format("{}: {} of {} samples done; the analysis needs at least 2", dir.string(),
                                summary.samples_used.size(), samples.size()));

  const std::size_t d = summary.parameters.size();
  std::vector<std::string> names = experiments::observable_names(config);

  sobol::MetamodelSobolOptions sobol_options;
  sobol_options.base = summary.base_samples;
  sobol_options.second_order = summary.second_order;
  sobol_options.bootstrap = summary.bootstrap;
  sobol_options.interval = config.analysis.interval;
  sobol_options.confidence = config.analysis.confidence;
  sobol_options.seed = config.seed;
  sobol_options.stop = options.should_stop;

  const sobol::MetamodelOptions model_options = config.analysis.metamodel_options();
  // Every fitted metamodel as a file (model_file.hpp), written with the rest once everything is computed.
  SavedModel saved;
  for (const ParameterRange& p : config.parameters) {
    saved.inputs.push_back(p.name);
    saved.bounds.push_back(p.bounds);
  }
  std::vector<std::pair<std::string, std::string>> model_files;  // file name, JSON text
  for (const std::string& name : names) {
    const TrainingData data = training_data(config, samples, observables, name);
    ObservableAnalysis analysis;
    analysis.name = name;
    analysis.samples = static_cast<int>(data.size());
    analysis.mean = mean_of(data.y);
    analysis.sd = sd_of(data.y);
    analysis.noise = measured_noise(replicates, observables, name, summary.confidence, analysis.sd);
    // A measured noise sets the GP's nugget (sobol::GpOptions::noise_share).
    const sobol::MetamodelOptions observable_options = with_measured_noise(model_options, analysis.noise, data.y);
    if (analysis.noise) analysis.noise->nugget_share = observable_options.gp.noise_share;
    if (data.size() >= 2 && sobol::negligible_variance(analysis.mean, analysis.sd * analysis.sd)) {
      // A metamodel of a constant would fit it exactly and give indices of round-off (R² NaN, S1 of noise).
      analysis.error = fmt::format(
          "constant observable: every one of its {} samples is {:.10g} (standard deviation {:.3g}): no metamodel "
          "and no Sobol' index can be computed; check its measurement",
          data.size(), analysis.mean, analysis.sd);
      log::warn("{}: observable '{}': {}", dir.string(), name, analysis.error);
      summary.observables.push_back(std::move(analysis));
      continue;
    }
    for (const sobol::MetamodelKind kind : kinds) {
      sobol::throw_if_stopped(options.should_stop);
      FittedMetamodel fit = fit_metamodel(kind, observable_options, data.unit, data.y);
      // A model that cannot be fitted to this data (too few samples for an RSM of degree 3, a singular system) is
      // reported, not fatal: the others still give indices.
      ModelAnalysis model;
      model.model = fit.name();
      model.error = fit.error;
      if (fit.ok()) {
        saved.output = name;
        saved.model = std::move(fit.model);
        model_files.emplace_back(model_file_name(name, model.model), model_to_json(saved));
        fit.model = std::move(saved.model);
        model.fitted = true;
        model.quality = fit.quality;
        if (std::string unmeasurable = unmeasurable_text(fit.quality); !unmeasurable.empty()) {
          // A model whose prediction error cannot be measured cannot be judged against the others: its indices would
          // rank the parameters on a fit that may be anything between the samples. It gets none, and so is never
          // the best metamodel of the report, the refinement or `demsa predict`.
          model.error = std::move(unmeasurable);
          log::warn("{}: observable '{}', metamodel {}: {}", dir.string(), name, model.model, model.error);
        } else {
          try {
            model.indices = sobol::metamodel_sobol(*fit.model, sobol_options);
            model.ok = true;
          } catch (const sobol::Stopped&) {
            throw;
          } catch (const std::exception& e) {
            model.error = e.what();
          }
        }
      }
      analysis.models.push_back(std::move(model));
    }
    if (analysis.noise) {
      // The largest S1 of the metamodel of best Q² (the model the report ranks first), beside which the noise share
      // is judged.
      double best_q2 = -std::numeric_limits<double>::infinity();
      analysis.noise->largest_s1 = std::numeric_limits<double>::quiet_NaN();
      for (const ModelAnalysis& m : analysis.models) {
        if (!m.ok || m.indices.first.empty()) continue;
        const double q2 = std::isfinite(m.quality.q2) ? m.quality.q2 : -1e300;
        if (q2 <= best_q2) continue;
        best_q2 = q2;
        double largest = 0.0;
        for (const sobol::IndexEstimate& e : m.indices.first) largest = std::max(largest, e.value);
        analysis.noise->largest_s1 = largest;
      }
      analysis.noise->dominates = noise_dominates(analysis.noise->share, analysis.noise->largest_s1);
      if (analysis.noise->dominates)
        log::warn(
            "{}: observable '{}': DEM noise is {:.0f} % of its variance over the design (largest S1 {:.2f}): "
            "the noise dominates; more samples or a larger assembly reduce it",
            dir.string(), name, 100.0 * analysis.noise->share, analysis.noise->largest_s1);
    }
    summary.observables.push_back(std::move(analysis));
  }

  // Every result is computed before the first file is written: a stopped analysis leaves the folder as it was.
  sobol::throw_if_stopped(options.should_stop);
  fs::create_directories(summary.out_dir);

  // observables.csv
  std::set<std::string> extra;
  for (const auto& [sample, values] : observables)
    for (const auto& [name, value] : values)
      if (std::find(names.begin(), names.end(), name) == names.end()) extra.insert(name);
  std::vector<std::string> columns = names;
  columns.insert(columns.end(), extra.begin(), extra.end());
  {
    std::string text = "sample";
    for (const std::string& p : summary.parameters) text += ",u_" + p;
    for (const std::string& p : summary.parameters) text += "," + p;
    for (const std::string& c : columns) text += "," + c;
    text += "\n";
    for (const SampleRow& s : samples) {
      const auto it = observables.find(s.sample);
      if (it == observables.end()) continue;
      text += std::to_string(s.sample);
      for (double u : s.unit) text += "," + csv_number(u);
      for (double x : s.physical) text += "," + csv_number(x);
      for (const std::string& c : columns) {
        const auto v = it->second.find(c);
        text += "," + (v == it->second.end() ? std::string{} : csv_number(v->second));
      }
      text += "\n";
    }
    write_text(summary.out_dir / k_observables_csv, text);
  }
  // replicates.csv: the replicate cases beside the design case of their point (repeat 0).
  if (!replicates.empty()) {
    std::string text = "point,repeat,sample,assembly_seed";
    for (const std::string& c : columns) text += "," + c;
    text += "\n";
    const auto row = [&](int point, int repeat, int sample, const std::string& seed) {
      const auto it = observables.find(sample);
      if (it == observables.end()) return;
      text += fmt::format("{},{},{},{}", point, repeat, sample, seed);
      for (const std::string& c : columns) {
        const auto v = it->second.find(c);
        text += ',';
        if (v != it->second.end()) text += csv_number(v->second);
      }
      text += "\n";
    };
    int previous = -1;
    for (const ReplicateRow& r : replicates) {
      if (r.point != previous) row(r.point, 0, r.point, std::to_string(config.seed));
      previous = r.point;
      row(r.point, r.repeat, r.sample, std::to_string(r.seed));
    }
    write_text(summary.out_dir / k_replicates_csv, text);
  } else {
    std::error_code ec;
    fs::remove(summary.out_dir / k_replicates_csv, ec);
  }

  // metamodels.json, table_<observable>.csv, analysis.json, sobol_<model>.{csv,json}. A table of an observable no
  // longer measured (a study measured again with fewer stations) goes.
  for (const fs::directory_entry& entry : fs::directory_iterator(summary.out_dir)) {
    const std::string file = entry.path().filename().string();
    const bool current = std::any_of(summary.observables.begin(), summary.observables.end(),
                                     [&](const ObservableAnalysis& o) { return file == "table_" + o.name + ".csv"; });
    if (!current && entry.is_regular_file() && file.rfind("table_", 0) == 0 && entry.path().extension() == ".csv")
      fs::remove(entry.path());
  }
  json metamodels_json = json::object();
  for (const ObservableAnalysis& o : summary.observables) {
    json per_model = json::object();
    for (const ModelAnalysis& m : o.models) {
      // A fitted model without indices keeps its quality beside the reason (its Q² is null).
      json entry = m.fitted ? metamodel_summary_json(m.quality) : json::object();
      if (!m.ok) entry["error"] = m.error;
      per_model[m.model] = entry;
    }
    metamodels_json[o.name] = per_model;

    std::string table = "model";
    for (const std::string& p : summary.parameters) table += ",S1_" + p;
    table += ",residual,r2,q2\n";
    for (const ModelAnalysis& m : o.models) {
      if (!m.ok) continue;
      table += m.model;
      for (const sobol::IndexEstimate& e : m.indices.first) table += "," + csv_number(e.value);
      table += "," + csv_number(m.indices.residual.value) + "," + csv_number(m.quality.r2) + "," +
               csv_number(m.quality.q2) + "\n";
    }
    write_text(summary.out_dir / fmt::format("table_{}.csv", o.name), table);
  }
  write_text(summary.out_dir / k_metamodels_json, metamodels_json.dump(2) + "\n");
  // models/ holds the models of this analysis only: a file of a metamodel or observable no longer analysed goes.
  const fs::path models_dir = summary.out_dir / k_models_folder;
  fs::create_directories(models_dir);
  for (const fs::directory_entry& entry : fs::directory_iterator(models_dir)) {
    const std::string file = entry.path().filename().string();
    const bool current = std::any_of(model_files.begin(), model_files.end(),
                                     [&](const std::pair<std::string, std::string>& m) { return m.first == file; });
    if (!current && entry.is_regular_file() && entry.path().extension() == ".json") fs::remove(entry.path());
  }
  for (const auto& [file, text] : model_files) write_text(models_dir / file, text);
  write_text(summary.out_dir / k_analysis_json, analysis_to_json(summary));

  for (const std::string& model_name : models) {
    std::string csv = "observable,parameter,S1,S1_lower,S1_upper,ST,ST_lower,ST_upper\n";
    json per_obs = json::object();
    for (const ObservableAnalysis& o : summary.observables)
      for (const ModelAnalysis& m : o.models) {
        if (m.model != model_name || !m.ok) continue;
        per_obs[o.name] = sobol_result_json(m.indices, summary.parameters);
        for (std::size_t i = 0; i < d; ++i) {
          const sobol::IndexEstimate& s1 = m.indices.first.at(i);
          const sobol::IndexEstimate& st = m.indices.total.at(i);
          csv += fmt::format("{},{},{},{},{},{},{},{}\n", o.name, summary.parameters[i], csv_number(s1.value),
                             csv_number(s1.lower), csv_number(s1.upper), csv_number(st.value), csv_number(st.lower),
                             csv_number(st.upper));
        }
        csv += fmt::format("{},residual,{},{},{},,,\n", o.name, csv_number(m.indices.residual.value),
                           csv_number(m.indices.residual.lower), csv_number(m.indices.residual.upper));
      }
    write_text(summary.out_dir / fmt::format("sobol_{}.csv", model_name), csv);
    write_text(summary.out_dir / fmt::format("sobol_{}.json", model_name), per_obs.dump(2) + "\n");
  }
  return summary;
}

int balanced_base_samples(int base, const std::string& field, const std::function<void(const std::string&)>& warn) {
  if (base <= 0 || std::has_single_bit(static_cast<unsigned>(base))) return base;
  const int balanced = static_cast<int>(std::bit_ceil(static_cast<unsigned>(base)));
  if (warn)
    warn(fmt::format(
        "{} {} is not a power of two: rounded up to {} (a scrambled Sobol' sequence is balanced only at powers of "
        "two; Saltelli 2010 takes N = 2^k)",
        field, base, balanced));
  return balanced;
}

std::string analysis_failure(const AnalysisSummary& summary) {
  std::string why;
  for (const ObservableAnalysis& o : summary.observables) {
    for (const ModelAnalysis& m : o.models)
      if (m.ok) return "";
    if (!o.error.empty()) {
      why += fmt::format("\n  {}: {}", o.name, o.error);
      continue;
    }
    for (const ModelAnalysis& m : o.models) why += fmt::format("\n  {} ~ {}: {}", o.name, m.model, m.error);
  }
  return fmt::format("{}: no observable could be analysed:{}", summary.out_dir.string(),
                     why.empty() ? std::string(" the study has none") : why);
}

std::string noise_text(const NoiseAnalysis& noise) {
  const sobol::NoiseEstimate& e = noise.estimate;
  std::string text = fmt::format(
      "noise     {:>8.3f} share of the variance over the design ({:.0f} % interval {:.3f} to {:.3f}); noise variance "
      "{:.4g} ({:.4g} to {:.4g}) from {} points, {} cases, {} degrees of freedom",
      noise.share, 100.0 * e.confidence, noise.share_lower, noise.share_upper, e.variance, e.lower, e.upper, e.points,
      e.values, e.dof);
  if (noise.dominates)
    text +=
        fmt::format("\n          NOISE DOMINATES: share {:.3f} > {}", noise.share,
                    noise.share > 0.5 ? std::string("0.5") : fmt::format("the largest S1 {:.3f}", noise.largest_s1));
  return text;
}

std::string s1_table_text(const AnalysisSummary& summary, const ObservableAnalysis& observable) {
  std::string text = fmt::format("Sobol' S1 of {} ({} samples", observable.name, observable.samples);
  if (!summary.samples_left_out.empty()) text += fmt::format(", {} left out", summary.samples_left_out.size());
  text += ")\n";
  if (!observable.error.empty()) return text + fmt::format("not analysed: {}\n", observable.error);
  text += fmt::format("{:<10}", "model");
  for (const std::string& p : summary.parameters) text += fmt::format(" {:>8}", p);
  text += fmt::format(" {:>8} {:>7} {:>7}\n", "Res", "R2", "Q2");
  for (const ModelAnalysis& m : observable.models) {
    text += fmt::format("{:<10}", m.model);
    if (!m.ok) {
      // A fitted model without indices (Q² not computable) shows its R² beside the reason; its row has no index.
      text +=
          m.fitted ? fmt::format(" R2 {:.3f}; {}\n", m.quality.r2, m.error) : fmt::format(" not fitted: {}\n", m.error);
      continue;
    }
    for (const sobol::IndexEstimate& e : m.indices.first) text += fmt::format(" {:>8.3f}", e.value);
    text += fmt::format(" {:>8.3f} {:>7.3f} {:>7.3f}\n", m.indices.residual.value, m.quality.r2, m.quality.q2);
  }
  for (const ModelAnalysis& m : observable.models)
    if (m.ok && !m.indices.note.empty()) text += fmt::format("{}: {}\n", m.model, m.indices.note);
  if (observable.noise) text += noise_text(*observable.noise) + "\n";
  return text;
}

std::string analysis_tables_text(const AnalysisSummary& summary) {
  std::string text;
  for (const ObservableAnalysis& o : summary.observables) text += fmt::format("\n{}", s1_table_text(summary, o));
  if (!summary.samples_left_out.empty())
    text += fmt::format("\nleft out of the analysis (not done): samples {}\n", util::join(summary.samples_left_out));
  if (!summary.samples_unsettled.empty())
    text += fmt::format("\nunsettled, still moving at the end of settling (analysed all the same): sample {}\n",
                        summary.unsettled);
  text += fmt::format("\ntables, metamodels and indices with confidence intervals: {}\n", summary.out_dir.string());
  return text;
}

}  // namespace demsa::analysis
