// `demsa design lhs|sobol|saltelli`: a design of experiments as CSV, for any simulator
// (docs/reference/command-line.md). Values are on the unit cube unless parameters with bounds are given (--param
// NAME:LOW:HIGH[:log]); the space-filling metrics (on the unit cube) go to standard output, as JSON with --json (for
// saltelli: only with --json). A Saltelli design comes in independently scrambled replicates by default
// (sobol::default_saltelli_replicates), from whose spread `demsa sensitivity` takes its intervals.
#include "sobol/design.hpp"
#include "orchestrator/analysis/saltelli_design_file.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "orchestrator/util/text.hpp"
#include "sobol/error.hpp"
#include "sobol/saltelli.hpp"
#include "sobol/scaling.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace demsa::cli {

using namespace demsa::util;

namespace {

struct DesignArgs {
  int samples = 0;
  int dimension = 0;
  bool dimension_given = false;     ///< --dim was on the command line (with any value)
  std::vector<std::string> params;  ///< NAME:LOW:HIGH[:log]
  std::uint64_t seed = 12345;
  std::string output;
  bool json = false;
  // lhs
  std::string criterion;  ///< "", maximin, cl2
  bool centred = false;
  double time_limit = 60.0;                            ///< safety stop [s]; warns when it ends the search
  int iterations = sobol::DesignOptions{}.iterations;  ///< outer iterations at most
  double phi_p = 50.0;
  // saltelli
  bool second_order = false;
  /// Independently scrambled replicates (column 'replicate' when > 1); 0: sobol::default_saltelli_replicates(N).
  int replicates = 0;
};

// Points of the Sobol' sequence at most (sobol_sequence's limit, 30 binary digits per coordinate).
constexpr int k_max_sobol_points = 1 << 30;
/// The most values (samples x dimension) of a design `demsa design lhs|sobol` writes.
constexpr long long k_max_design_values = 1LL << 26;

struct Parameters {
  std::vector<std::string> names;
  std::vector<sobol::Bounds> bounds;
  bool scaled = false;
};

double parse_number(const std::string& text, const std::string& what) {
  if (const std::optional<double> v = util::parse_number(text)) return *v;
  throw UserError(fmt::format("{}: '{}' is not a number", what, text));
}

/// --param NAME:LOW:HIGH[:log|uniform] (repeatable) or --dim D (names x1..xD on the unit cube).
Parameters parse_parameters(const DesignArgs& args) {
  Parameters p;
  if (!args.params.empty() && args.dimension_given)
    throw UserError("give either --dim or --param, not both (--param fixes the dimension)");
  if (args.params.empty()) {
    if (!args.dimension_given) throw UserError("give the dimension with --dim D or the parameters with --param");
    if (args.dimension < 1)
      throw UserError(
          fmt::format("--dim {}: not a valid dimension, the number of parameters must be at least 1", args.dimension));
    for (int k = 0; k < args.dimension; ++k) p.names.push_back(fmt::format("x{}", k + 1));
    p.bounds.assign(static_cast<std::size_t>(args.dimension), sobol::Bounds{});
    return p;
  }
  for (const std::string& spec : args.params) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t colon = spec.find(':');; colon = spec.find(':', start)) {
      parts.push_back(spec.substr(start, colon == std::string::npos ? std::string::npos : colon - start));
      if (colon == std::string::npos) break;
      start = colon + 1;
    }
    if (parts.size() < 3 || parts.size() > 4 || parts[0].empty())
      throw UserError(fmt::format("--param '{}': expected NAME:LOW:HIGH or NAME:LOW:HIGH:log", spec));
    sobol::Bounds b;
    b.low = parse_number(parts[1], fmt::format("--param '{}': low", spec));
    b.high = parse_number(parts[2], fmt::format("--param '{}': high", spec));
    if (parts.size() == 4) {
      try {
        b.scale = sobol::scale_from_string(parts[3]);
      } catch (const sobol::InputError& e) {
        throw UserError(fmt::format("--param '{}': {}", spec, e.what()));
      }
    }
    for (const std::string& n : p.names)
      if (n == parts[0]) throw UserError(fmt::format("--param '{}': parameter '{}' given twice", spec, n));
    p.names.push_back(parts[0]);
    p.bounds.push_back(b);
  }
  try {
    sobol::validate_bounds(p.bounds, p.names);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("--param: {}", e.what()));
  }
  p.scaled = true;
  return p;
}

