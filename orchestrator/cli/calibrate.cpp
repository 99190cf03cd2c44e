// `demsa calibrate` (README "Usage"): the parameters that best match measured values on the study's metamodels,
// optionally verified by a real run at the optimum.
#include "orchestrator/analysis/calibration.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/exec/point_run.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <memory>
#include <string>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::analysis;

namespace {

struct CalibrateArgs {
  CalibrateOptions options;
  std::string dir;
  bool json = false;
};

int do_calibrate(CalibrateArgs& args) {
  args.options.dir = args.dir;
  args.options.run_point = exec::run_point;
  // Not while a `demsa run` holds the study: it writes analysis/calibration.json (and --verify a case) into it.
  const auto lock = study::hold_study_for_results(args.options.dir);
  const CalibrationOutcome outcome = calibrate_study(args.options);
  if (args.json)
    fmt::print("{}", calibration_to_json(outcome));
  else
    fmt::print("{}", calibration_text(outcome));
  // A verification that was asked for and did not give measurements is a failed check.
  return args.options.verify && !outcome.verified ? k_exit_check_failed : k_exit_ok;
}

}  // namespace

void register_calibrate_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<CalibrateArgs>();
  CLI::App* sub =
      app.add_subcommand("calibrate", "Parameters that best match measured values, optionally verified by a real run");
  sub->add_option("dir", args->dir, "Study folder")->required();
  sub->add_option("--target", args->options.targets,
                  "NAME=VALUE to match, e.g. angle=33.5 or settlement=0.5e-3,1.2e-3,1.9e-3 (default: the study's "
                  "target angle or measured settlements)");
  sub->add_option("--weight", args->options.weights, "NAME=W weight of a target (default 1)");
  sub->add_option("--model", args->options.model, "Metamodel for every target (default: the best Q² per target)");
  sub->add_flag("--verify", args->options.verify, "Run the real case at the optimum and compare");
  sub->add_option("--global", args->options.global, "NLopt global pass: direct-l, crs2, isres, mlsl-lds, none");
  sub->add_option("--local", args->options.local, "NLopt local pass: bobyqa, nelder-mead, sbplx, cobyla, none");
  sub->add_option("--global-evaluations", args->options.global_evaluations, "Budget of the global pass");
  sub->add_option("--local-evaluations", args->options.local_evaluations, "Budget of the local pass");
  sub->add_flag("--json", args->json, "Machine-readable output (the calibration.json document)");
  sub->callback([args, &state] { state.exit_code = do_calibrate(*args); });
}

}  // namespace demsa::cli
