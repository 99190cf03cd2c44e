#include "orchestrator/analysis/simulator_design.hpp"

#include "orchestrator/analysis/saltelli_design_file.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"
#include "sobol/error.hpp"

#include <fmt/core.h>

#include <bit>
#include <climits>
#include <cmath>
#include <filesystem>

namespace demsa::analysis {

using util::UserError;

namespace {

// Points of the Sobol' sequence at most (sobol_sequence's limit, 30 binary digits per coordinate).
constexpr int k_max_sobol_points = 1 << 30;
/// The most values (samples x dimension) of a point design: it is held in memory (and its CSV text): -n 200000000
/// --dim 2 took 10 GB.
constexpr long long k_max_design_values = 1LL << 26;

// The checks below name the options' fields, their value and the rule. They run before the sobol library's own
// validate(), whose messages name the fields of sobol::DesignOptions and sobol::SaltelliOptions.

/// How the dimension was given, for messages: "PointDesignOptions.dimension 41" or "41 parameters
/// (PointDesignOptions.parameters)".
std::string dimension_source(const std::string& options, const DesignParameters& p) {
  const auto dimension = p.names.size();
  return p.named ? fmt::format("{} parameters ({}.parameters)", dimension, options)
                 : fmt::format("{}.dimension {}", options, dimension);
}

/// The design's values are held in memory.
void check_design_values(const PointDesignOptions& o) {
  const long long dimension = static_cast<long long>(o.parameters.names.size());
  const long long values = static_cast<long long>(o.samples) * dimension;
  if (values > k_max_design_values)
    throw UserError(fmt::format(
        "PointDesignOptions.samples {}: {} samples x {} = {} values, more than 2^26 = {} (a design is held in memory)",
        o.samples, o.samples, dimension_source("PointDesignOptions", o.parameters), values, k_max_design_values));
}

void check_point_design(const PointDesignOptions& o) {
  const int dimension = static_cast<int>(o.parameters.names.size());
  if (o.kind == sobol::DesignKind::sobol) {
    if (o.samples < 1)
      throw UserError(
          fmt::format("PointDesignOptions.samples {}: the number of samples must be at least 1", o.samples));
    if (o.samples > k_max_sobol_points)
      throw UserError(fmt::format("PointDesignOptions.samples {}: the Sobol' sequence has at most 2^30 = {} points",
                                  o.samples, k_max_sobol_points));
    if (dimension > sobol::k_max_sobol_dimension)
      throw UserError(fmt::format("{}: the Sobol' sequence supports at most {} parameters",
                                  dimension_source("PointDesignOptions", o.parameters), sobol::k_max_sobol_dimension));
    check_design_values(o);
    return;
  }
  if (o.samples < 2)
    throw UserError(
        fmt::format("PointDesignOptions.samples {}: a Latin hypercube needs at least 2 samples", o.samples));
  if (!(o.time_limit > 0.0))
    throw UserError(fmt::format("PointDesignOptions.time_limit {}: the safety stop must be > 0 seconds", o.time_limit));
  if (o.iterations < 1)
    throw UserError(
        fmt::format("PointDesignOptions.iterations {}: the optimisation needs at least 1 iteration", o.iterations));
  if ((o.kind == sobol::DesignKind::lhs_maximin || o.kind == sobol::DesignKind::lhs_cl2) &&
      o.samples > sobol::k_max_optimised_lhs_samples)
    throw UserError(
        fmt::format("PointDesignOptions.samples {}: an optimised Latin hypercube keeps n x n tables of pairs; at most "
                    "{} samples (a plain or centred one has no limit)",
                    o.samples, sobol::k_max_optimised_lhs_samples));
  if (!(o.phi_p >= 1.0) || !std::isfinite(o.phi_p))
    throw UserError(fmt::format("PointDesignOptions.phi_p {}: p must be a finite number >= 1", o.phi_p));
  check_design_values(o);
}

/// A missing output folder is the user's error, found before any work: the atomic writer would report it as an I/O
/// error on its temporary file.
void check_output_folder(const std::string& options, const std::string& output) {
  const std::filesystem::path folder = std::filesystem::path(output).parent_path();
  std::error_code ec;
  if (!folder.empty() && !std::filesystem::is_directory(folder, ec))
    throw UserError(fmt::format("{}.output {}: the folder '{}' does not exist", options, output, folder.string()));
}

/// A scrambled Sobol' sequence keeps the balance of a (t,m,d)-net only over its first 2^m points (Owen 1997,
/// "Monte Carlo variance of scrambled net quadrature"); Saltelli et al. 2010 (Comput. Phys. Commun. 181, 259-270)
/// take N = 2^k for the same reason. Another size is allowed, with a warning.
void warn_unless_power_of_two(const PointDesignOptions& o) {
  const auto n = static_cast<unsigned>(o.samples);
  if (o.samples < 1 || std::has_single_bit(n)) return;
  const unsigned below = std::bit_floor(n);
  emit_warning(o.warn,
               fmt::format("PointDesignOptions.samples {} is not a power of two (nearest: {} and {}); a scrambled "
                           "Sobol' sequence is balanced only at powers of two (Owen 1997)",
                           o.samples, below, 2 * below));
}

void warn_without_pair_metrics(const WarningSink& sink, const sobol::DesignMetrics& m, Eigen::Index rows) {
  if (!m.phi_p)
    emit_warning(
        sink, fmt::format("phi_p and the centred L2 discrepancy are not computed for {} points (O(n^2) time; at most "
                          "{})",
                          rows, sobol::k_max_pair_metric_samples));
}

/// The pair metrics are absent above sobol::k_max_pair_metric_samples points (null in JSON).
nlohmann::json optional_json(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(); }

nlohmann::json metrics_json(const sobol::DesignMetrics& m) {
  return {{"min_distance", m.min_distance},
          {"phi_p", optional_json(m.phi_p)},
          {"phi_p_power", m.phi_p_power},
          {"centred_l2_discrepancy", optional_json(m.centred_l2)}};
}

/// The base sample size of a Saltelli design: N rounded up to the next power of two, with a warning naming both
/// values. Scrambled Sobol' points are balanced only over their first 2^m points (Owen 1997), and the Sobol' index
/// estimates lose accuracy in between (Ishigami, S1: mean error 3.6e-3 at N = 10,000 against 5.4e-4 at 8192);
/// Saltelli et al. 2010 take N = 2^k.
int saltelli_base(const SaltelliDesignFileOptions& o) {
  if (o.base < 2)
    throw UserError(fmt::format("SaltelliDesignFileOptions.base {}: the base sample size must be at least 2", o.base));
  if (o.base > sobol::k_max_base_samples)
    throw UserError(
        fmt::format("SaltelliDesignFileOptions.base {}: at most 2^20 = {} (the design holds N (2d + 2) rows in memory)",
                    o.base, sobol::k_max_base_samples));
  return balanced_base_samples(o.base, "SaltelliDesignFileOptions.base",
                               [&o](const std::string& message) { emit_warning(o.warn, message); });
}

void check_saltelli(const SaltelliDesignFileOptions& o, int base, int replicates) {
  const int dimension = static_cast<int>(o.parameters.names.size());
  if (dimension > sobol::k_max_saltelli_dimension)
    throw UserError(fmt::format(
        "{}: a Saltelli design supports at most {} parameters (A and B come from one {}-dimensional Sobol' sequence)",
        dimension_source("SaltelliDesignFileOptions", o.parameters), sobol::k_max_saltelli_dimension,
        2 * sobol::k_max_saltelli_dimension));
  if (replicates > 1 && (base % replicates != 0 || base / replicates < 2))
    throw UserError(
        fmt::format("SaltelliDesignFileOptions.replicates {}: must divide the base N = {} and leave at least 2 rows "
                    "to each replicate",
                    replicates, base));
  const long long blocks = o.second_order ? 2LL * dimension + 2 : dimension + 2LL;
  if (blocks * base > INT_MAX)
    throw UserError(
        fmt::format("SaltelliDesignFileOptions.base {}: the design would have {} x {} = {} rows, more than "
                    "{}",
                    base, base, blocks, blocks * base, INT_MAX));
}

}  // namespace

DesignParameters parse_design_parameters(const DesignParameterOptions& options) {
  DesignParameters p;
  if (!options.parameters.empty() && options.dimension)
    throw UserError(
        "give either DesignParameterOptions.dimension or DesignParameterOptions.parameters, not both "
        "(DesignParameterOptions.parameters fixes the dimension)");
  if (options.parameters.empty()) {
    if (!options.dimension)
      throw UserError(
          "give the dimension with DesignParameterOptions.dimension D or the parameters with "
          "DesignParameterOptions.parameters");
    const int dimension = *options.dimension;
    if (dimension < 1)
      throw UserError(fmt::format(
          "DesignParameterOptions.dimension {}: not a valid dimension, the number of parameters must be at least 1",
          dimension));
    for (int k = 0; k < dimension; ++k) p.names.push_back(fmt::format("x{}", k + 1));
    p.bounds.assign(static_cast<std::size_t>(dimension), sobol::Bounds{});
    return p;
  }
  for (const std::string& spec : options.parameters) {
    const std::vector<std::string> parts = util::split(spec, ':');
    if (parts.size() < 3 || parts.size() > 4 || parts[0].empty())
      throw UserError(
          fmt::format("DesignParameterOptions.parameters '{}': expected NAME:LOW:HIGH or NAME:LOW:HIGH:log", spec));
    const auto number = [&spec](const std::string& text, const char* what) {
      if (const std::optional<double> v = util::parse_number(text)) return *v;
      throw UserError(
          fmt::format("DesignParameterOptions.parameters '{}': {}: '{}' is not a number", spec, what, text));
    };
    sobol::Bounds b;
    b.low = number(parts[1], "low");
    b.high = number(parts[2], "high");
    if (parts.size() == 4) {
      try {
        b.scale = sobol::scale_from_string(parts[3]);
      } catch (const sobol::InputError& e) {
        throw UserError(fmt::format("DesignParameterOptions.parameters '{}': {}", spec, e.what()));
      }
    }
    for (const std::string& n : p.names)
      if (n == parts[0])
        throw UserError(fmt::format("DesignParameterOptions.parameters '{}': parameter '{}' given twice", spec, n));
    p.names.push_back(parts[0]);
    p.bounds.push_back(b);
  }
  try {
    sobol::validate_bounds(p.bounds, p.names);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("DesignParameterOptions.parameters: {}", e.what()));
  }
  p.named = true;
  return p;
}