// The checks below name the command-line option, its value and the rule. They run before the library's own
// validate(), whose messages name the fields of sobol::DesignOptions and sobol::SaltelliOptions, which a command-line
// user never sees; the library keeps its checks for its other callers. CLI11 does not tell which spelling of an
// option was typed, so the sample size is named "-n" (for -n/--samples) and "--base" (for -N/--base).

/// How the dimension was given, for messages: "--dim 41" or "41 parameters (--param)".
std::string dimension_source(const DesignArgs& args, int dimension) {
  return args.params.empty() ? fmt::format("--dim {}", dimension) : fmt::format("{} parameters (--param)", dimension);
}

void check_sobol_samples(const std::string& option, int samples) {
  if (samples > k_max_sobol_points)
    throw UserError(
        fmt::format("{} {}: the Sobol' sequence has at most 2^30 = {} points", option, samples, k_max_sobol_points));
}

/// A scrambled Sobol' sequence keeps the balance of a (t,m,d)-net only over its first 2^m points (Owen 1997,
/// "Monte Carlo variance of scrambled net quadrature"); Saltelli et al. 2010 (Comput. Phys. Commun. 181, 259-270)
/// take N = 2^k for the same reason. Another size is allowed, with a warning on standard error (standard output may
/// carry the JSON).
void warn_unless_power_of_two(const std::string& option, int samples, const std::string& why) {
  const auto n = static_cast<unsigned>(samples);
  if (samples < 1 || std::has_single_bit(n)) return;
  const unsigned below = std::bit_floor(n);
  log::warn("{} {} is not a power of two (nearest: {} and {}); {}", option, samples, below, 2 * below, why);
}

/// The design is held in memory (and its CSV text): -n 200000000 --dim 2 took 10 GB.
void check_design_values(const DesignArgs& args, int dimension) {
  const long long values = static_cast<long long>(args.samples) * dimension;
  if (values > k_max_design_values)
    throw UserError(fmt::format("-n {}: {} samples x {} = {} values, more than 2^26 = {} (a design is held in memory)",
                                args.samples, args.samples, dimension_source(args, dimension), values,
                                k_max_design_values));
}

void check_point_design(const DesignArgs& args, sobol::DesignKind kind, int dimension) {
  if (kind == sobol::DesignKind::sobol) {
    if (args.samples < 1) throw UserError(fmt::format("-n {}: the number of samples must be at least 1", args.samples));
    check_sobol_samples("-n", args.samples);
    if (dimension > sobol::k_max_sobol_dimension)
      throw UserError(fmt::format("{}: the Sobol' sequence supports at most {} parameters",
                                  dimension_source(args, dimension), sobol::k_max_sobol_dimension));
    check_design_values(args, dimension);
    return;
  }
  if (args.samples < 2) throw UserError(fmt::format("-n {}: a Latin hypercube needs at least 2 samples", args.samples));
  if (!(args.time_limit > 0.0))
    throw UserError(fmt::format("--time-limit {}: the safety stop must be > 0 seconds", args.time_limit));
  if (args.iterations < 1)
    throw UserError(fmt::format("--iterations {}: the optimisation needs at least 1 iteration", args.iterations));
  if ((kind == sobol::DesignKind::lhs_maximin || kind == sobol::DesignKind::lhs_cl2) &&
      args.samples > sobol::k_max_optimised_lhs_samples)
    throw UserError(
        fmt::format("-n {}: an optimised Latin hypercube keeps n x n tables of pairs; at most {} samples "
                    "(a plain or centred one has no limit)",
                    args.samples, sobol::k_max_optimised_lhs_samples));
  if (!(args.phi_p >= 1.0) || !std::isfinite(args.phi_p))
    throw UserError(fmt::format("--phi-p {}: p must be a finite number >= 1", args.phi_p));
  check_design_values(args, dimension);
}

