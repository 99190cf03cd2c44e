// `demsa plan DIR [DIR ...]` (docs/explanation/method.md "Which experiments to run"): before any lab work, the expected
// posterior width of every parameter for every set of the given studies' experiments (analysis/experiment_plan.hpp),
// its cost, a recommendation, DIR/plan/plan.json and the figure plan_widths.
#include "orchestrator/analysis/experiment_plan.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/cli/targets.hpp"
#include "orchestrator/report/posterior_plots.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <memory>
#include <string>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::analysis;

namespace {

struct PlanArgs {
  PlanOptions options;
  std::vector<std::string> dirs, sds, observe, near;
  std::string out;
  std::uint64_t seed = 0;
  bool json = false;
  bool no_plots = false;
};

int do_plan(PlanArgs& args) {
  for (const std::string& text : args.sds) args.options.sds.push_back(parse_observable_sd(text));
  for (const std::string& text : args.observe) args.options.observe.push_back(parse_observable("--observe", text));
  // A value without its spread is refused by plan_experiments (PlanOptions.near).
  for (const std::string& text : args.near)
    for (const MeasuredTarget& m : parse_measured("--near", text)) args.options.near.push_back(m);
  for (const std::string& d : args.dirs) args.options.dirs.emplace_back(d);
  args.options.out = args.out;
  if (args.seed != 0) args.options.seed = args.seed;
  // Reads every study's store (none may be extended by a `demsa run` meanwhile); writes only into the first study's
  // plan/ (or --out).
  std::vector<std::unique_ptr<study::StudyLock>> locks;
  for (const std::filesystem::path& d : args.options.dirs) locks.push_back(study::hold_study_for_results(d));
  const PlanOutcome outcome = with_option_names({{"sds", "--sd"},
                                                 {"observe", "--observe"},
                                                 {"near", "--near"},
                                                 {"truths", "--truths"},
                                                 {"goal", "--goal"},
                                                 {"model", "--model"},
                                                 {"threads", "--threads"},
                                                 {"out", "--out"}},
                                                [&] { return plan_experiments(args.options); });
  std::string plot_note;
  if (!args.no_plots) {
    try {
      report::plot_plan(report::Plotter(), outcome, outcome.out);
    } catch (const std::exception& e) {
      plot_note = fmt::format("no plot: {}", e.what());
    }
  }
  if (args.json)
    fmt::print("{}", plan_to_json(outcome));
  else
    fmt::print("{}{}", plan_text(outcome), plot_note.empty() ? "" : plot_note + "\n");
  return outcome.problems.empty() ? k_exit_ok : k_exit_check_failed;
}

}  // namespace

void register_plan_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<PlanArgs>();
  CLI::App* sub = app.add_subcommand(
      "plan", "Which experiments to run: the expected posterior width of each parameter for every set of studies");
  sub->add_option("dir", args->dirs, "Study folders, one per candidate experiment (1 to 6)")->required();
  sub->add_option("--sd", args->sds,
                  "NAME=SD or STUDY:NAME=SD: the total sd of a measured observable (default: the study's DEM noise "
                  "from its replicates combined with a measurement error of 2 % of the observable's median)");
  sub->add_option("--observe", args->observe,
                  "NAME or STUDY:NAME: the observables measured (default: what a laboratory measures in each "
                  "experiment: a pile's angle, an incline's two angles, ...)");
  sub->add_option("--near", args->near,
                  "NAME=V±E or STUDY:NAME=V±E: a guess of the value the lab will measure; the truths are drawn where "
                  "the metamodel predicts it (default: the whole prior)");
  sub->add_option("--truths", args->options.truths, "Parameter points drawn from the prior, 2..1000 (default 50)");
  sub->add_option("--goal", args->options.goal,
                  "The width, over the prior width, the recommendation asks of every parameter with ST >= 0.1 "
                  "(default 0.5)");
  sub->add_option("--model", args->options.model, "Metamodel for every observable (default: the best Q² each)");
  sub->add_option("--seed", args->seed, "Seed of the truths and samplers (default: the first study's seed)");
  sub->add_option("--out", args->out, "Output folder (default: DIR/plan of the first study)");
  sub->add_option("--threads", args->options.threads,
                  "Truths calibrated side by side (default 0: one per core); the plan is the same");
  sub->add_flag("--no-plots", args->no_plots, "No gnuplot figure");
  sub->add_flag("--json", args->json, "Machine-readable output (plan.json)");
  sub->callback([args, &state] { state.exit_code = do_plan(*args); });
}

}  // namespace demsa::cli
