#include "orchestrator/analysis/sensitivity.hpp"

#include "orchestrator/analysis/fit.hpp"
#include "orchestrator/analysis/model_file.hpp"
#include "orchestrator/analysis/saltelli_design_file.hpp"
#include "orchestrator/analysis/sobol_json.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "orchestrator/util/text.hpp"
#include "sobol/error.hpp"
#include "sobol/noise.hpp"
#include "sobol/stop.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <utility>

namespace demsa::analysis {

using util::CsvTable;
using util::UserError;

void emit_warning(const WarningSink& sink, const std::string& message) {
  if (sink)
    sink(message);
  else
    util::log::warn("{}", message);
}

namespace {

/// No NaN index leaves demsa as a result: a computation that gave one is refused (sobol::NumericalError) with what
/// the indices were computed from.
void require_finite_indices(const sobol::SobolResult& r, const std::vector<std::string>& names) {
  const auto check = [&r](const sobol::IndexEstimate& e, const std::string& what) {
    if (std::isnan(e.value) || std::isnan(e.lower) || std::isnan(e.upper))
      throw sobol::NumericalError(
          fmt::format("{} is not a number (output mean {:.4g}, variance {:.4g}): the "
                      "indices cannot be computed from these outputs",
                      what, r.mean, r.variance));
  };
  for (std::size_t k = 0; k < r.first.size(); ++k) check(r.first[k], "S1 of " + names[k]);
  for (std::size_t k = 0; k < r.total.size(); ++k) check(r.total[k], "ST of " + names[k]);
  for (const sobol::SecondOrderIndex& s : r.second)
    check(s.s, fmt::format("S2 of {},{}", names[static_cast<std::size_t>(s.i)], names[static_cast<std::size_t>(s.j)]));
}

}  // namespace

// ---------------------------------------------------------------- Saltelli design and its responses

SaltelliSensitivity saltelli_sensitivity(const SaltelliSensitivityOptions& options) {
  const std::vector<std::string>& named = options.responses;
  if (options.responses_file.empty() && named.empty())
    throw UserError(
        "SaltelliSensitivityOptions.design needs the outputs of every design row: "
        "SaltelliSensitivityOptions.responses_file Y.csv (one row per design row), or "
        "SaltelliSensitivityOptions.responses NAME[,...] naming response columns appended to the design file");
  CsvTable table = read_saltelli_csv(options.design);
  // Responses appended to the design (design columns, then response columns in the same file) when no responses
  // file is given; with one, a named column that the design also holds could be either: refused.
  const bool appended = options.responses_file.empty();
  if (appended) {
    for (const std::string& name : named) table.column_index(name);  // names the file and its columns
    if (static_cast<int>(named.size()) >= static_cast<int>(table.columns.size()))
      throw UserError(options.design, 0,
                      "every column is named by SaltelliSensitivityOptions.responses: no parameter column is left");
  } else {
    for (const std::string& name : named)
      if (table.has_column(name))
        throw UserError(
            fmt::format("SaltelliSensitivityOptions.responses {}: ambiguous: '{}' is a column of the design {} and "
                        "SaltelliSensitivityOptions.responses_file {} is given too; drop "
                        "SaltelliSensitivityOptions.responses_file to read the appended column, or rename the design "
                        "column",
                        name, name, options.design, options.responses_file));
  }
  const SaltelliDesignFile file = saltelli_design_of(std::move(table), appended ? named : std::vector<std::string>{});
  const CsvTable& design = file.table;
  const std::vector<std::string>& names = file.parameters;
  const int d = static_cast<int>(names.size());
  // Scrambled Sobol' points are balanced only over 2^m of them (Owen 1997): another base costs accuracy.
  {
    const int replicates = file.replicates();
    const int base = file.base();
    if (!std::has_single_bit(static_cast<unsigned>(base)))
      emit_warning(
          options.warn,
          fmt::format("{}: the base N = {}{} is not a power of two: a scrambled Sobol' design is balanced only "
                      "at powers of two, and the extra rows cost accuracy instead of adding it (Ishigami, RMS "
                      "error of S1 and ST over 50 seeds: 1.4e-3 at N = 10000 against 1.0e-3 at N = 8192); "
                      "`demsa design saltelli` rounds N up to a power of two",
                      options.design, base,
                      replicates > 1 ? fmt::format(" of each of the {} replicates", replicates) : ""));
    if (replicates < 2 && options.indices.interval == sobol::SaltelliInterval::replicates)
      emit_warning(options.warn,
                   fmt::format("{}: one scrambled design, without independently scrambled replicates (column "
                               "'replicate'): its indices come without intervals. `demsa design saltelli` writes {} "
                               "replicates by default, from whose spread the intervals come; "
                               "SaltelliSensitivityOptions.interval bootstrap gives bootstrap intervals, conservative "
                               "for QMC (often several times too wide)",
                               options.design, sobol::k_default_saltelli_replicates));
  }

  const CsvTable y = appended ? design : util::read_csv(options.responses_file);
  if (y.rows() != design.rows())
    throw UserError(options.responses_file, 0,
                    fmt::format("{} rows, but the design {} has {}: give one output row per design row, in order",
                                y.rows(), options.design, design.rows()));
  options.indices.validate();  // a sobol::InputError names the field

  SaltelliSensitivity result;
  result.design = options.design;
  result.responses_file = appended ? options.design : options.responses_file;
  result.inputs = names;
  for (const std::string& name : named.empty() ? y.columns : named) {
    const int column = y.column_index(name);
    sobol::SaltelliResponses split;
    try {
      split = sobol::group_responses(y.values.col(column), file.codes, d);
    } catch (const sobol::DataError& e) {
      // Block structure problems belong to the design file, value problems to the responses file.
      if (e.detail().rfind("response", 0) == 0) y.fail(e.row(), column, e.detail());
      design.fail(e.row(), file.block_column, e.detail());
    } catch (const sobol::InputError& e) {
      throw UserError(options.design, 0, e.what());
    }
    split.replicate = file.replicate;
    SaltelliResponseIndices out;
    out.response = name;
    sobol::SobolResult& r = out.indices;
    try {
      r = sobol::sobol_indices(split, options.indices);
      require_finite_indices(r, names);
    } catch (const sobol::InputError& e) {
      throw UserError(options.design, 0, e.what());
    } catch (const sobol::NumericalError& e) {
      throw UserError(options.responses_file, 0, fmt::format("column '{}': {}", name, e.what()));
    }
    // An index whose whole interval lies outside [0, 1] is not estimator noise: the responses' rows most likely do
    // not belong to the design's rows (shuffled, sorted, from another design or seed). Without intervals (bounds on
    // the estimate) a small index just below 0 is estimator noise: nothing to say.
    std::vector<std::string> outside;
    const bool intervals = r.bootstrap > 0 || r.replicates > 0;
    for (std::size_t k = 0; k < names.size() && intervals; ++k)
      for (const auto& [label, e] : {std::pair{"S1", r.first[k]}, std::pair{"ST", r.total[k]}})
        if (e.upper < 0.0 || e.lower > 1.0)
          outside.push_back(
              fmt::format("{} of {} = {:.3f} [{:.3f}, {:.3f}]", label, names[k], e.value, e.lower, e.upper));
    if (!outside.empty())
      out.warning = fmt::format(
          "column '{}': {} lie{} wholly outside [0, 1]: the responses may not match the design's "
          "rows (same order as {}, from this design and seed?)",
          name, util::join(outside, "; "), outside.size() == 1 ? "s" : "", options.design);
    if (options.on_response) options.on_response(names, out);
    if (!out.warning.empty()) emit_warning(options.warn, out.warning);
    result.outputs.push_back(std::move(out));
  }
  if (!options.json_file.empty())
    util::write_file_atomically(options.json_file, saltelli_sensitivity_json(result).dump(2) + "\n");
  return result;
}

nlohmann::json saltelli_sensitivity_json(const SaltelliSensitivity& result) {
  nlohmann::json outputs = nlohmann::json::array();
  for (const SaltelliResponseIndices& o : result.outputs) {
    const bool intervals = o.indices.bootstrap > 0 || o.indices.replicates > 0;
    nlohmann::json j = sobol_result_json(o.indices, result.inputs,
                                         intervals ? IntervalJson::as_estimated : IntervalJson::null_without);
    j["output"] = o.response;
    if (!o.warning.empty()) j["warning"] = o.warning;
    outputs.push_back(j);
  }
  return {
      {"design", result.design}, {"responses", result.responses_file}, {"inputs", result.inputs}, {"outputs", outputs}};
}

// ---------------------------------------------------------------- samples and responses: metamodels, then indices

namespace {

/// Bounds per input: given, or the data's range.
std::vector<sobol::Bounds> bounds_of(const DataSensitivityOptions& options, const CsvTable& data,
                                     const std::vector<int>& columns) {
  const std::vector<std::string>& inputs = options.inputs;
  std::vector<sobol::Bounds> bounds(inputs.size());
  for (const auto& [name, given] : options.bounds)
    if (std::find(inputs.begin(), inputs.end(), name) == inputs.end())
      throw UserError(fmt::format("DataSensitivityOptions.bounds: '{}' is not one of the inputs", name));
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    if (const auto it = options.bounds.find(inputs[k]); it != options.bounds.end()) {
      bounds[k] = it->second;
      continue;
    }
    const Eigen::VectorXd col = data.values.col(columns[k]);
    bounds[k].low = col.minCoeff();
    bounds[k].high = col.maxCoeff();
    if (bounds[k].low == bounds[k].high)
      throw UserError(data.file, 0,
                      fmt::format("column '{}': constant input (every sample is {}): it carries no information; "
                                  "drop it from DataSensitivityOptions.inputs",
                                  inputs[k], bounds[k].low));
  }
  try {
    sobol::validate_bounds(bounds, inputs);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("DataSensitivityOptions.bounds: {}", e.what()));
  }
  return bounds;
}