/// The base sample size of a Saltelli design: N rounded up to the next power of two, with a warning naming both
/// values. Scrambled Sobol' points are balanced only over their first 2^m points (Owen 1997), and the Sobol' index
/// estimates lose accuracy in between (Ishigami, S1: mean error 3.6e-3 at N = 10,000 against 5.4e-4 at 8192);
/// Saltelli et al. 2010 take N = 2^k.
int saltelli_base(int samples) {
  if (samples < 2) throw UserError(fmt::format("--base {}: the base sample size must be at least 2", samples));
  if (samples > sobol::k_max_base_samples)
    throw UserError(fmt::format("--base {}: at most 2^20 = {} (the design holds N (2d + 2) rows in memory)", samples,
                                sobol::k_max_base_samples));
  const unsigned rounded = std::bit_ceil(static_cast<unsigned>(samples));
  if (rounded == static_cast<unsigned>(samples)) return samples;
  log::warn(
      "--base {} is not a power of two: rounded up to {} (a scrambled Sobol' sequence is balanced only at "
      "powers of two; Saltelli 2010 takes N = 2^k)",
      samples, rounded);
  return static_cast<int>(rounded);
}

void check_saltelli(const DesignArgs& args, int dimension) {
  if (dimension > sobol::k_max_saltelli_dimension)
    throw UserError(fmt::format(
        "{}: a Saltelli design supports at most {} parameters (A and B come from one {}-dimensional Sobol' sequence)",
        dimension_source(args, dimension), sobol::k_max_saltelli_dimension, 2 * sobol::k_max_saltelli_dimension));
  if (args.replicates > 1 && (args.samples % args.replicates != 0 || args.samples / args.replicates < 2))
    throw UserError(
        fmt::format("--replicates {}: must divide the base N = {} and leave at least 2 rows to each "
                    "replicate",
                    args.replicates, args.samples));
  const long long blocks = args.second_order ? 2LL * dimension + 2 : dimension + 2LL;
  if (blocks * args.samples > INT_MAX)
    throw UserError(fmt::format("--base {}: the design would have {} x {} = {} rows, more than {}", args.samples,
                                args.samples, blocks, blocks * args.samples, INT_MAX));
}

/// A missing output folder is the user's error (exit 2), found before any work: the atomic writer would report it
/// as an I/O error (exit 3) on its temporary file.
void check_output_folder(const std::string& output) {
  if (output.empty()) throw UserError("-o/--out FILE is required: the CSV file to write");
  const std::filesystem::path folder = std::filesystem::path(output).parent_path();
  std::error_code ec;
  if (!folder.empty() && !std::filesystem::is_directory(folder, ec))
    throw UserError(fmt::format("-o {}: the folder '{}' does not exist", output, folder.string()));
}

/// The pair metrics are absent above sobol::k_max_pair_metric_samples points (null in JSON).
nlohmann::json optional_json(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(); }

nlohmann::json metrics_json(const sobol::DesignMetrics& m) {
  return {{"min_distance", m.min_distance},
          {"phi_p", optional_json(m.phi_p)},
          {"phi_p_power", m.phi_p_power},
          {"centred_l2_discrepancy", optional_json(m.centred_l2)}};
}

void warn_without_pair_metrics(const sobol::DesignMetrics& m, Eigen::Index rows) {
  if (!m.phi_p)
    log::warn("phi_p and the centred L2 discrepancy are not computed for {} points (O(n^2) time; at most {})", rows,
              sobol::k_max_pair_metric_samples);
}

void run_point_design(const DesignArgs& args, sobol::DesignKind kind) {
  const Parameters p = parse_parameters(args);
  check_point_design(args, kind, static_cast<int>(p.names.size()));
  check_output_folder(args.output);
  if (kind == sobol::DesignKind::sobol)
    warn_unless_power_of_two("-n", args.samples,
                             "a scrambled Sobol' sequence is balanced only at powers of two (Owen 1997)");
  sobol::DesignOptions options;
  options.kind = kind;
  options.samples = args.samples;
  options.dimension = static_cast<int>(p.names.size());
  options.seed = args.seed;
  options.time_limit = args.time_limit;
  options.iterations = args.iterations;
  options.phi_p_power = args.phi_p;
  const sobol::DesignResult r = sobol::make_design(options);
  if (r.stop == sobol::DesignStop::time_limit)
    log::warn(
        "--time-limit {}: the optimisation stopped at the safety time limit after {} of at most {} iterations; "
        "this design depends on the machine's speed, not on the seed alone (raise --time-limit or lower "
        "--iterations)",
        args.time_limit, r.iterations, args.iterations);
  warn_without_pair_metrics(r.metrics, r.points.rows());
  const Eigen::MatrixXd values = p.scaled ? sobol::to_physical(r.points, p.bounds) : r.points;
  write_csv(args.output, p.names, values);
  if (args.json) {
    const nlohmann::json j = {{"design", sobol::to_string(r.kind)},
                              {"file", args.output},
                              {"samples", r.points.rows()},
                              {"dimension", r.points.cols()},
                              {"parameters", p.names},
                              {"seed", r.seed},
                              {"iterations", r.iterations},
                              {"stop", sobol::to_string(r.stop)},
                              {"seconds", r.seconds},
                              {"metrics", metrics_json(r.metrics)}};
    fmt::print("{}\n", j.dump(2));
  } else {
    fmt::print("{} design: {} samples x {} parameters (seed {}) written to {}\n", sobol::to_string(r.kind),
               r.points.rows(), r.points.cols(), r.seed, args.output);
    if (r.iterations > 0)
      fmt::print("optimised in {} iterations (stop: {}), {:.2f} s\n", r.iterations, sobol::to_string(r.stop),
                 r.seconds);
    if (r.metrics.phi_p && r.metrics.centred_l2)
      fmt::print("minimum distance {:.4f}, phi_{:g} {:.4f}, centred L2 discrepancy {:.5f} (on the unit cube)\n",
                 r.metrics.min_distance, r.metrics.phi_p_power, *r.metrics.phi_p, *r.metrics.centred_l2);
    else
      fmt::print("minimum distance {:.4f} (on the unit cube)\n", r.metrics.min_distance);
  }
}

