// `demsa sensitivity`: Sobol' indices for any simulator (README "Usage"; paper §5–6), either
//   --saltelli DESIGN.csv --responses Y.csv   outputs evaluated outside on a `demsa design saltelli` design (or
//   --saltelli DESIGN.csv --response NAME     response columns appended to the design file, the SALib habit),
//                                             intervals from the design's replicates (--interval, default
//                                             `replicates`; the bootstrap by name), or
//   --data DATA.csv --inputs ... --response ... samples the user already has: metamodels fitted on the unit cube
//                                             (scaled by --bounds or by the data's range), indices of each;
//                                             --save-model writes each fitted model (analysis/model_file.hpp).
// Option names across the commands: -o/--out is a file or folder demsa writes, --response a column of responses
// (--output, the old spelling of both, is a deprecated alias that warns).
// Every input error names the user's file, line, column and value. A constant output (up to round-off) is an error
// on both paths. SIGINT/SIGTERM stop the long loops (bootstrap, refits, QMC) within a step: exit 128 + N, and the
// --json file is not written.
#include "orchestrator/analysis/fit.hpp"
#include "orchestrator/analysis/model_file.hpp"
#include "orchestrator/analysis/sobol_json.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "orchestrator/util/signals.hpp"
#include "orchestrator/util/text.hpp"
#include "sobol/error.hpp"
#include "sobol/metamodel.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/noise.hpp"
#include "sobol/saltelli.hpp"
#include "sobol/scaling.hpp"
#include "sobol/stop.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::analysis;

namespace {

constexpr int k_mode_default = std::numeric_limits<int>::min();

struct SensitivityArgs {
  std::string saltelli;
  std::string responses;
  std::string data;
  std::string inputs;
  std::string outputs;
  std::string bounds;
  std::string metamodels = "rsm2,rsm3,rbf-cubic,rbf-tps,gp";
  bool second_order = false;
  int bootstrap = k_mode_default;  ///< k_mode_default: 200 resamples for --saltelli, 100 refits for --data
  std::string interval;            ///< --saltelli: sobol::SaltelliInterval by name ("": replicates, or bootstrap when
                                   ///< --bootstrap is given)
  double confidence = 0.95;
  int base = 16384;
  std::uint64_t seed = 12345;
  std::string json;        ///< file, or "-" for standard output
  std::string save_model;  ///< --data: model file (one model) or folder (several)
  std::string gp_kernel = "squared-exponential";
  std::string gp_trend = "constant";
  bool gp_nugget = false;
  std::string replicates;            ///< --data: CSV of repeated runs (column `point` + the responses) for the noise
  bool allow_extrapolation = false;  ///< --data: proceed when the data cover less than k_min_coverage of --bounds
};

/// --data: the least share of an input's --bounds (on its scale) the samples must span. Below it the metamodels
/// extrapolate over most of the box, and the indices, integrals over the whole box, describe the extrapolation.
constexpr double k_min_coverage = 0.5;

/// The numeric options, checked here so that a message names the option as the user typed it.
void check_numeric_options(const SensitivityArgs& args) {
  if (args.bootstrap != k_mode_default && args.bootstrap < 0)
    throw UserError(fmt::format("--bootstrap {}: must be >= 0 (0: no intervals)", args.bootstrap));
  if (!(args.confidence > 0.0 && args.confidence < 1.0))
    throw UserError(fmt::format("--confidence {}: must be strictly between 0 and 1 (e.g. 0.95)", args.confidence));
  if (args.base < 16)
    throw UserError(
        fmt::format("--base {}: must be at least 16 (a power of two, e.g. 16384, balances best)", args.base));
  if (args.base > sobol::k_max_base_samples)
    throw UserError(
        fmt::format("--base {}: at most 2^20 = {} (the indices' QMC design holds N (2d + 2) points in "
                    "memory)",
                    args.base, sobol::k_max_base_samples));
}

std::string interval_text(const sobol::IndexEstimate& e) {
  if (e.lower == e.value && e.upper == e.value) return fmt::format("{:8.4f}", e.value);
  return fmt::format("{:8.4f} [{:7.4f}, {:7.4f}]", e.value, e.lower, e.upper);
}

void print_indices(const sobol::SobolResult& r, const std::vector<std::string>& names) {
  std::size_t width = 5;
  for (const std::string& n : names) width = std::max(width, n.size());
  fmt::print("  {:<{}}  {:<27}  {:<27}\n", "input", width, "S1", "ST");
  for (std::size_t k = 0; k < names.size(); ++k)
    fmt::print("  {:<{}}  {:<27}  {:<27}\n", names[k], width, interval_text(r.first[k]), interval_text(r.total[k]));
  fmt::print("  residual 1 - sum S1: {}\n", interval_text(r.residual));
  for (const sobol::SecondOrderIndex& s : r.second)
    fmt::print("  S2 {},{}: {}\n", names[static_cast<std::size_t>(s.i)], names[static_cast<std::size_t>(s.j)],
               interval_text(s.s));
  if (r.replicates > 0)
    fmt::print("  ({:g}% Student-t intervals from {} independently scrambled replicates)\n", 100 * r.confidence,
               r.replicates);
  if (r.bootstrap > 0) fmt::print("  ({:g}% intervals from {} bootstrap resamples)\n", 100 * r.confidence, r.bootstrap);
  if (!r.note.empty()) fmt::print("  ({})\n", r.note);
}

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

void write_json(const std::string& target, const nlohmann::json& j) {
  if (target.empty()) return;
  if (target == "-") {
    fmt::print("{}\n", j.dump(2));
    return;
  }
  std::ofstream out(target, std::ios::trunc);
  if (!out) throw UserError(target, 0, "cannot write the file");
  out << j.dump(2) << '\n';
  if (!out.flush()) throw UserError(target, 0, "write failed");
}

// ---------------------------------------------------------------- --saltelli DESIGN.csv --responses Y.csv

/// The interval method of --saltelli: --interval by name; without it the replicates', or the bootstrap when
/// --bootstrap gives its resamples (the bootstrap named by its option).
sobol::SaltelliInterval saltelli_interval(const SensitivityArgs& args) {
  const bool resamples_given = args.bootstrap != k_mode_default;
  if (args.interval.empty())
    return resamples_given ? sobol::SaltelliInterval::bootstrap : sobol::SaltelliInterval::replicates;
  sobol::SaltelliInterval interval;
  try {
    interval = sobol::saltelli_interval_from_string(args.interval);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("--interval: {}", e.what()));
  }
  if (resamples_given && interval != sobol::SaltelliInterval::bootstrap)
    throw UserError(fmt::format("--bootstrap {} gives the resamples of --interval bootstrap, not of --interval {}",
                                args.bootstrap, args.interval));
  return interval;
}