/// Two inputs in an exact linear relation (a copy, a unit conversion) make every metamodel singular; say which.
void check_collinear_inputs(const CsvTable& data, const std::vector<std::string>& inputs,
                            const std::vector<int>& columns) {
  Eigen::MatrixXd centred(data.rows(), static_cast<Eigen::Index>(inputs.size()));
  for (std::size_t k = 0; k < inputs.size(); ++k)
    centred.col(static_cast<Eigen::Index>(k)) =
        data.values.col(columns[k]).array() - data.values.col(columns[k]).mean();
  for (std::size_t i = 0; i < inputs.size(); ++i)
    for (std::size_t j = i + 1; j < inputs.size(); ++j) {
      const auto a = centred.col(static_cast<Eigen::Index>(i));
      const auto b = centred.col(static_cast<Eigen::Index>(j));
      const double denominator = std::sqrt(a.squaredNorm() * b.squaredNorm());
      if (!(denominator > 0.0)) continue;  // a constant column is reported with its bounds
      const double r = a.dot(b) / denominator;
      if (std::abs(r) < 1.0 - 1e-12) continue;
      const double slope = a.dot(b) / a.squaredNorm();
      double intercept = data.values.col(columns[j]).mean() - slope * data.values.col(columns[i]).mean();
      if (std::abs(intercept) <= 1e-9 * data.values.col(columns[j]).cwiseAbs().maxCoeff()) intercept = 0.0;
      throw UserError(data.file, 0,
                      fmt::format("columns '{}' and '{}' are collinear ({} = {:.6g} * {} + {:.6g} in every sample): "
                                  "no metamodel can tell their effects apart; keep one of them in "
                                  "DataSensitivityOptions.inputs",
                                  inputs[i], inputs[j], inputs[j], slope, inputs[i], intercept));
    }
}

