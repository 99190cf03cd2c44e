// `demsa calibrate` (docs/reference/command-line.md): what measured values say about the parameters, on the studies'
// metamodels. The method (bayes, optimize or auto) and the combinations each refuses: analysis/calibration_method.hpp.
#include "orchestrator/analysis/calibration_method.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/exec/point_run.hpp"
#include "orchestrator/report/posterior_plots.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"

#include <fmt/core.h>

#include <memory>
#include <string>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::analysis;

namespace {

struct CalibrateArgs {
  CalibrateOptions options;
  PosteriorOptions posterior;
  std::vector<std::string> dirs, targets, target_files, weights;
  std::string method = "auto";
  std::string out;
  std::uint64_t seed = 0;
  int verify = -1;
  bool json = false;
  bool no_plots = false;
};

/// The library's fields as the options that set them.
const OptionNames k_option_names{{"targets", "--target"},  {"target_files", "--target-file"},
                                 {"weights", "--weight"},  {"method", "--method"},
                                 {"walkers", "--walkers"}, {"steps", "--steps"},
                                 {"burn_in", "--burn-in"}, {"verify", "--verify"},
                                 {"model", "--model"},     {"global_evaluations", "--global-evaluations"},
                                 {"global", "--global"},   {"local_evaluations", "--local-evaluations"},
                                 {"local", "--local"}};

int do_optimize(CalibrateArgs& args) {
  args.options.dir = args.dirs.front();
  args.options.verify = args.verify >= 0;
  args.options.run_point = exec::run_point;
  // Not while a `demsa run` holds the study: it writes analysis/calibration.json (and --verify a case) into it.
  const auto lock = study::hold_study_for_results(args.options.dir);
  const CalibrationOutcome outcome = with_option_names(k_option_names, [&] { return calibrate_study(args.options); });
  if (args.json)
    fmt::print("{}", calibration_to_json(outcome));
  else
    fmt::print("{}", calibration_text(outcome));
  for (const std::string& problem : outcome.problems) log::warn("check failed: {}", problem);
  return calibration_failed(outcome, args.options.verify) ? k_exit_check_failed : k_exit_ok;
}

int do_bayes(CalibrateArgs& args) {
  PosteriorOptions& p = args.posterior;
  for (const std::string& d : args.dirs) p.dirs.emplace_back(d);
  p.model = args.options.model;
  p.out = args.out;
  if (args.seed != 0) p.seed = args.seed;
  p.verify = args.verify;
  p.run_point = exec::run_point;
  std::vector<std::unique_ptr<study::StudyLock>> locks;
  for (const std::filesystem::path& d : p.dirs) locks.push_back(study::hold_study_for_results(d));
  const PosteriorOutcome outcome = with_option_names(k_option_names, [&] { return calibrate_posterior(p); });
  const std::string plot_note = args.no_plots ? "" : report::plot_posterior_note(outcome);
  if (args.json)
    fmt::print("{}", posterior_to_json(outcome));
  else
    fmt::print("{}{}", posterior_text(outcome), plot_note.empty() ? "" : plot_note + "\n");
  for (const std::string& problem : outcome.problems) log::warn("check failed: {}", problem);
  return posterior_failed(outcome) ? k_exit_check_failed : k_exit_ok;
}

int do_calibrate(CalibrateArgs& args) {
  CalibrationMethodOptions choice = with_option_names(
      k_option_names, [&] { return read_calibration_targets(args.targets, args.target_files, args.weights); });
  choice.method = args.method;
  choice.studies = args.dirs.size();
  choice.verify = args.verify;
  args.options.targets = choice.targets;
  args.options.weights = args.posterior.weights = choice.weights;
  args.posterior.targets = choice.targets;
  args.posterior.targets.insert(args.posterior.targets.end(), choice.target_files.begin(), choice.target_files.end());
  const CalibrationMethod method = with_option_names(k_option_names, [&] { return choice.choose(); });
  return method == CalibrationMethod::optimize ? do_optimize(args) : do_bayes(args);
}

}  // namespace

void register_calibrate_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<CalibrateArgs>();
  CLI::App* sub = app.add_subcommand(
      "calibrate", "What measured values say about the parameters: a posterior (bayes) or the best point (optimize)");
  sub->add_option("dir", args->dirs, "Study folders (several: a joint calibration of studies sharing parameters)")
      ->required();
  sub->add_option("--method", args->method,
                  "auto (default: bayes when a target has an uncertainty or several studies are given), bayes, "
                  "optimize");
  sub->add_option("--target", args->targets,
                  "NAME=VALUE[±ERROR] to match (also +-), e.g. angle=33.5±1.5 or settlement=s1,s2,s3±e1,e2,e3 "
                  "(optimize default: the study's target angle or measured settlements)");
  sub->add_option("--target-file", args->target_files,
                  "NAME=FILE.csv: a measured curve, one row per point, columns mean and sd, or low, high and tests");
  sub->add_option("--weight", args->weights, "NAME=W weight of a target (default 1)");
  sub->add_option("--model", args->options.model, "Metamodel for every target (default: the best Q² per target)");
  sub->add_option(
         "--verify", args->verify,
         "Run the real case at the optimum (optimize), or at the MAP and K posterior draws (bayes: --verify K)")
      ->expected(0, 1)
      ->default_str("0");
  sub->add_option("--walkers", args->posterior.walkers, "bayes: ensemble walkers (default max(32, 4 d))");
  sub->add_option(
      "--steps", args->posterior.steps,
      "bayes: kept steps per walker (default 0: automatic, 3000 lengthened until >= 50 autocorrelation times)");
  sub->add_option("--burn-in", args->posterior.burn_in, "bayes: discarded steps per walker (default 1000)");
  sub->add_option("--seed", args->seed, "bayes: sampler seed (default: the first study's seed)");
  sub->add_option("--out", args->out, "bayes: output folder (default: DIR/calibration of the first study)");
  sub->add_flag("--no-plots", args->no_plots, "bayes: no gnuplot figures");
  sub->add_option("--global", args->options.global,
                  "optimize: NLopt global pass: direct-l, crs2, isres, mlsl-lds, none");
  sub->add_option("--local", args->options.local,
                  "optimize: NLopt local pass: bobyqa, nelder-mead, sbplx, cobyla, none");
  sub->add_option("--global-evaluations", args->options.global_evaluations, "optimize: budget of the global pass");
  sub->add_option("--local-evaluations", args->options.local_evaluations, "optimize: budget of the local pass");
  sub->add_flag("--json", args->json, "Machine-readable output (calibration.json or posterior.json)");
  sub->callback([args, &state] { state.exit_code = do_calibrate(*args); });
}

}  // namespace demsa::cli
