// `demsa sensitivity`: Sobol' indices for any simulator (docs/reference/command-line.md; paper §5–6), either
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
#include "orchestrator/analysis/sensitivity.hpp"
#include "orchestrator/analysis/sensitivity_choices.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "orchestrator/util/signals.hpp"
#include "sobol/stop.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <limits>
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
  int bootstrap = k_mode_default;  ///< k_mode_default: the path's default (analysis/sensitivity_choices.hpp)
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
  std::string repeats;               ///< --data: CSV of repeated runs (column `point` + the responses) for the noise
  bool allow_extrapolation = false;  ///< --data: proceed when the data cover less than k_min_coverage of --bounds
};

/// The option of each field of analysis::SaltelliSensitivityOptions, DataSensitivityOptions,
/// SensitivityChoiceOptions and GpChoiceOptions, for the library's messages.
const OptionNames k_option_names{{"design", "--saltelli"},
                                 {"responses_file", "--responses"},
                                 {"responses", "--response"},
                                 {"interval", "--interval"},
                                 {"data", "--data"},
                                 {"inputs", "--inputs"},
                                 {"bounds", "--bounds"},
                                 {"allow_extrapolation", "--allow-extrapolation"},
                                 {"metamodels", "--metamodels"},
                                 {"save_model", "--save-model"},
                                 {"base", "--base"},
                                 {"repeats", "--repeats"},
                                 {"bootstrap", "--bootstrap"},
                                 {"confidence", "--confidence"},
                                 {"kernel", "--gp-kernel"},
                                 {"trend", "--gp-trend"}};

/// The choices of the indices as the library checks them (analysis/sensitivity_choices.hpp).
SensitivityChoiceOptions choices(const SensitivityArgs& args) {
  SensitivityChoiceOptions c;
  if (args.bootstrap != k_mode_default) c.bootstrap = args.bootstrap;
  c.interval = args.interval;
  c.confidence = args.confidence;
  c.base = args.base;
  c.design = args.saltelli;
  c.data = args.data;
  c.repeats = args.repeats;
  c.save_model = args.save_model;
  return c;
}

// ---------------------------------------------------------------- --saltelli DESIGN.csv --responses Y.csv

void run_saltelli(const SensitivityArgs& args) {
  SaltelliSensitivityOptions options;
  options.indices.interval = with_option_names(k_option_names, [&] { return saltelli_interval_choice(choices(args)); });
  options.design = args.saltelli;
  options.responses_file = args.responses;
  options.responses = split_list(args.outputs);
  options.indices.second_order = args.second_order;
  options.indices.bootstrap = choices(args).bootstrap.value_or(k_default_saltelli_bootstrap);
  options.indices.confidence = args.confidence;
  options.indices.seed = args.seed;
  options.indices.stop = [] { return StopFlag::raised(); };
  options.warn = warnings_with_option_names(k_option_names);
  options.on_response = [&args](const std::vector<std::string>& inputs, const SaltelliResponseIndices& o) {
    if (args.json == "-") return;
    fmt::print("{}", saltelli_response_text(o, inputs));
  };
  if (args.json != "-") options.json_file = args.json;
  const SaltelliSensitivity result = with_option_names(k_option_names, [&] { return saltelli_sensitivity(options); });
  if (args.json == "-") fmt::print("{}\n", saltelli_sensitivity_json(result).dump(2));
}

// ---------------------------------------------------------------- --data DATA.csv: metamodels, then indices

void run_data(const SensitivityArgs& args) {
  DataSensitivityOptions options;
  options.data = args.data;
  options.inputs = split_list(args.inputs);
  options.responses = split_list(args.outputs);
  with_option_names(k_option_names, [&] {
    options.bounds = parse_input_bounds(args.bounds, options.inputs);
    options.metamodels = choose_metamodels(split_list(args.metamodels));
    choose_gp({args.gp_kernel, args.gp_trend}, options.models.gp);
  });
  options.allow_extrapolation = args.allow_extrapolation;
  options.indices.base = args.base;
  options.indices.second_order = args.second_order;
  options.indices.bootstrap = choices(args).bootstrap.value_or(k_default_data_refits);
  options.indices.confidence = args.confidence;
  options.indices.seed = args.seed;
  options.indices.stop = [] { return StopFlag::raised(); };
  options.models.gp.seed = args.seed;
  options.models.gp.nugget = args.gp_nugget;
  options.repeats = args.repeats;
  options.save_model = args.save_model;
  options.warn = warnings_with_option_names(k_option_names);
  const bool print = args.json != "-";
  options.on_model = [print, &options](const std::string& response, const DataModelIndices& m) {
    if (!print) return;
    fmt::print("{}", data_model_text(response, m, options.inputs));
  };
  options.on_noise = [print](const NoiseAnalysis& noise) {
    if (print) fmt::print("{}\n", noise_text(noise));
  };
  if (args.json != "-") options.json_file = args.json;
  const DataSensitivity result = with_option_names(k_option_names, [&] { return data_sensitivity(options); });
  if (print)
    for (const std::string& file : result.model_files) fmt::print("metamodel written to {}\n", file);
  if (args.json == "-") fmt::print("{}\n", data_sensitivity_json(result).dump(2));
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
  sub->add_option("--repeats", args->repeats,
                  "With --data: CSV of repeated runs, a column 'point' labelling the runs of one input point and the "
                  "response columns (e.g. DIR/analysis/replicates.csv): measures each response's noise variance, "
                  "sets the gp nugget from it and prints its share of the response's variance");
  // "replicates" are a study's DEM-noise cases and a Saltelli design's scrambled blocks; the runs repeated at input
  // points here are repeats.
  add_deprecated_option(sub, "--replicates", "--repeats", args->repeats);
  sub->add_flag("--gp-nugget", args->gp_nugget,
                "Estimate a nugget in the gp metamodel (noisy simulators such as DEM: it then smooths, not "
                "interpolates)");
  sub->callback([args, &state] {
    with_option_names(k_option_names, [&] { check_sensitivity_choices(choices(*args)); });
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