/// The noise of `response` from the repeated runs, grouped by their column `point` (sobol/noise.hpp), as the study
/// analysis measures it from [design] replicates; its share divides by the variance of `y` over the data.
NoiseAnalysis repeats_noise(const CsvTable& repeats, const std::string& response, const Eigen::VectorXd& y,
                            double confidence) {
  std::map<double, std::vector<double>> by_point;
  const Eigen::VectorXd points = repeats.column("point");
  const Eigen::VectorXd values = repeats.column(response);
  for (Eigen::Index r = 0; r < points.size(); ++r) by_point[points(r)].push_back(values(r));
  std::vector<std::vector<double>> groups;
  for (auto& [point, group] : by_point) groups.push_back(std::move(group));
  sobol::NoiseEstimate estimate;
  try {
    estimate = sobol::pooled_noise_variance(groups, confidence);
  } catch (const sobol::InputError& e) {
    throw UserError(repeats.file, 0, fmt::format("response '{}': {}", response, e.what()));
  }
  const double mean = y.mean();
  const double ss = (y.array() - mean).square().sum();
  const double n_rows = static_cast<double>(y.size());
  const double variance = y.size() > 1 ? ss / (n_rows - 1.0) : 0.0;
  NoiseAnalysis n;
  n.estimate = estimate;
  n.share = n.estimate.variance / variance;
  n.share_lower = n.estimate.lower / variance;
  n.share_upper = n.estimate.upper / variance;
  n.nugget_share = n.estimate.variance / (ss / n_rows);
  n.largest_s1 = std::numeric_limits<double>::quiet_NaN();
  return n;
}