void run_saltelli(const SensitivityArgs& args) {
  const sobol::SaltelliInterval interval = saltelli_interval(args);
  if (!args.save_model.empty())
    throw UserError("--save-model: a Saltelli design gives indices without a metamodel: nothing to save (use --data)");
  const std::vector<std::string> named = split_list(args.outputs);
  if (args.responses.empty() && named.empty())
    throw UserError(
        "--saltelli needs the outputs of every design row: --responses Y.csv (one row per design row), or "
        "--response NAME[,...] naming response columns appended to the design file");
  CsvReadOptions design_options;
  design_options.require_varying = true;  // a parameter held constant was not sampled: its indices would be noise
  const CsvTable design = read_csv(args.saltelli, design_options);
  // Responses appended to the design (design columns, then response columns in the same file) when no --responses
  // file is given; with one, a named column that the design also holds could be either: refused.
  const bool appended = args.responses.empty();
  if (appended) {
    for (const std::string& name : named) design.column_index(name);  // names the file and its columns
    if (static_cast<int>(named.size()) >= static_cast<int>(design.columns.size()))
      throw UserError(args.saltelli, 0, "every column is named by --response: no parameter column is left");
  } else {
    for (const std::string& name : named)
      if (design.has_column(name))
        throw UserError(fmt::format(
            "--response {}: ambiguous: '{}' is a column of the design {} and --responses {} is given too; drop "
            "--responses to read the appended column, or rename the design column",
            name, name, args.saltelli, args.responses));
  }
  const int block_column = design.column_index("block");
  int replicate_column = -1;  // optional: written by `demsa design saltelli --replicates R`
  for (int k = 0; k < static_cast<int>(design.columns.size()); ++k)
    if (design.columns[static_cast<std::size_t>(k)] == "replicate") replicate_column = k;
  std::vector<std::string> names;
  std::vector<int> parameter_columns;  // column of names[k] in the file
  const auto is_response = [&](int k) {
    return appended &&
           std::find(named.begin(), named.end(), design.columns[static_cast<std::size_t>(k)]) != named.end();
  };
  for (int k = 0; k < static_cast<int>(design.columns.size()); ++k)
    if (k != block_column && k != replicate_column && !is_response(k)) {
      names.push_back(design.columns[static_cast<std::size_t>(k)]);
      parameter_columns.push_back(k);
    }
  const int d = static_cast<int>(names.size());
  if (d < 1) design.fail(-1, -1, "no parameter column besides 'block'");
  std::vector<int> codes(static_cast<std::size_t>(design.rows()));
  for (int r = 0; r < design.rows(); ++r) {
    const double c = design.values(r, block_column);
    if (c != std::floor(c) || c < 0 || c > 2 * d + 1)
      design.fail(
          r, block_column,
          fmt::format("'{}' is not a block code 0..{} (0 = A, 1 = B, 1+i = AB_i, 1+{}+i = BA_i)", c, 2 * d + 1, d));
    codes[static_cast<std::size_t>(r)] = static_cast<int>(c);
  }
  // The parameter values must form a Saltelli design (AB_i from A and B, A and B independent): indices computed
  // from anything else are wrong without any sign in the numbers.
  Eigen::MatrixXd x(design.rows(), d);
  for (int k = 0; k < d; ++k) x.col(k) = design.values.col(parameter_columns[static_cast<std::size_t>(k)]);
  try {
    sobol::check_saltelli_inputs(x, codes, d);
  } catch (const sobol::DataError& e) {
    design.fail(e.row(), e.column() >= 0 ? parameter_columns[static_cast<std::size_t>(e.column())] : block_column,
                e.detail());
  } catch (const sobol::InputError& e) {
    throw UserError(args.saltelli, 0, e.what());
  }
  std::vector<int> replicate;  // of each base row; empty without a replicate column
  if (replicate_column >= 0) {
    std::vector<long long> labels(static_cast<std::size_t>(design.rows()));
    for (int r = 0; r < design.rows(); ++r) {
      const double v = design.values(r, replicate_column);
      if (v != std::floor(v) || std::abs(v) > 1e15)
        design.fail(r, replicate_column, fmt::format("'{}' is not a replicate number (an integer)", v));
      labels[static_cast<std::size_t>(r)] = static_cast<long long>(v);
    }
    try {
      replicate = sobol::base_row_replicates(codes, labels, d);
    } catch (const sobol::DataError& e) {
      design.fail(e.row(), replicate_column, e.detail());
    }
  }
  // Scrambled Sobol' points are balanced only over 2^m of them (Owen 1997): another base costs accuracy.
  {
    const int replicates = replicate.empty() ? 1 : 1 + *std::max_element(replicate.begin(), replicate.end());
    const int base = static_cast<int>(std::count(codes.begin(), codes.end(), 0)) / replicates;
    if (!std::has_single_bit(static_cast<unsigned>(base)))
      log::warn(
          "{}: the base N = {}{} is not a power of two: a scrambled Sobol' design is balanced only at powers of two, "
          "and the extra rows cost accuracy instead of adding it (Ishigami, RMS error of S1 and ST over 50 seeds: "
          "1.4e-3 at N = 10000 against 1.0e-3 at N = 8192); `demsa design saltelli` rounds N up to a power of two",
          args.saltelli, base, replicates > 1 ? fmt::format(" of each of the {} replicates", replicates) : "");
    if (replicates < 2 && interval == sobol::SaltelliInterval::replicates)
      log::warn(
          "{}: one scrambled design, without independently scrambled replicates (column 'replicate'): its indices "
          "come without intervals. `demsa design saltelli` writes {} replicates by default, from whose spread the "
          "intervals come; --interval bootstrap gives bootstrap intervals, conservative for QMC (often several times "
          "too wide)",
          args.saltelli, sobol::k_default_saltelli_replicates);
  }

  const CsvTable y = appended ? design : read_csv(args.responses);
  if (y.rows() != design.rows())
    throw UserError(args.responses, 0,
                    fmt::format("{} rows, but the design {} has {}: give one output row per design row, in order",
                                y.rows(), args.saltelli, design.rows()));
  const std::vector<std::string> outputs = named.empty() ? y.columns : named;

  sobol::SobolOptions options;
  options.second_order = args.second_order;
  options.interval = interval;
  options.bootstrap = args.bootstrap == k_mode_default ? 200 : args.bootstrap;
  options.confidence = args.confidence;
  options.seed = args.seed;
  options.stop = [] { return StopFlag::raised(); };
  options.validate();  // a sobol::InputError is the user's (cli::run_cli)

  nlohmann::json results = nlohmann::json::array();
  for (const std::string& name : outputs) {
    const int column = y.column_index(name);
    sobol::SaltelliResponses split;
    try {
      split = sobol::group_responses(y.values.col(column), codes, d);
    } catch (const sobol::DataError& e) {
      // Block structure problems belong to the design file, value problems to the responses file.
      if (e.detail().rfind("response", 0) == 0) y.fail(e.row(), column, e.detail());
      design.fail(e.row(), block_column, e.detail());
    } catch (const sobol::InputError& e) {
      throw UserError(args.saltelli, 0, e.what());
    }
    split.replicate = replicate;
    sobol::SobolResult r;
    try {
      r = sobol::sobol_indices(split, options);
      require_finite_indices(r, names);
    } catch (const sobol::InputError& e) {
      throw UserError(args.saltelli, 0, e.what());
    } catch (const sobol::NumericalError& e) {
      throw UserError(args.responses, 0, fmt::format("column '{}': {}", name, e.what()));
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
    std::string warning;
    if (!outside.empty())
      warning = fmt::format(
          "column '{}': {} lie{} wholly outside [0, 1]: the responses may not match the design's "
          "rows (same order as {}, from this design and seed?)",
          name, join(outside, "; "), outside.size() == 1 ? "s" : "", args.saltelli);
    if (args.json != "-") {
      fmt::print("{}: Sobol' indices from a Saltelli design, N = {}, {} evaluations\n", name, r.base, r.evaluations);
      print_indices(r, names);
    }
    if (!warning.empty()) log::warn("{}", warning);
    nlohmann::json j = sobol_result_json(r, names);
    j["output"] = name;
    if (!warning.empty()) j["warning"] = warning;
    results.push_back(j);
  }
  write_json(args.json, {{"design", args.saltelli},
                         {"responses", appended ? args.saltelli : args.responses},
                         {"inputs", names},
                         {"outputs", results}});
}

// ---------------------------------------------------------------- --data DATA.csv: metamodels, then indices

/// "name=low:high[:log],..." -> bounds per input (inputs without an entry: the data's range).
std::vector<sobol::Bounds> parse_bounds(const std::string& text, const std::vector<std::string>& inputs,
                                        const CsvTable& data, const std::vector<int>& columns) {
  std::vector<sobol::Bounds> bounds(inputs.size());
  std::vector<bool> given(inputs.size(), false);
  for (const std::string& item : split_list(text)) {
    const std::size_t eq = item.find('=');
    const std::string name = eq == std::string::npos ? "" : item.substr(0, eq);
    std::size_t k = 0;
    while (k < inputs.size() && inputs[k] != name) ++k;
    if (eq == std::string::npos || k == inputs.size())
      throw UserError(fmt::format("--bounds '{}': expected NAME=LOW:HIGH[:log] with NAME one of --inputs", item));
    std::vector<std::string> parts;
    std::string rest = item.substr(eq + 1);
    for (std::size_t c = rest.find(':'); c != std::string::npos; c = rest.find(':')) {
      parts.push_back(rest.substr(0, c));
      rest = rest.substr(c + 1);
    }
    parts.push_back(rest);
    if (parts.size() < 2 || parts.size() > 3)
      throw UserError(fmt::format("--bounds '{}': expected NAME=LOW:HIGH[:log]", item));
    auto number = [&](const std::string& s) {
      char* end = nullptr;
      const double v = std::strtod(s.c_str(), &end);
      if (s.empty() || *end != '\0') throw UserError(fmt::format("--bounds '{}': '{}' is not a number", item, s));
      return v;
    };
    bounds[k].low = number(parts[0]);
    bounds[k].high = number(parts[1]);
    if (parts.size() == 3) {
      try {
        bounds[k].scale = sobol::scale_from_string(parts[2]);
      } catch (const sobol::InputError& e) {
        throw UserError(fmt::format("--bounds '{}': {}", item, e.what()));
      }
    }
    if (given[k]) throw UserError(fmt::format("--bounds: '{}' is given twice", name));
    given[k] = true;
  }
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    if (given[k]) continue;
    const Eigen::VectorXd col = data.values.col(columns[k]);
    bounds[k].low = col.minCoeff();
    bounds[k].high = col.maxCoeff();
    if (bounds[k].low == bounds[k].high)
      throw UserError(data.file, 0,
                      fmt::format("column '{}': constant input (every sample is {}): it carries no information; "
                                  "drop it from --inputs",
                                  inputs[k], bounds[k].low));
  }
  try {
    sobol::validate_bounds(bounds, inputs);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("--bounds: {}", e.what()));
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
                                  "no metamodel can tell their effects apart; keep one of them in --inputs",
                                  inputs[i], inputs[j], inputs[j], slope, inputs[i], intercept));
    }
}