void run_saltelli(const DesignArgs& given) {
  const Parameters p = parse_parameters(given);
  DesignArgs args = given;
  args.samples = saltelli_base(given.samples);
  // Replicates by default: `demsa sensitivity` takes its intervals from their spread (sobol/saltelli.hpp).
  if (args.replicates == 0) args.replicates = sobol::default_saltelli_replicates(args.samples);
  check_saltelli(args, static_cast<int>(p.names.size()));
  check_output_folder(args.output);
  sobol::SaltelliOptions options;
  options.base = args.samples;
  options.dimension = static_cast<int>(p.names.size());
  options.second_order = args.second_order;
  options.seed = args.seed;
  options.replicates = args.replicates;
  const sobol::SaltelliDesign d = sobol::saltelli_design(options);
  Eigen::MatrixXd values = d.stacked();
  if (p.scaled) values = sobol::to_physical(values, p.bounds);
  analysis::write_saltelli_design(args.output, d, values, p.names);
  if (args.json) {
    // Only on request: the pair metrics take O(N^2) time (computed up to sobol::k_max_pair_metric_samples).
    const sobol::DesignMetrics m = sobol::design_metrics(d.a);
    warn_without_pair_metrics(m, d.a.rows());
    const nlohmann::json j = {{"design", "saltelli"},
                              {"file", args.output},
                              {"base", d.base},
                              {"dimension", d.dimension},
                              {"second_order", d.second_order},
                              {"rows", d.rows()},
                              {"parameters", p.names},
                              {"seed", d.seed},
                              {"replicates", d.replicates},
                              {"metrics_of_a", metrics_json(m)}};
    fmt::print("{}\n", j.dump(2));
  } else {
    fmt::print("saltelli design: base {} x {} parameters{}, {} rows (seed {}) written to {}\n", d.base, d.dimension,
               d.second_order ? " with second order" : "", d.rows(), d.seed, args.output);
    if (d.replicates > 1)
      fmt::print(
          "{} independently scrambled replicates of {} base rows (column 'replicate'): `demsa sensitivity` "
          "gives Student-t intervals from their spread\n",
          d.replicates, d.base / d.replicates);
    else
      fmt::print(
          "one scrambled design (no replicates): `demsa sensitivity` gives its indices without intervals, or "
          "with bootstrap ones by --interval bootstrap (conservative for QMC)\n");
    fmt::print("column 'block': 0 = A, 1 = B, 1+i = AB_i, 1+{}+i = BA_i; evaluate every row, keep the order\n",
               d.dimension);
  }
}

void add_common(CLI::App* sub, DesignArgs& args, const std::string& samples_name, const std::string& samples_help) {
  sub->add_option(samples_name, args.samples, samples_help)->required();
  sub->add_option("--dim", args.dimension, "Number of parameters (names x1..xD, unit cube)")
      ->each([&args](const std::string&) { args.dimension_given = true; });
  sub->add_option("--param", args.params, "Parameter NAME:LOW:HIGH[:log] (repeat for each parameter)");
  sub->add_option("--seed", args.seed, "Seed of every random choice")->capture_default_str();
  sub->add_option("-o,--out", args.output, "CSV file to write (header row, one row per sample); required");
  add_deprecated_option(sub, "--output", "-o/--out", args.output);
  sub->add_flag("--json", args.json, "Print the design's description and metrics as JSON");
}

}  // namespace