/// A response the metamodels cannot take: values beyond double's sums of squares, or a constant.
void check_response(const CsvTable& data, const std::string& output, const Eigen::VectorXd& y) {
  if (const double largest = y.cwiseAbs().maxCoeff(); largest > sobol::k_large_output) {
    // Sums of squares of such values leave double's range: R² and indices would be NaN, an RBF would take the
    // output for constant and a GP blame duplicated points. The true cause, and the remedy:
    const auto at = static_cast<std::size_t>(std::distance(
        y.data(),
        std::max_element(y.data(), y.data() + y.size(), [](double a, double b) { return std::abs(a) < std::abs(b); })));
    throw UserError(data.file, 0,
                    fmt::format("output '{}': values reach {:.3g} in magnitude (line {}), beyond {:g}: the "
                                "metamodels' sums of squares would overflow double precision; divide the column "
                                "by a power of ten (Sobol' indices do not depend on the output's unit)",
                                output, y(static_cast<Eigen::Index>(at)), data.lines[at], sobol::k_large_output));
  }
  // A metamodel of a constant fits it exactly (R² NaN) and its indices are round-off: refuse.
  const double mean = y.mean();
  const double variance = y.size() > 1 ? (y.array() - mean).square().sum() / static_cast<double>(y.size()) : 0.0;
  if (sobol::negligible_variance(mean, variance))
    throw UserError(data.file, 0,
                    fmt::format("output '{}' is constant (every one of its {} samples is {:.10g}, standard "
                                "deviation {:.3g}): its Sobol' indices are undefined",
                                output, y.size(), mean, std::sqrt(variance)));
}

}  // namespace

