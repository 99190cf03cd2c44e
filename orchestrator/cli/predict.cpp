// `demsa predict DIR|MODEL.json --points CSV`: a saved metamodel (analysis/model_file.hpp) evaluated at new points
// given in physical units.
//
// The points file is a CSV table with a header (util/csv.hpp); the model's input columns are found by name, in any
// order; other columns are not read and not copied. The output is a CSV table: the model's inputs (as read), then
// the prediction in a column named after the model's output, then with --std its predictive standard deviation
// (`<output>_sd`, Gaussian process only). A missing input column is an error naming the file and the column; points
// outside the model's bounds are predicted (extrapolation), with a warning that counts them.
//
// For a study folder DIR the model is DIR/analysis/models/<observable>.<metamodel>.json: --observable picks the
// observable (required when the study has several), --model the metamodel (default: the largest leave-one-out Q²
// of DIR/analysis/analysis.json, as the analysis and the calibration choose).
#include "orchestrator/analysis/analysis_json.hpp"
#include "orchestrator/analysis/model_file.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "orchestrator/util/text.hpp"
#include "sobol/gp.hpp"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::analysis;

namespace {

namespace fs = std::filesystem;

struct PredictArgs {
  std::string source;      ///< study folder or model file
  std::string points;      ///< CSV of points in physical units
  std::string model;       ///< metamodel name (study folder: which one; file: checked)
  std::string observable;  ///< study folder: which observable (file: checked)
  bool standard_deviation = false;
  std::string out;  ///< CSV file ("" or "-": standard output)
};

std::string joined(const std::set<std::string>& names) {
  std::string text;
  for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

/// The model file of a study folder that the options name (or the best by Q²).
fs::path study_model_file(const PredictArgs& args) {
  const fs::path dir(args.source);
  const fs::path models_dir = dir / "analysis" / "models";
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
                      "--observable",
                      args.source, files.size(), joined(observables)));
    observable = files.begin()->first;
  } else if (!files.count(observable)) {
    throw UserError(fmt::format("--observable {}: no metamodel of it in {} (observables: {})", observable,
                                models_dir.string(), joined(observables)));
  }
  const std::set<std::string>& models = files.at(observable);
  if (!args.model.empty()) {
    if (!models.count(args.model))
      throw UserError(fmt::format("--model {}: no such metamodel of '{}' in {} (metamodels: {})", args.model,
                                  observable, models_dir.string(), joined(models)));
    return models_dir / model_file_name(observable, args.model);
  }
  // The analysis' choice: the largest leave-one-out Q² (analysis/fit.hpp best_by_q2), in the analysis' order.
  const fs::path analysis_file = dir / "analysis" / "analysis.json";
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
                                "again, or name one with --model",
                                observable, models_dir.string(), joined(models), args.source));
  log::info("{}: observable '{}': metamodel {} (largest leave-one-out Q2, {:.4f})", args.source, observable, best,
            best_q2);
  return models_dir / model_file_name(observable, best);
}

void run_predict(const PredictArgs& args) {
  const bool folder = fs::is_directory(args.source);
  const fs::path file = folder ? study_model_file(args) : fs::path(args.source);
  if (!folder && !fs::exists(file)) throw UserError(args.source, 0, "no such study folder or model file");
  const SavedModel saved = read_model_file(file);
  const std::string kind = saved.model->name();
  if (!folder && !args.model.empty() && args.model != kind)
    throw UserError(fmt::format("--model {}: {} holds a {} metamodel", args.model, file.string(), kind));
  if (!folder && !args.observable.empty() && args.observable != saved.output)
    throw UserError(fmt::format("--observable {}: {} models '{}'", args.observable, file.string(), saved.output));
  const auto* gp = dynamic_cast<const sobol::GaussianProcess*>(saved.model.get());
  if (args.standard_deviation && gp == nullptr)
    throw UserError(
        fmt::format("--std: the {} metamodel of {} has no predictive standard deviation (only gp has "
                    "one); drop --std or choose --model gp",
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

  Eigen::MatrixXd table(n, d + 1 + (args.standard_deviation ? 1 : 0));
  table.leftCols(d) = physical;
  // A GP's sum k(x)ᵀα cancels: accumulated in long double (sobol/gp.hpp, predict_precise).
  table.col(d) = gp ? gp->predict_precise(unit) : saved.model->predict(unit);
  std::vector<std::string> header = saved.inputs;
  header.push_back(saved.output);
  if (args.standard_deviation) {
    table.col(d + 1) = gp->predict_sd(unit);
    header.push_back(saved.output + "_sd");
  }
  if (args.out.empty() || args.out == "-") {
    fmt::print("{}", format_csv(header, table));
  } else {
    write_csv(args.out, header, table);
    fmt::print("{} predictions of '{}' by {} ({}) written to {}\n", n, saved.output, kind, file.string(), args.out);
  }
}

}  // namespace

void register_predict_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<PredictArgs>();
  CLI::App* sub = app.add_subcommand("predict", "Predict with a saved metamodel at new points in physical units");
  sub->add_option("source", args->source, "Study folder (its analysis/models/) or a metamodel file (.json)")
      ->required();
  sub->add_option("--points", args->points,
                  "CSV of points: a header naming the model's inputs (other columns are "
                  "ignored), one row per point, physical units")
      ->required();
  sub->add_option("--model", args->model,
                  "Metamodel of a study folder (default: the largest leave-one-out Q2); with a file: checked");
  sub->add_option("--observable", args->observable,
                  "Observable of a study folder (required when it has several); with a file: checked");
  sub->add_flag("--std", args->standard_deviation, "Add the predictive standard deviation (<output>_sd; gp only)");
  sub->add_option("-o,--out", args->out, "CSV file to write (default: standard output)");
  sub->callback([args, &state] {
    run_predict(*args);
    state.exit_code = k_exit_ok;
  });
}

}  // namespace demsa::cli
