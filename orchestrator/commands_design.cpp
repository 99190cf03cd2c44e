// `demsa design lhs|sobol|saltelli`: a design of experiments as CSV, for any simulator (DESIGN.md §3). Values are
// on the unit cube unless parameters with bounds are given (--param NAME:LOW:HIGH[:log]); the space-filling
// metrics (on the unit cube) go to standard output, as JSON with --json.
#include "orchestrator/commands.hpp"
#include "orchestrator/csv.hpp"
#include "orchestrator/errors.hpp"
#include "sobol/design.hpp"
#include "sobol/error.hpp"
#include "sobol/saltelli.hpp"
#include "sobol/scaling.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace demsa {

namespace {

struct DesignArgs {
  int samples = 0;
  int dimension = 0;
  std::vector<std::string> params;  ///< NAME:LOW:HIGH[:log]
  std::uint64_t seed = 12345;
  std::string output;
  bool json = false;
  // lhs
  std::string criterion;  ///< "", maximin, cl2
  bool centred = false;
  double time_limit = 5.0;
  int iterations = 1000000;
  double phi_p = 50.0;
  // saltelli
  bool second_order = false;
};

struct Parameters {
  std::vector<std::string> names;
  std::vector<sobol::Bounds> bounds;
  bool scaled = false;
};

double parse_number(const std::string& text, const std::string& what) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || *end != '\0')
    throw UserError(fmt::format("{}: '{}' is not a number", what, text));
  return v;
}