DataSensitivity data_sensitivity(const DataSensitivityOptions& options) {
  const std::vector<std::string>& inputs = options.inputs;
  const std::vector<std::string>& outputs = options.responses;
  if (inputs.empty())
    throw UserError("DataSensitivityOptions.data needs DataSensitivityOptions.inputs NAME,... (the input columns)");
  if (outputs.empty())
    throw UserError(
        "DataSensitivityOptions.data needs DataSensitivityOptions.responses NAME[,...] (the response columns)");
  for (std::size_t i = 0; i < inputs.size(); ++i)
    for (std::size_t j = i + 1; j < inputs.size(); ++j)
      if (inputs[i] == inputs[j])
        throw UserError(fmt::format("DataSensitivityOptions.inputs: '{}' is listed twice", inputs[i]));
  for (const std::string& output : outputs)
    for (const std::string& input : inputs)
      if (output == input)
        throw UserError(fmt::format(
            "'{}' is both an input (DataSensitivityOptions.inputs) and a response (DataSensitivityOptions.responses)",
            output));
  util::CsvReadOptions read_options;
  read_options.numeric_columns = inputs;
  read_options.numeric_columns.insert(read_options.numeric_columns.end(), outputs.begin(), outputs.end());
  const CsvTable data = util::read_csv(options.data, read_options);
  std::vector<int> columns;
  for (const std::string& n : inputs) columns.push_back(data.column_index(n));
  for (const std::string& n : outputs) data.column_index(n);
  DataSensitivity result;
  result.data = options.data;
  result.samples = data.rows();
  result.inputs = inputs;
  result.bounds = bounds_of(options, data, columns);
  const std::vector<sobol::Bounds>& bounds = result.bounds;
  check_collinear_inputs(data, inputs, columns);

  // Inputs to the unit cube; a value outside its bounds is the user's to fix.
  Eigen::MatrixXd x(data.rows(), static_cast<Eigen::Index>(inputs.size()));
  for (int r = 0; r < data.rows(); ++r)
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      const double v = data.values(r, columns[k]);
      const sobol::Bounds& b = bounds[k];
      if (v < b.low || v > b.high || (b.scale == sobol::Scale::log_uniform && v <= 0.0))
        data.fail(r, columns[k], fmt::format("{} is outside the bounds [{}, {}]", v, b.low, b.high));
      x(r, static_cast<Eigen::Index>(k)) = sobol::to_unit(v, b);
    }
  // What share of each input's bounds the samples span (docs/reference/checks.md).
  result.coverage.assign(inputs.size(), 1.0);
  for (std::size_t k = 0; k < inputs.size() && x.rows() > 0; ++k) {
    const auto c = x.col(static_cast<Eigen::Index>(k));
    result.coverage[k] = c.maxCoeff() - c.minCoeff();
    if (result.coverage[k] >= k_min_coverage) continue;
    const Eigen::VectorXd raw = data.values.col(columns[k]);
    const std::string what = fmt::format(
        "DataSensitivityOptions.bounds {}={:g}:{:g}: the data cover {} in [{:g}, {:g}], {:.1f} % of the bounds (less "
        "than {:g} %): the metamodels would extrapolate over the rest, and the indices describe that extrapolation",
        inputs[k], bounds[k].low, bounds[k].high, inputs[k], raw.minCoeff(), raw.maxCoeff(), 100.0 * result.coverage[k],
        100.0 * k_min_coverage);
    if (!options.allow_extrapolation)
      throw UserError(what + "; narrow the bounds to the data, or give DataSensitivityOptions.allow_extrapolation");
    emit_warning(options.warn, what + " (DataSensitivityOptions.allow_extrapolation)");
  }

  const std::vector<sobol::MetamodelKind>& kinds = options.metamodels;
  if (kinds.empty()) throw UserError("DataSensitivityOptions.metamodels: no metamodel named");
  // One model to a file, several into a folder (named <response>.<metamodel>.json).
  const std::size_t model_count = outputs.size() * kinds.size();
  const std::filesystem::path save_path(options.save_model);
  if (!options.save_model.empty()) {
    // A model file names its inputs and output; `demsa predict` would refuse one it cannot read back.
    std::vector<std::string> names = inputs;
    names.insert(names.end(), outputs.begin(), outputs.end());
    for (const std::string& n : names)
      if (const std::string why = bad_name_reason(n); !why.empty())
        throw UserError(data.file, 0, fmt::format("DataSensitivityOptions.save_model: column {}", why));
  }
  const bool save_to_file =
      model_count == 1 && save_path.extension() == ".json" && !std::filesystem::is_directory(save_path);
  if (!options.save_model.empty()) {
    if (model_count > 1 && save_path.extension() == ".json" && !std::filesystem::is_directory(save_path))
      throw UserError(
          fmt::format("DataSensitivityOptions.save_model {}: {} metamodels ({} response(s) x {} kind(s)) need a "
                      "folder, not a .json file: give a folder (each model is written as "
                      "<response>.<metamodel>.json)",
                      options.save_model, model_count, outputs.size(), kinds.size()));
    const std::filesystem::path parent = save_to_file ? save_path.parent_path() : save_path;
    std::error_code ec;
    if (!parent.empty() && !save_to_file) std::filesystem::create_directories(parent, ec);
    if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
      throw UserError(
          fmt::format("DataSensitivityOptions.save_model {}: the folder '{}' does not exist and cannot be created",
                      options.save_model, parent.string()));
  }
  std::vector<std::pair<std::filesystem::path, std::string>> model_files;  // written once every model is fitted

  sobol::MetamodelSobolOptions index_options = options.indices;
  // As the study analysis and `design saltelli`: the QMC design on the metamodel is a scrambled Sobol' sequence,
  // balanced only at powers of two (Owen 1997; docs/explanation/benchmarks.md).
  index_options.base = balanced_base_samples(index_options.base, "DataSensitivityOptions.base",
                                             [&](const std::string& message) { emit_warning(options.warn, message); });
  index_options.validate();  // a sobol::InputError names the field

  std::optional<CsvTable> repeats;
  if (!options.repeats.empty()) {
    util::CsvReadOptions repeat_options;
    repeat_options.numeric_columns = {"point"};
    repeat_options.numeric_columns.insert(repeat_options.numeric_columns.end(), outputs.begin(), outputs.end());
    repeats = util::read_csv(options.repeats, repeat_options);
  }

  for (const std::string& output : outputs) {
    const Eigen::VectorXd y = data.column(output);
    DataResponseIndices response;
    response.response = output;
    sobol::MetamodelOptions output_options = options.models;
    if (repeats) {
      response.noise = repeats_noise(*repeats, output, y, index_options.confidence);
      output_options.gp.nugget = true;
      output_options.gp.noise_share = response.noise->nugget_share;
    }
    check_response(data, output, y);
    double best_q2 = -std::numeric_limits<double>::infinity();
    for (const sobol::MetamodelKind kind : kinds) {
      DataModelIndices model;
      model.metamodel = sobol::to_string(kind);
      sobol::throw_if_stopped(index_options.stop);
      FittedMetamodel fit = fit_metamodel(kind, output_options, x, y);
      model.quality = fit.quality;
      try {
        // Unlike the study analysis, a model that does not fit is the user's to fix: its error names the line.
        if (!fit.ok()) std::rethrow_exception(fit.exception);
        // As the study analysis (analysis/fit.hpp): no index from a fit whose leave-one-out error cannot be measured.
        if (const std::string why = unmeasurable_error(fit.quality); !why.empty())
          throw UserError(data.file, 0, fmt::format("output '{}', metamodel {}: {}", output, model.metamodel, why));
        model.indices = sobol::metamodel_sobol(*fit.model, index_options);
        require_finite_indices(model.indices, inputs);
      } catch (const sobol::DataError& e) {
        const int column = e.column() >= 0 ? columns[static_cast<std::size_t>(e.column())] : -1;
        std::string other;
        if (e.other_row() >= 0) {
          const std::size_t first = static_cast<std::size_t>(e.other_row());
          std::string point;
          for (std::size_t k = 0; k < inputs.size(); ++k)
            point += fmt::format("{}{} = {}", k ? ", " : "", inputs[k],
                                 data.values(static_cast<Eigen::Index>(first), columns[k]));
          other = fmt::format(" (sample {} is line {}: {})", first + 1, data.lines[first], point);
        }
        data.fail(e.row(), column,
                  fmt::format("{}{} (metamodel {}, output '{}')", e.detail(), other, model.metamodel, output));
      } catch (const sobol::InputError& e) {
        throw UserError(data.file, 0, fmt::format("output '{}': {}", output, e.what()));
      } catch (const sobol::NumericalError& e) {
        throw UserError(data.file, 0, fmt::format("output '{}': {}", output, e.what()));
      }
      if (!options.save_model.empty()) {
        const std::filesystem::path file =
            save_to_file ? save_path : save_path / model_file_name(output, model.metamodel);
        SavedModel saved{std::move(fit.model), inputs, bounds, output, ""};
        model_files.emplace_back(file, model_to_json(saved));
        model.saved_to = file.string();
      }
      if (options.on_model) options.on_model(output, model);
      const double q2 = std::isfinite(model.quality.q2) ? model.quality.q2 : -1e300;
      if (response.noise && q2 > best_q2 && !model.indices.first.empty()) {
        best_q2 = q2;
        response.noise->largest_s1 = 0.0;
        for (const sobol::IndexEstimate& e : model.indices.first)
          response.noise->largest_s1 = std::max(response.noise->largest_s1, e.value);
      }
      response.models.push_back(std::move(model));
    }
    if (response.noise) {
      response.noise->dominates = noise_dominates(response.noise->share, response.noise->largest_s1);
      if (options.on_noise) options.on_noise(*response.noise);
    }
    result.outputs.push_back(std::move(response));
  }
  for (const auto& [file, text] : model_files) {
    util::write_file_atomically(file, text);
    result.model_files.push_back(file.string());
  }
  if (!options.json_file.empty())
    util::write_file_atomically(options.json_file, data_sensitivity_json(result).dump(2) + "\n");
  return result;
}

