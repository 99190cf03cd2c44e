// `demsa design lhs|sobol|saltelli`: a design of experiments as CSV, for any simulator
// (docs/reference/command-line.md). Values are on the unit cube unless parameters with bounds are given (--param
// NAME:LOW:HIGH[:log]); the space-filling metrics (on the unit cube) go to standard output, as JSON with --json (for
// saltelli: only with --json). A Saltelli design comes in independently scrambled replicates by default
// (sobol::default_saltelli_replicates), from whose spread `demsa sensitivity` takes its intervals.
#include "sobol/design.hpp"
#include "orchestrator/analysis/simulator_design.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "sobol/saltelli.hpp"

#include <fmt/core.h>

#include <cstdint>
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

/// The option of each field of analysis::PointDesignOptions, SaltelliDesignFileOptions, DesignParameterOptions and
/// LhsKindOptions. CLI11 does not tell which
/// spelling of an option was typed, so the sample size is named "-n" (for -n/--samples) and "--base" (for -N/--base).
const OptionNames k_option_names{{"samples", "-n"},
                                 {"base", "--base"},
                                 {"dimension", "--dim"},
                                 {"parameters", "--param"},
                                 {"time_limit", "--time-limit"},
                                 {"iterations", "--iterations"},
                                 {"phi_p", "--phi-p"},
                                 {"replicates", "--replicates"},
                                 {"output", "-o"},
                                 {"centred", "--centred"},
                                 {"criterion", "--criterion"}};

/// --param NAME:LOW:HIGH[:log|uniform] (repeatable) or --dim D (names x1..xD on the unit cube).
analysis::DesignParameters parse_parameters(const DesignArgs& args) {
  analysis::DesignParameterOptions options;
  options.parameters = args.params;
  if (args.dimension_given) options.dimension = args.dimension;
  return with_option_names(k_option_names, [&] { return analysis::parse_design_parameters(options); });
}

/// -o is checked before the library sees it: the file is the user's to name.
void check_output_given(const std::string& output) {
  if (output.empty()) throw UserError("-o/--out FILE is required: the CSV file to write");
}

void run_point_design(const DesignArgs& args, sobol::DesignKind kind) {
  analysis::PointDesignOptions options;
  options.parameters = parse_parameters(args);
  options.kind = kind;
  options.samples = args.samples;
  options.seed = args.seed;
  options.time_limit = args.time_limit;
  options.iterations = args.iterations;
  options.phi_p = args.phi_p;
  options.output = args.output;
  options.warn = warnings_with_option_names(k_option_names);
  check_output_given(args.output);
  const analysis::PointDesign written =
      with_option_names(k_option_names, [&] { return analysis::write_point_design(options); });
  fmt::print("{}",
             args.json ? analysis::point_design_json(written).dump(2) + "\n" : analysis::point_design_text(written));
}

void run_saltelli(const DesignArgs& args) {
  analysis::SaltelliDesignFileOptions options;
  options.parameters = parse_parameters(args);
  options.base = args.samples;
  options.second_order = args.second_order;
  options.replicates = args.replicates;
  options.seed = args.seed;
  options.output = args.output;
  options.metrics = args.json;  // only on request: the pair metrics take O(N^2) time
  options.warn = warnings_with_option_names(k_option_names);
  check_output_given(args.output);
  const analysis::SaltelliDesignWritten written =
      with_option_names(k_option_names, [&] { return analysis::write_simulator_saltelli_design(options); });
  fmt::print("{}", args.json ? analysis::saltelli_design_written_json(written).dump(2) + "\n"
                             : analysis::saltelli_design_written_text(written));
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
    const sobol::DesignKind kind = with_option_names(k_option_names, [&] {
      return analysis::lhs_kind({args->centred, args->criterion});
    });
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