sobol::DesignKind lhs_kind(const LhsKindOptions& options) {
  if (options.criterion.empty()) return options.centred ? sobol::DesignKind::lhs_centred : sobol::DesignKind::lhs;
  if (options.centred) throw UserError("LhsKindOptions.centred and LhsKindOptions.criterion cannot be combined");
  try {
    return sobol::lhs_criterion_from_string(options.criterion);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("LhsKindOptions.criterion: {}", e.what()));
  }
}

PointDesign write_point_design(const PointDesignOptions& o) {
  check_point_design(o);
  check_output_folder("PointDesignOptions", o.output);
  if (o.kind == sobol::DesignKind::sobol) warn_unless_power_of_two(o);
  sobol::DesignOptions options;
  options.kind = o.kind;
  options.samples = o.samples;
  options.dimension = static_cast<int>(o.parameters.names.size());
  options.seed = o.seed;
  options.time_limit = o.time_limit;
  options.iterations = o.iterations;
  options.phi_p_power = o.phi_p;
  PointDesign written{sobol::make_design(options), o.parameters.names, o.output};
  const sobol::DesignResult& r = written.design;
  if (r.stop == sobol::DesignStop::time_limit)
    emit_warning(o.warn,
                 fmt::format("PointDesignOptions.time_limit {}: the optimisation stopped at the safety time limit "
                             "after {} of at most {} iterations; this design depends on the machine's speed, not on "
                             "the seed alone (raise PointDesignOptions.time_limit or lower "
                             "PointDesignOptions.iterations)",
                             o.time_limit, r.iterations, o.iterations));
  warn_without_pair_metrics(o.warn, r.metrics, r.points.rows());
  const Eigen::MatrixXd values = o.parameters.named ? sobol::to_physical(r.points, o.parameters.bounds) : r.points;
  util::write_csv(o.output, o.parameters.names, values);
  return written;
}