nlohmann::json data_sensitivity_json(const DataSensitivity& result) {
  nlohmann::json outputs = nlohmann::json::array();
  for (const DataResponseIndices& response : result.outputs) {
    nlohmann::json models = nlohmann::json::array();
    for (const DataModelIndices& m : response.models)
      models.push_back({{"metamodel", m.metamodel},
                        {"quality", metamodel_summary_json(m.quality)},
                        {"sobol", sobol_result_json(m.indices, result.inputs)}});
    nlohmann::json entry{{"output", response.response}, {"metamodels", models}};
    if (response.noise) entry["noise"] = noise_json(*response.noise);
    outputs.push_back(entry);
  }
  nlohmann::json bounds = nlohmann::json::array();
  for (std::size_t k = 0; k < result.inputs.size(); ++k)
    bounds.push_back({{"input", result.inputs[k]},
                      {"low", result.bounds[k].low},
                      {"high", result.bounds[k].high},
                      {"scale", sobol::to_string(result.bounds[k].scale)},
                      {"coverage", result.coverage[k]},
                      {"extrapolated", result.coverage[k] < k_min_coverage}});
  return {{"data", result.data},
          {"samples", result.samples},
          {"inputs", result.inputs},
          {"bounds", bounds},
          {"outputs", outputs}};
}