/// --param NAME:LOW:HIGH[:log|uniform] (repeatable) or --dim D (names x1..xD on the unit cube).
Parameters parse_parameters(const DesignArgs& args) {
  Parameters p;
  if (!args.params.empty() && args.dimension > 0)
    throw UserError("give either --dim or --param, not both (--param fixes the dimension)");
  if (args.params.empty()) {
    if (args.dimension < 1) throw UserError("give the dimension with --dim D or the parameters with --param");
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

nlohmann::json metrics_json(const sobol::DesignMetrics& m) {
  return {{"min_distance", m.min_distance},
          {"phi_p", m.phi_p},
          {"phi_p_power", m.phi_p_power},
          {"centred_l2_discrepancy", m.centred_l2}};
}

void run_point_design(const DesignArgs& args, sobol::DesignKind kind) {
  const Parameters p = parse_parameters(args);
  sobol::DesignOptions options;
  options.kind = kind;
  options.samples = args.samples;
  options.dimension = static_cast<int>(p.names.size());
  options.seed = args.seed;
  options.time_limit = args.time_limit;
  options.iterations = args.iterations;
  options.phi_p_power = args.phi_p;
  sobol::DesignResult r;
  try {
    r = sobol::make_design(options);
  } catch (const sobol::InputError& e) {
    throw UserError(e.what());
  }
  const Eigen::MatrixXd values = p.scaled ? sobol::to_physical(r.points, p.bounds) : r.points;
  write_csv(args.output, p.names, values);
  if (args.json) {
    const nlohmann::json j = {
        {"design", sobol::to_string(r.kind)}, {"file", args.output},   {"samples", r.points.rows()},
        {"dimension", r.points.cols()},       {"parameters", p.names}, {"seed", r.seed},
        {"iterations", r.iterations},         {"seconds", r.seconds},  {"metrics", metrics_json(r.metrics)}};
    fmt::print("{}\n", j.dump(2));
  } else {
    fmt::print("{} design: {} samples x {} parameters (seed {}) written to {}\n", sobol::to_string(r.kind),
               r.points.rows(), r.points.cols(), r.seed, args.output);
    if (r.iterations > 0) fmt::print("optimised in {} iterations, {:.2f} s\n", r.iterations, r.seconds);
    fmt::print("minimum distance {:.4f}, phi_{:g} {:.4f}, centred L2 discrepancy {:.5f} (on the unit cube)\n",
               r.metrics.min_distance, r.metrics.phi_p_power, r.metrics.phi_p, r.metrics.centred_l2);
  }
}

void run_saltelli(const DesignArgs& args) {
  const Parameters p = parse_parameters(args);
  sobol::SaltelliOptions options;
  options.base = args.samples;
  options.dimension = static_cast<int>(p.names.size());
  options.second_order = args.second_order;
  options.seed = args.seed;
  sobol::SaltelliDesign d;
  try {
    d = sobol::saltelli_design(options);
  } catch (const sobol::InputError& e) {
    throw UserError(e.what());
  }
  const Eigen::MatrixXd unit = d.stacked();
  const Eigen::MatrixXd values = p.scaled ? sobol::to_physical(unit, p.bounds) : unit;
  const std::vector<int> codes = d.block_codes();
  Eigen::MatrixXd table(values.rows(), values.cols() + 1);
  for (Eigen::Index r = 0; r < values.rows(); ++r) table(r, 0) = codes[static_cast<std::size_t>(r)];
  table.rightCols(values.cols()) = values;
  std::vector<std::string> header{"block"};
  header.insert(header.end(), p.names.begin(), p.names.end());
  write_csv(args.output, header, table);
  const sobol::DesignMetrics m = sobol::design_metrics(d.a);
  if (args.json) {
    const nlohmann::json j = {
        {"design", "saltelli"},           {"file", args.output}, {"base", d.base},        {"dimension", d.dimension},
        {"second_order", d.second_order}, {"rows", d.rows()},    {"parameters", p.names}, {"seed", d.seed},
        {"metrics_of_a", metrics_json(m)}};
    fmt::print("{}\n", j.dump(2));
  } else {
    fmt::print("saltelli design: base {} x {} parameters{}, {} rows (seed {}) written to {}\n", d.base, d.dimension,
               d.second_order ? " with second order" : "", d.rows(), d.seed, args.output);
    fmt::print("column 'block': 0 = A, 1 = B, 1+i = AB_i, 1+{}+i = BA_i; evaluate every row, keep the order\n",
               d.dimension);
  }
}

void add_common(CLI::App* sub, DesignArgs& args, const std::string& samples_name, const std::string& samples_help) {
  sub->add_option(samples_name, args.samples, samples_help)->required();
  sub->add_option("--dim", args.dimension, "Number of parameters (names x1..xD, unit cube)");
  sub->add_option("--param", args.params, "Parameter NAME:LOW:HIGH[:log] (repeat for each parameter)");
  sub->add_option("--seed", args.seed, "Seed of every random choice")->capture_default_str();
  sub->add_option("-o,--output", args.output, "CSV file to write (header row, one row per sample)")->required();
  sub->add_flag("--json", args.json, "Print the design's description and metrics as JSON");
}

}  // namespace

void register_design_command(CLI::App& app, CliState& state) {
  CLI::App* design = app.add_subcommand("design", "Write a design (lhs, sobol, saltelli) as CSV, for any simulator");
  design->require_subcommand(1);
  auto args = std::make_shared<DesignArgs>();

  CLI::App* lhs = design->add_subcommand("lhs", "Latin hypercube: plain, centred, or optimised (maximin, cl2)");
  add_common(lhs, *args, "-n,--samples", "Number of samples");
  lhs->add_option("--criterion", args->criterion, "Optimise for: maximin (phi_p) or cl2 (centred L2 discrepancy)");
  lhs->add_flag("--centred", args->centred, "Put every point at the centre of its stratum");
  lhs->add_option("--time-limit", args->time_limit, "Optimisation budget [s]")->capture_default_str();
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

  CLI::App* sobol_cmd = design->add_subcommand("sobol", "Scrambled Sobol' sequence (first point at the origin)");
  add_common(sobol_cmd, *args, "-n,--samples", "Number of samples (a power of two balances best)");
  sobol_cmd->callback([args, &state] {
    run_point_design(*args, sobol::DesignKind::sobol);
    state.exit_code = k_exit_ok;
  });

  CLI::App* saltelli = design->add_subcommand(
      "saltelli", "Saltelli design for Sobol' indices: blocks A, B, AB_i (and BA_i), column 'block' names them");
  add_common(saltelli, *args, "-N,--base", "Base sample size N (rows of A and of B; a power of two)");
  saltelli->add_flag("--second-order", args->second_order, "Add the BA_i blocks needed for second-order indices");
  saltelli->callback([args, &state] {
    run_saltelli(*args);
    state.exit_code = k_exit_ok;
  });
}

}  // namespace demsa