void run_data(const SensitivityArgs& args) {
  const std::vector<std::string> inputs = split_list(args.inputs);
  const std::vector<std::string> outputs = split_list(args.outputs);
  if (inputs.empty()) throw UserError("--data needs --inputs NAME,... (the input columns)");
  if (outputs.empty()) throw UserError("--data needs --response NAME[,...] (the response columns)");
  for (std::size_t i = 0; i < inputs.size(); ++i)
    for (std::size_t j = i + 1; j < inputs.size(); ++j)
      if (inputs[i] == inputs[j]) throw UserError(fmt::format("--inputs: '{}' is listed twice", inputs[i]));
  for (const std::string& output : outputs)
    for (const std::string& input : inputs)
      if (output == input)
        throw UserError(fmt::format("'{}' is both an input (--inputs) and a response (--response)", output));
  CsvReadOptions read_options;
  read_options.numeric_columns = inputs;
  read_options.numeric_columns.insert(read_options.numeric_columns.end(), outputs.begin(), outputs.end());
  const CsvTable data = read_csv(args.data, read_options);
  std::vector<int> columns;
  for (const std::string& n : inputs) columns.push_back(data.column_index(n));
  for (const std::string& n : outputs) data.column_index(n);
  const std::vector<sobol::Bounds> bounds = parse_bounds(args.bounds, inputs, data, columns);
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
  // What share of each input's bounds the samples span (docs/checks.md).
  std::vector<double> coverage(inputs.size(), 1.0);
  for (std::size_t k = 0; k < inputs.size() && x.rows() > 0; ++k) {
    const auto c = x.col(static_cast<Eigen::Index>(k));
    coverage[k] = c.maxCoeff() - c.minCoeff();
    if (coverage[k] >= k_min_coverage) continue;
    const Eigen::VectorXd raw = data.values.col(columns[k]);
    const std::string what = fmt::format(
        "--bounds {}={:g}:{:g}: the data cover {} in [{:g}, {:g}], {:.1f} % of the bounds (less than {:g} %): the "
        "metamodels would extrapolate over the rest, and the indices describe that extrapolation",
        inputs[k], bounds[k].low, bounds[k].high, inputs[k], raw.minCoeff(), raw.maxCoeff(), 100.0 * coverage[k],
        100.0 * k_min_coverage);
    if (!args.allow_extrapolation)
      throw UserError(what + "; narrow the bounds to the data, or give --allow-extrapolation");
    log::warn("{} (--allow-extrapolation)", what);
  }

  std::vector<sobol::MetamodelKind> kinds;
  for (const std::string& name : split_list(args.metamodels)) {
    try {
      kinds.push_back(sobol::metamodel_kind_from_string(name));
    } catch (const sobol::InputError& e) {
      throw UserError(fmt::format("--metamodels: {}", e.what()));
    }
  }
  if (kinds.empty()) throw UserError("--metamodels: no metamodel named");
  // --save-model: one model to a file, several into a folder (named <response>.<metamodel>.json).
  const std::size_t model_count = outputs.size() * kinds.size();
  const std::filesystem::path save_path(args.save_model);
  if (!args.save_model.empty()) {
    // A model file names its inputs and output; `demsa predict` would refuse one it cannot read back.
    std::vector<std::string> names = inputs;
    names.insert(names.end(), outputs.begin(), outputs.end());
    for (const std::string& n : names)
      if (const std::string why = bad_name_reason(n); !why.empty())
        throw UserError(data.file, 0, fmt::format("--save-model: column {}", why));
  }
  const bool save_to_file =
      model_count == 1 && save_path.extension() == ".json" && !std::filesystem::is_directory(save_path);
  if (!args.save_model.empty()) {
    if (model_count > 1 && save_path.extension() == ".json" && !std::filesystem::is_directory(save_path))
      throw UserError(
          fmt::format("--save-model {}: {} metamodels ({} response(s) x {} kind(s)) need a folder, "
                      "not a .json file: give a folder (each model is written as "
                      "<response>.<metamodel>.json)",
                      args.save_model, model_count, outputs.size(), kinds.size()));
    const std::filesystem::path parent = save_to_file ? save_path.parent_path() : save_path;
    std::error_code ec;
    if (!parent.empty() && !save_to_file) std::filesystem::create_directories(parent, ec);
    if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
      throw UserError(fmt::format("--save-model {}: the folder '{}' does not exist and cannot be created",
                                  args.save_model, parent.string()));
  }
  std::vector<std::pair<std::filesystem::path, std::string>> model_files;  // written once every model is fitted

  sobol::MetamodelSobolOptions options;
  options.base = args.base;
  if (!std::has_single_bit(static_cast<unsigned>(args.base))) {
    // As `analyze --base` and `design saltelli --base`: the QMC design on the metamodel is a scrambled Sobol'
    // sequence, balanced only at powers of two (Owen 1997; docs/benchmarks.md).
    options.base = static_cast<int>(std::bit_ceil(static_cast<unsigned>(args.base)));
    log::warn(
        "--base {} is not a power of two: rounded up to {} (a scrambled Sobol' sequence is balanced only at "
        "powers of two; Saltelli 2010 takes N = 2^k)",
        args.base, options.base);
  }
  options.second_order = args.second_order;
  options.bootstrap = args.bootstrap == k_mode_default ? 100 : args.bootstrap;
  options.confidence = args.confidence;
  options.seed = args.seed;
  options.stop = [] { return StopFlag::raised(); };
  options.validate();  // a sobol::InputError is the user's (cli::run_cli)
  sobol::MetamodelOptions model_options;
  model_options.gp.seed = args.seed;
  model_options.gp.nugget = args.gp_nugget;
  try {
    model_options.gp.kernel = sobol::gp_kernel_from_string(args.gp_kernel);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("--gp-kernel: {}", e.what()));
  }
  try {
    model_options.gp.trend = sobol::gp_trend_from_string(args.gp_trend);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("--gp-trend: {}", e.what()));
  }

  // --replicates: the runs of each input point grouped by the column `point`; each response's noise is their pooled
  // within-point variance (sobol/noise.hpp), as the study analysis measures it from [design] replicates.
  std::optional<CsvTable> replicates;
  if (!args.replicates.empty()) {
    CsvReadOptions replicate_options;
    replicate_options.numeric_columns = {"point"};
    replicate_options.numeric_columns.insert(replicate_options.numeric_columns.end(), outputs.begin(), outputs.end());
    replicates = read_csv(args.replicates, replicate_options);
  }

  nlohmann::json results = nlohmann::json::array();
  for (const std::string& output : outputs) {
    const Eigen::VectorXd y = data.column(output);
    std::optional<NoiseAnalysis> noise;
    sobol::MetamodelOptions output_options = model_options;
    if (replicates) {
      std::map<double, std::vector<double>> by_point;
      const Eigen::VectorXd points = replicates->column("point");
      const Eigen::VectorXd values = replicates->column(output);
      for (Eigen::Index r = 0; r < points.size(); ++r) by_point[points(r)].push_back(values(r));
      std::vector<std::vector<double>> groups;
      for (auto& [point, group] : by_point) groups.push_back(std::move(group));
      NoiseAnalysis n;
      try {
        n.estimate = sobol::pooled_noise_variance(groups, args.confidence);
      } catch (const sobol::InputError& e) {
        throw UserError(replicates->file, 0, fmt::format("response '{}': {}", output, e.what()));
      }
      const double mean = y.mean();
      const double ss = (y.array() - mean).square().sum();
      const double n_rows = static_cast<double>(y.size());
      const double variance = y.size() > 1 ? ss / (n_rows - 1.0) : 0.0;
      n.share = n.estimate.variance / variance;
      n.share_lower = n.estimate.lower / variance;
      n.share_upper = n.estimate.upper / variance;
      n.nugget_share = n.estimate.variance / (ss / n_rows);
      n.largest_s1 = std::numeric_limits<double>::quiet_NaN();
      output_options.gp.nugget = true;
      output_options.gp.noise_share = n.nugget_share;
      noise = n;
    }
    double best_q2 = -std::numeric_limits<double>::infinity();
    if (const double largest = y.cwiseAbs().maxCoeff(); largest > sobol::k_large_output) {
      // Sums of squares of such values leave double's range: R² and indices would be NaN, an RBF would take the
      // output for constant and a GP blame duplicated points. The true cause, and the remedy:
      const auto at = static_cast<std::size_t>(
          std::distance(y.data(), std::max_element(y.data(), y.data() + y.size(),
                                                   [](double a, double b) { return std::abs(a) < std::abs(b); })));
      throw UserError(data.file, 0,
                      fmt::format("output '{}': values reach {:.3g} in magnitude (line {}), beyond {:g}: the "
                                  "metamodels' sums of squares would overflow double precision; divide the column "
                                  "by a power of ten (Sobol' indices do not depend on the output's unit)",
                                  output, y(static_cast<Eigen::Index>(at)), data.lines[at], sobol::k_large_output));
    }
    {
      // A metamodel of a constant fits it exactly (R² NaN) and its indices are round-off: refuse.
      const double mean = y.mean();
      const double variance = y.size() > 1 ? (y.array() - mean).square().sum() / static_cast<double>(y.size()) : 0.0;
      if (sobol::negligible_variance(mean, variance))
        throw UserError(data.file, 0,
                        fmt::format("output '{}' is constant (every one of its {} samples is {:.10g}, standard "
                                    "deviation {:.3g}): its Sobol' indices are undefined",
                                    output, y.size(), mean, std::sqrt(variance)));
    }
    nlohmann::json models = nlohmann::json::array();
    for (const sobol::MetamodelKind kind : kinds) {
      const std::string model_name = sobol::to_string(kind);
      sobol::throw_if_stopped(options.stop);
      FittedMetamodel fit = fit_metamodel(kind, output_options, x, y);
      const sobol::MetamodelSummary& summary = fit.quality;
      sobol::SobolResult indices;
      try {
        // Unlike the study analysis, a model that does not fit is the user's to fix: its error names the line.
        if (!fit.ok()) std::rethrow_exception(fit.exception);
        indices = sobol::metamodel_sobol(*fit.model, options);
        require_finite_indices(indices, inputs);
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
                  fmt::format("{}{} (metamodel {}, output '{}')", e.detail(), other, model_name, output));
      } catch (const sobol::InputError& e) {
        throw UserError(data.file, 0, fmt::format("output '{}': {}", output, e.what()));
      } catch (const sobol::NumericalError& e) {
        throw UserError(data.file, 0, fmt::format("output '{}': {}", output, e.what()));
      }
      if (args.json != "-") {
        fmt::print("{} ~ {}: R2 {:.4f}, adjusted R2 {:.4f}, Q2_LOO {:.4f} ({} samples)\n", output, model_name,
                   summary.r2, summary.adjusted_r2, summary.q2, summary.samples);
        print_indices(indices, inputs);
      }
      if (!args.save_model.empty()) {
        SavedModel saved{std::move(fit.model), inputs, bounds, output, ""};
        model_files.emplace_back(save_to_file ? save_path : save_path / model_file_name(output, model_name),
                                 model_to_json(saved));
      }
      models.push_back({{"metamodel", model_name},
                        {"quality", metamodel_summary_json(summary)},
                        {"sobol", sobol_result_json(indices, inputs)}});
      const double q2 = std::isfinite(summary.q2) ? summary.q2 : -1e300;
      if (noise && q2 > best_q2 && !indices.first.empty()) {
        best_q2 = q2;
        noise->largest_s1 = 0.0;
        for (const sobol::IndexEstimate& e : indices.first) noise->largest_s1 = std::max(noise->largest_s1, e.value);
      }
    }
    nlohmann::json result{{"output", output}, {"metamodels", models}};
    if (noise) {
      noise->dominates = noise_dominates(noise->share, noise->largest_s1);
      if (args.json != "-") fmt::print("{}\n", noise_text(*noise));
      const auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
      result["noise"] = {{"variance", number(noise->estimate.variance)},
                         {"lower", number(noise->estimate.lower)},
                         {"upper", number(noise->estimate.upper)},
                         {"confidence", noise->estimate.confidence},
                         {"points", noise->estimate.points},
                         {"values", noise->estimate.values},
                         {"dof", noise->estimate.dof},
                         {"share", number(noise->share)},
                         {"share_lower", number(noise->share_lower)},
                         {"share_upper", number(noise->share_upper)},
                         {"largest_s1", number(noise->largest_s1)},
                         {"dominates", noise->dominates},
                         {"nugget_share", number(noise->nugget_share)}};
    }
    results.push_back(result);
  }
  nlohmann::json bounds_json = nlohmann::json::array();
  for (std::size_t k = 0; k < inputs.size(); ++k)
    bounds_json.push_back({{"input", inputs[k]},
                           {"low", bounds[k].low},
                           {"high", bounds[k].high},
                           {"scale", sobol::to_string(bounds[k].scale)},
                           {"coverage", coverage[k]},
                           {"extrapolated", coverage[k] < k_min_coverage}});
  for (const auto& [file, text] : model_files) {
    write_file_atomically(file, text);
    if (args.json != "-") fmt::print("metamodel written to {}\n", file.string());
  }
  write_json(args.json, {{"data", args.data},
                         {"samples", data.rows()},
                         {"inputs", inputs},
                         {"bounds", bounds_json},
                         {"outputs", results}});
}

}  // namespace