nlohmann::json point_design_json(const PointDesign& written) {
  const sobol::DesignResult& r = written.design;
  return {{"design", sobol::to_string(r.kind)}, {"file", written.output},           {"samples", r.points.rows()},
          {"dimension", r.points.cols()},       {"parameters", written.names},      {"seed", r.seed},
          {"iterations", r.iterations},         {"stop", sobol::to_string(r.stop)}, {"seconds", r.seconds},
          {"metrics", metrics_json(r.metrics)}};
}

SaltelliDesignWritten write_simulator_saltelli_design(const SaltelliDesignFileOptions& o) {
  const int base = saltelli_base(o);
  // Replicates by default: `demsa sensitivity` takes its intervals from their spread (sobol/saltelli.hpp).
  const int replicates = o.replicates == 0 ? sobol::default_saltelli_replicates(base) : o.replicates;
  check_saltelli(o, base, replicates);
  check_output_folder("SaltelliDesignFileOptions", o.output);
  sobol::SaltelliOptions options;
  options.base = base;
  options.dimension = static_cast<int>(o.parameters.names.size());
  options.second_order = o.second_order;
  options.seed = o.seed;
  options.replicates = replicates;
  SaltelliDesignWritten written{sobol::saltelli_design(options), o.parameters.names, o.output, std::nullopt};
  const sobol::SaltelliDesign& d = written.design;
  Eigen::MatrixXd values = d.stacked();
  if (o.parameters.named) values = sobol::to_physical(values, o.parameters.bounds);
  write_saltelli_design(o.output, d, values, o.parameters.names);
  if (o.metrics) {
    written.metrics_of_a = sobol::design_metrics(d.a);
    warn_without_pair_metrics(o.warn, *written.metrics_of_a, d.a.rows());
  }
  return written;
}

