#include "orchestrator/analysis/prediction.hpp"

#include "orchestrator/analysis/analysis_json.hpp"
#include "orchestrator/analysis/model_file.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "sobol/gp.hpp"

#include <fmt/core.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace demsa::analysis {

using namespace demsa::util;

namespace {

namespace fs = std::filesystem;

std::string joined(const std::set<std::string>& names) {
  std::string text;
  for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

/// The model file of a study folder that the options name (or the best by Q²).
fs::path study_model_file(const PredictOptions& args) {
  const fs::path dir(args.source);
  const fs::path models_dir = dir / study::k_analysis_folder / study::k_models_folder;
  if (!fs::is_directory(models_dir))
    throw UserError(args.source, 0,
                    fmt::format("no saved metamodels ({} does not exist): run `demsa analyze {}` first",
                                models_dir.string(), args.source));
  // <observable>.<metamodel>.json: the metamodel names hold no '.'.
  std::map<std::string, std::set<std::string>> files;  // observable -> metamodels
  for (const fs::directory_entry& entry : fs::directory_iterator(models_dir)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".json") continue;
    const std::string stem = entry.path().stem().string();
    const std::size_t dot = stem.rfind('.');
    if (dot == std::string::npos || dot == 0) continue;
    files[stem.substr(0, dot)].insert(stem.substr(dot + 1));
  }
  if (files.empty())
    throw UserError(models_dir.string(), 0,
                    fmt::format("no metamodel file: run `demsa analyze {}` (it writes one per observable and "
                                "metamodel)",
                                args.source));
  std::set<std::string> observables;
  for (const auto& [o, models] : files) observables.insert(o);
  std::string observable = args.observable;
  if (observable.empty()) {
    if (files.size() > 1)
      throw UserError(
          fmt::format("{}: the study has {} observables with metamodels ({}): choose one with "
                      "PredictOptions.observable",
                      args.source, files.size(), joined(observables)));
    observable = files.begin()->first;
  } else if (!files.count(observable)) {
    throw UserError(fmt::format("PredictOptions.observable {}: no metamodel of it in {} (observables: {})", observable,
                                models_dir.string(), joined(observables)));
  }
  const std::set<std::string>& models = files.at(observable);
  if (!args.model.empty()) {
    if (!models.count(args.model))
      throw UserError(fmt::format("PredictOptions.model {}: no such metamodel of '{}' in {} (metamodels: {})",
                                  args.model, observable, models_dir.string(), joined(models)));
    return models_dir / model_file_name(observable, args.model);
  }
  // The analysis' choice: the largest leave-one-out Q² (analysis/fit.hpp best_by_q2), in the analysis' order.
  const fs::path analysis_file = dir / study::k_analysis_folder / study::k_analysis_json;
  const AnalysisSummary summary = read_analysis(analysis_file);
  const auto rank = [](double q2) { return std::isfinite(q2) ? q2 : -std::numeric_limits<double>::infinity(); };
  std::string best;
  double best_q2 = 0.0;
  for (const ObservableAnalysis& o : summary.observables) {
    if (o.name != observable) continue;
    for (const ModelAnalysis& m : o.models) {
      if (!m.ok || !models.count(m.model)) continue;
      if (best.empty() || rank(m.quality.q2) > rank(best_q2)) {
        best = m.model;
        best_q2 = m.quality.q2;
      }
    }
  }
  if (best.empty())
    throw UserError(analysis_file.string(), 0,
                    fmt::format("no fitted metamodel of '{}' matches the files in {} ({}): run `demsa analyze {}` "
                                "again, or name one with PredictOptions.model",
                                observable, models_dir.string(), joined(models), args.source));
  log::info("{}: observable '{}': metamodel {} (largest leave-one-out Q2, {:.4f})", args.source, observable, best,
            best_q2);
  return models_dir / model_file_name(observable, best);
}

}  // namespace