namespace {

std::string interval_text(const sobol::IndexEstimate& e) {
  if (e.lower == e.value && e.upper == e.value) return fmt::format("{:8.4f}", e.value);
  return fmt::format("{:8.4f} [{:7.4f}, {:7.4f}]", e.value, e.lower, e.upper);
}

}  // namespace

std::string sobol_indices_text(const sobol::SobolResult& r, const std::vector<std::string>& names) {
  std::size_t width = 5;
  for (const std::string& n : names) width = std::max(width, n.size());
  std::string text = fmt::format("  {:<{}}  {:<27}  {:<27}\n", "input", width, "S1", "ST");
  for (std::size_t k = 0; k < names.size(); ++k)
    text += fmt::format("  {:<{}}  {:<27}  {:<27}\n", names[k], width, interval_text(r.first[k]),
                        interval_text(r.total[k]));
  text += fmt::format("  residual 1 - sum S1: {}\n", interval_text(r.residual));
  for (const sobol::SecondOrderIndex& s : r.second)
    text += fmt::format("  S2 {},{}: {}\n", names[static_cast<std::size_t>(s.i)], names[static_cast<std::size_t>(s.j)],
                        interval_text(s.s));
  if (r.replicates > 0)
    text += fmt::format("  ({:g}% Student-t intervals from {} independently scrambled replicates)\n",
                        100 * r.confidence, r.replicates);
  if (r.bootstrap > 0)
    text += fmt::format("  ({:g}% intervals from {} bootstrap resamples)\n", 100 * r.confidence, r.bootstrap);
  if (!r.note.empty()) text += fmt::format("  ({})\n", r.note);
  return text;
}

std::string saltelli_response_text(const SaltelliResponseIndices& response, const std::vector<std::string>& inputs) {
  return fmt::format("{}: Sobol' indices from a Saltelli design, N = {}, {} evaluations\n", response.response,
                     response.indices.base, response.indices.evaluations) +
         sobol_indices_text(response.indices, inputs);
}

std::string data_model_text(const std::string& response, const DataModelIndices& model,
                            const std::vector<std::string>& inputs) {
  return fmt::format("{} ~ {}: R2 {:.4f}, adjusted R2 {:.4f}, Q2_LOO {:.4f} ({} samples)\n", response, model.metamodel,
                     model.quality.r2, model.quality.adjusted_r2, model.quality.q2, model.quality.samples) +
         sobol_indices_text(model.indices, inputs);
}

}  // namespace demsa::analysis