nlohmann::json saltelli_design_written_json(const SaltelliDesignWritten& written) {
  const sobol::SaltelliDesign& d = written.design;
  nlohmann::json j = {{"design", "saltelli"},
                      {"file", written.output},
                      {"base", d.base},
                      {"dimension", d.dimension},
                      {"second_order", d.second_order},
                      {"rows", d.rows()},
                      {"parameters", written.names},
                      {"seed", d.seed},
                      {"replicates", d.replicates}};
  if (written.metrics_of_a) j["metrics_of_a"] = metrics_json(*written.metrics_of_a);
  return j;
}

std::string point_design_text(const PointDesign& written) {
  const sobol::DesignResult& r = written.design;
  std::string text = fmt::format("{} design: {} samples x {} parameters (seed {}) written to {}\n",
                                 sobol::to_string(r.kind), r.points.rows(), r.points.cols(), r.seed, written.output);
  if (r.iterations > 0)
    text += fmt::format("optimised in {} iterations (stop: {}), {:.2f} s\n", r.iterations, sobol::to_string(r.stop),
                        r.seconds);
  if (r.metrics.phi_p && r.metrics.centred_l2)
    text += fmt::format("minimum distance {:.4f}, phi_{:g} {:.4f}, centred L2 discrepancy {:.5f} (on the unit cube)\n",
                        r.metrics.min_distance, r.metrics.phi_p_power, *r.metrics.phi_p, *r.metrics.centred_l2);
  else
    text += fmt::format("minimum distance {:.4f} (on the unit cube)\n", r.metrics.min_distance);
  return text;
}

std::string saltelli_design_written_text(const SaltelliDesignWritten& written) {
  const sobol::SaltelliDesign& d = written.design;
  std::string text =
      fmt::format("saltelli design: base {} x {} parameters{}, {} rows (seed {}) written to {}\n", d.base, d.dimension,
                  d.second_order ? " with second order" : "", d.rows(), d.seed, written.output);
  if (d.replicates > 1)
    text += fmt::format(
        "{} independently scrambled replicates of {} base rows (column 'replicate'): `demsa sensitivity` "
        "gives Student-t intervals from their spread\n",
        d.replicates, d.base / d.replicates);
  else
    text +=
        "one scrambled design (no replicates): `demsa sensitivity` gives its indices without intervals, or "
        "with bootstrap ones by --interval bootstrap (conservative for QMC)\n";
  text += fmt::format("column 'block': 0 = A, 1 = B, 1+i = AB_i, 1+{}+i = BA_i; evaluate every row, keep the order\n",
                      d.dimension);
  return text;
}

}  // namespace demsa::analysis
