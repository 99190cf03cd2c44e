// `demsa refine DIR --target-ci W [--batch B] [--max-samples M]` (docs/how-to/refine.md): run what is left, fit the
// study's metamodels, compute the Sobol' indices with their intervals, and stop once every S1 and ST interval
// half-width is at most W (for every observable) or the study holds M samples; otherwise add B samples where the
// metamodels are least sure (analysis/refinement.hpp) and go round again.
//
// The loop is analysis::refine_study; the cases run through exec::run_study (the same executor, local or SLURM, the
// same recovery), handed in here.
#include "orchestrator/analysis/refinement.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/signals.hpp"

#include <fmt/core.h>

#include <filesystem>
#include <memory>
#include <string>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::study;

namespace {

namespace fs = std::filesystem;

struct RefineArgs {
  std::string dir;
  double target = 0.0;
  long batch = 4;
  long max_samples = 0;  ///< 0: twice the design samples
  bool quiet = false;
};

int do_refine(const RefineArgs& args) {
  const fs::path dir = args.dir;
  require_study_folder(dir);
  StopFlag::install();
  analysis::RefineOptions options;
  options.dir = dir;
  options.target = args.target;
  options.batch = args.batch;
  options.max_samples = args.max_samples;
  options.should_stop = [] { return StopFlag::raised(); };
  options.run_cases = [&args, &dir] {
    exec::RunOptions run;
    run.study_file = dir / k_frozen_study;
    run.dir = dir;
    run.quiet = args.quiet;
    const exec::RunSummary ran = exec::run_study(run);
    return analysis::RefineRun{ran.interrupted, ran.done, ran.samples};
  };
  options.on_start = [&options](long max_samples) {
    fmt::print("{}", analysis::refine_start_text(options, max_samples));
  };
  options.on_step = [](const RefineStep& step) { fmt::print("{}", analysis::refine_step_text(step)); };
  const analysis::RefineSummary refined = analysis::refine_study(options);
  fmt::print("{}", analysis::refine_end_text(refined, options));
  switch (refined.end) {
    case analysis::RefineEnd::reached:
      return k_exit_ok;
    case analysis::RefineEnd::budget:
      return k_exit_check_failed;
    default:
      return interrupted_status();
  }
}

}  // namespace

void register_refine_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<RefineArgs>();
  CLI::App* refine = app.add_subcommand(
      "refine",
      "Add samples where the metamodels are least sure until every Sobol' S1 and ST interval half-width is "
      "at most --target-ci (resumable)");
  refine->add_option("dir", args->dir, "Study folder (run or partly run)")->required();
  refine->add_option("--target-ci", args->target, "Largest admissible half-width of an S1 or ST interval")
      ->required()
      ->check(number_in(1e-6, 1.0));
  refine->add_option("--batch", args->batch, "Samples added per step")->check(integer_in(1, 10000));
  refine
      ->add_option("--max-samples", args->max_samples,
                   "Most samples the study may hold (design and refinement; default: twice the design samples)")
      ->check(integer_in(2, 100000));
  refine->add_flag("--quiet", args->quiet, "No progress output of the runs");
  refine->callback([&state, args] { state.exit_code = do_refine(*args); });
}

}  // namespace demsa::cli