void register_design_command(CLI::App& app, CliState& state) {
  CLI::App* design = app.add_subcommand("design", "Write a design (lhs, sobol, saltelli) as CSV, for any simulator");
  // At most one kind; none (or an unknown word) is reported by the check below, which lists the kinds, rather than by
  // CLI11's "A subcommand is required". It runs once `design` is parsed, before CLI11 rejects the unknown word.
  design->require_subcommand(0, 1);
  design->parse_complete_callback([design] {
    if (!design->get_subcommands().empty()) return;
    const std::vector<std::string> words = design->remaining();
    if (!words.empty() && !words[0].empty() && words[0][0] != '-')
      throw UserError(fmt::format("unknown design '{}' (valid: lhs, sobol, saltelli)", words[0]));
    throw UserError("give the kind of design: demsa design lhs|sobol|saltelli ... (see demsa design --help)");
  });
  auto args = std::make_shared<DesignArgs>();

  CLI::App* lhs = design->add_subcommand("lhs", "Latin hypercube: plain, centred, or optimised (maximin, cl2)");
  add_common(lhs, *args, "-n,--samples", "Number of samples");
  lhs->add_option("--criterion", args->criterion, "Optimise for: maximin (phi_p) or cl2 (centred L2 discrepancy)");
  lhs->add_flag("--centred", args->centred, "Put every point at the centre of its stratum");
  lhs->add_option("--iterations", args->iterations,
                  "Optimisation budget: outer iterations at most (the search also stops once it gains less than "
                  "0.1% over 25 of them); the seed alone fixes the design")
      ->capture_default_str();
  lhs->add_option("--time-limit", args->time_limit,
                  "Safety stop [s]: when it ends the optimisation a warning says so, and the design then depends on "
                  "the machine's speed")
      ->capture_default_str();
  lhs->add_option("--phi-p", args->phi_p, "p of the phi_p criterion")->capture_default_str();
  lhs->callback([args, &state] {
    sobol::DesignKind kind = args->centred ? sobol::DesignKind::lhs_centred : sobol::DesignKind::lhs;
    if (!args->criterion.empty()) {
      if (args->centred) throw UserError("--centred and --criterion cannot be combined");
      try {
        kind = sobol::lhs_criterion_from_string(args->criterion);
      } catch (const sobol::InputError& e) {
        throw UserError(fmt::format("--criterion: {}", e.what()));
      }
    }
    run_point_design(*args, kind);
    state.exit_code = k_exit_ok;
  });

  CLI::App* sobol_cmd = design->add_subcommand(
      "sobol", "Scrambled Sobol' sequence (random linear matrix scrambling and digital shift, Matousek 1998)");
  add_common(sobol_cmd, *args, "-n,--samples", "Number of samples (a power of two balances best)");
  sobol_cmd->callback([args, &state] {
    run_point_design(*args, sobol::DesignKind::sobol);
    state.exit_code = k_exit_ok;
  });

  CLI::App* saltelli = design->add_subcommand(
      "saltelli", "Saltelli design for Sobol' indices: blocks A, B, AB_i (and BA_i), column 'block' names them");
  add_common(saltelli, *args, "-N,--base",
             "Base sample size N (rows of A and of B); another value than a power of two is rounded up to the next "
             "one, with a warning");
  saltelli->add_flag("--second-order", args->second_order, "Add the BA_i blocks needed for second-order indices");
  saltelli
      ->add_option(
          "--replicates", args->replicates,
          fmt::format("Split N into R independently scrambled designs (column 'replicate'), from whose "
                      "spread `demsa sensitivity` gives Student-t intervals valid for QMC (default {}, fewer "
                      "below N = {} so that each keeps {} rows; 1: one design, whose intervals only a "
                      "bootstrap gives, conservative for QMC)",
                      sobol::k_default_saltelli_replicates,
                      sobol::k_default_saltelli_replicates * sobol::k_min_replicate_base, sobol::k_min_replicate_base))
      ->check(positive_number());
  saltelli->callback([args, &state] {
    run_saltelli(*args);
    state.exit_code = k_exit_ok;
  });
}

}  // namespace demsa::cli