void register_sensitivity_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<SensitivityArgs>();
  CLI::App* sub =
      app.add_subcommand("sensitivity", "Metamodels and Sobol' indices from a CSV of samples and responses");
  sub->add_option("--saltelli", args->saltelli, "Saltelli design written by `demsa design saltelli`");
  sub->add_option("--responses", args->responses, "CSV of outputs, one row per design row (with --saltelli)");
  sub->add_option("--data", args->data, "CSV of samples: input and output columns");
  sub->add_option("--inputs", args->inputs, "Input columns of --data, comma-separated");
  sub->add_option("--response", args->outputs,
                  "Response column(s), comma-separated: of --data, of --responses (default: all), or appended to the "
                  "--saltelli design (then without --responses)");
  add_deprecated_option(sub, "--output", "--response", args->outputs);
  sub->add_option("--bounds", args->bounds, "NAME=LOW:HIGH[:log],... bounds of inputs (default: the data's range)");
  sub->add_option("--metamodels", args->metamodels, "rsm1, rsm2, rsm3, rbf-cubic, rbf-tps, gp (comma-separated)")
      ->capture_default_str();
  sub->add_flag("--second-order", args->second_order, "Also compute second-order indices S2");
  sub->add_flag("--allow-extrapolation", args->allow_extrapolation,
                "--data: proceed (with a warning) when the samples span less than half of an input's --bounds");
  sub->add_option("--bootstrap", args->bootstrap,
                  "Bootstrap resamples: with --saltelli those of --interval bootstrap (given alone, it chooses that "
                  "interval; default 200), with --data the design refits of each metamodel (default 100)");
  sub->add_option("--interval", args->interval,
                  "With --saltelli: replicates (the default: Student-t over the design's independently scrambled "
                  "replicates, valid for QMC; none without them), bootstrap (a percentile bootstrap of its rows, "
                  "conservative for QMC: often several times too wide) or none");
  sub->add_option("--confidence", args->confidence, "Confidence level of the intervals")->capture_default_str();
  sub->add_option("--base", args->base, "QMC base sample size N for metamodel indices")->capture_default_str();
  sub->add_option("--seed", args->seed, "Seed of the QMC design and of the bootstrap")->capture_default_str();
  sub->add_option("--json", args->json, "Write the results as JSON to this file ('-': standard output only)");
  sub->add_option("--save-model", args->save_model,
                  "With --data: write each fitted metamodel as JSON (for `demsa predict`): a .json file for one "
                  "model, else a folder of <response>.<metamodel>.json");
  sub->add_option("--gp-kernel", args->gp_kernel, "Correlation of the gp metamodel: squared-exponential, matern52")
      ->capture_default_str();
  sub->add_option("--gp-trend", args->gp_trend, "Trend of the gp metamodel: constant, linear")->capture_default_str();
  sub->add_option("--replicates", args->replicates,
                  "With --data: CSV of repeated runs, a column 'point' labelling the runs of one input point and the "
                  "response columns (e.g. DIR/analysis/replicates.csv): measures each response's noise variance, "
                  "sets the gp nugget from it and prints its share of the response's variance");
  sub->add_flag("--gp-nugget", args->gp_nugget,
                "Estimate a nugget in the gp metamodel (noisy simulators such as DEM: it then smooths, not "
                "interpolates)");
  sub->callback([args, &state] {
    if (!args->saltelli.empty() == !args->data.empty())
      throw UserError("give exactly one of --saltelli DESIGN.csv (with --responses) or --data DATA.csv");
    if (!args->interval.empty() && !args->data.empty())
      throw UserError(
          "--interval goes with --saltelli: the intervals of --data are design-bootstrap refits of each metamodel "
          "(--bootstrap)");
    if (!args->replicates.empty() && args->data.empty())
      throw UserError("--replicates goes with --data: the noise sets the nugget of the metamodels fitted to the data");
    check_numeric_options(*args);
    StopFlag::install();
    try {
      if (!args->saltelli.empty())
        run_saltelli(*args);
      else
        run_data(*args);
    } catch (const sobol::Stopped&) {
      fmt::print(stderr, "demsa: sensitivity stopped by signal {}; nothing written\n", StopFlag::signal_number());
      state.exit_code = k_exit_signal_base + StopFlag::signal_number();
      return;
    }
    state.exit_code = k_exit_ok;
  });
}

}  // namespace demsa::cli