Prediction predict(const PredictOptions& args) {
  const bool folder = fs::is_directory(args.source);
  const fs::path file = folder ? study_model_file(args) : fs::path(args.source);
  if (!folder && !fs::exists(file)) throw UserError(args.source, 0, "no such study folder or model file");
  const SavedModel saved = read_model_file(file);
  const std::string kind = saved.model->name();
  if (!folder && !args.model.empty() && args.model != kind)
    throw UserError(fmt::format("PredictOptions.model {}: {} holds a {} metamodel", args.model, file.string(), kind));
  if (!folder && !args.observable.empty() && args.observable != saved.output)
    throw UserError(
        fmt::format("PredictOptions.observable {}: {} models '{}'", args.observable, file.string(), saved.output));
  const auto* gp = dynamic_cast<const sobol::GaussianProcess*>(saved.model.get());
  if (args.standard_deviation && gp == nullptr)
    throw UserError(
        fmt::format("PredictOptions.standard_deviation: the {} metamodel of {} has no predictive standard deviation "
                    "(only gp has one); drop PredictOptions.standard_deviation or choose PredictOptions.model gp",
                    kind, file.string()));

  CsvReadOptions read_options;
  read_options.numeric_columns = saved.inputs;
  const CsvTable points = read_csv(args.points, read_options);
  std::vector<int> columns;
  for (const std::string& name : saved.inputs) columns.push_back(points.column_index(name));
  const Eigen::Index n = points.values.rows();
  const Eigen::Index d = static_cast<Eigen::Index>(saved.inputs.size());
  Eigen::MatrixXd physical(n, d);
  Eigen::MatrixXd unit(n, d);
  long outside = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    bool out_of_bounds = false;
    for (Eigen::Index k = 0; k < d; ++k) {
      const int c = columns[static_cast<std::size_t>(k)];
      const sobol::Bounds& b = saved.bounds[static_cast<std::size_t>(k)];
      const double v = points.values(i, c);
      if (b.scale == sobol::Scale::log_uniform && !(v > 0.0))
        points.fail(static_cast<int>(i), c,
                    fmt::format("{}: the input '{}' has a log scale, so its values must be > 0", v,
                                saved.inputs[static_cast<std::size_t>(k)]));
      out_of_bounds = out_of_bounds || v < b.low || v > b.high;
      physical(i, k) = v;
      unit(i, k) = sobol::to_unit(v, b);
    }
    outside += out_of_bounds ? 1 : 0;
  }
  if (outside > 0)
    log::warn("{}: {} of {} points lie outside the bounds of the model's inputs: their predictions extrapolate",
              args.points, outside, n);
  Prediction prediction;
  prediction.model_file = file;
  prediction.metamodel = kind;
  prediction.inputs = saved.inputs;
  prediction.output = saved.output;
  prediction.physical = physical;
  prediction.outside = outside;
  // A GP's sum k(x)ᵀα cancels: accumulated in long double (sobol/gp.hpp, predict_precise).
  prediction.mean = gp ? gp->predict_precise(unit) : saved.model->predict(unit);
  if (args.standard_deviation) prediction.sd = gp->predict_sd(unit);
  return prediction;
}

std::string prediction_written_text(const Prediction& p, const std::string& file) {
  return fmt::format("{} predictions of '{}' by {} ({}) written to {}\n", p.physical.rows(), p.output, p.metamodel,
                     p.model_file.string(), file);
}

std::string prediction_csv(const Prediction& p) {
  const Eigen::Index d = p.physical.cols();
  const bool with_sd = p.sd.size() > 0;
  Eigen::MatrixXd table(p.physical.rows(), d + 1 + (with_sd ? 1 : 0));
  table.leftCols(d) = p.physical;
  table.col(d) = p.mean;
  std::vector<std::string> header = p.inputs;
  header.push_back(p.output);
  if (with_sd) {
    table.col(d + 1) = p.sd;
    header.push_back(p.output + "_sd");
  }
  return format_csv(header, table);
}

}  // namespace demsa::analysis
