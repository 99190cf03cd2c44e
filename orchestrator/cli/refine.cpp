// `demsa refine DIR --target-ci W [--batch B] [--max-samples M]` (docs/refine.md): run what is left, fit the
// study's metamodels, compute the Sobol' indices with their intervals, and stop once every S1 and ST interval
// half-width is at most W (for every observable) or the study holds M samples; otherwise add B samples where the
// metamodels are least sure (analysis/refinement.hpp) and go round again.
//
// Resumable and kill -9 safe as `demsa run` is: the cases run through run_study (the same executor, local or SLURM,
// the same recovery), a batch's samples enter the store in one transaction before any of them runs, and a step's
// history row is keyed by its number of done samples, so a restarted refine runs what its predecessor added and
// records each step once.
#include "orchestrator/analysis/refinement.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/signals.hpp"
#include "sobol/stop.hpp"

#include <fmt/core.h>

#include <cmath>
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

int interrupted_status() {
  const int sig = StopFlag::signal_number();
  return sig > 0 ? k_exit_signal_base + sig : k_exit_check_failed;
}

std::string width_text(double w) { return std::isfinite(w) ? fmt::format("{:.4f}", w) : std::string("none"); }

void print_step(const RefineStep& step) {
  std::string widths;
  for (const auto& [name, w] : step.max_half_width) widths += fmt::format("  {} {}", name, width_text(w));
  fmt::print("refine: step {:>3}  {:>5} samples  max half-width:{}  -> {}\n", step.iteration, step.samples, widths,
             step.decision);
}

void write_history(const fs::path& dir, const std::vector<RefineStep>& steps) {
  const fs::path out = dir / k_analysis_folder;
  fs::create_directories(out);
  write_file_atomically(out / "refine.csv", analysis::refine_history_csv(steps));
  write_file_atomically(out / "refine.json", analysis::refine_history_json(steps));
}

int do_refine(const RefineArgs& args) {
  const fs::path dir = args.dir;
  require_study_folder(dir);
  const fs::path study_file = dir / k_frozen_study;
  StopFlag::install();
  const auto should_stop = [] { return StopFlag::raised(); };
  long max_samples = args.max_samples;
  if (max_samples == 0) max_samples = 2L * Store::open_read_only((dir / k_store_file).string()).design_samples();
  fmt::print("refine {}: target half-width {}, batches of {}, at most {} samples\n", dir.string(), args.target,
             args.batch, max_samples);

  for (;;) {
    exec::RunOptions run;
    run.study_file = study_file;
    run.dir = dir;
    run.quiet = args.quiet;
    const exec::RunSummary ran = exec::run_study(run);
    if (ran.interrupted) {
      fmt::print("interrupted: `demsa refine {} --target-ci {}` resumes\n", dir.string(), args.target);
      return interrupted_status();
    }
    if (ran.done < 2)
      throw UserError(
          fmt::format("{}: {} of {} samples done; the indices need at least 2", dir.string(), ran.done, ran.samples));

    // The analysis and the new samples hold the study as `demsa analyze` does (no `demsa run` in between).
    const auto lock = hold_study_for_results(dir);
    analysis::AnalyzeOptions analyze;
    analyze.dir = dir;
    analyze.second_order = 0;  // the stop rule reads S1 and ST; the last step computes S2 if the study asks
    analyze.should_stop = should_stop;
    analysis::AnalysisSummary summary;
    try {
      summary = analysis::analyze_study(analyze);
    } catch (const sobol::Stopped&) {
      fmt::print("interrupted during the analysis: `demsa refine {} --target-ci {}` resumes\n", dir.string(),
                 args.target);
      return interrupted_status();
    }
    const analysis::RefinementCheck check = analysis::check_refinement(summary);

    Store store((dir / k_store_file).string());
    const StudyConfig config = experiments::load_study(study_file);
    const std::vector<SampleRow> samples = store.samples();
    std::vector<RefineStep> history = store.refine_history();
    RefineStep step;
    step.iteration = static_cast<int>(history.size()) + 1;
    for (const RefineStep& h : history)
      if (h.samples == ran.done) step.iteration = h.iteration;
    step.samples = ran.done;
    step.target = args.target;
    step.time = unix_now();
    step.max_half_width = check.max_half_width;
    step.indices_json = check.indices_json;
    const bool reached = check.reached(args.target);
    const long room = max_samples - static_cast<long>(samples.size());
    std::vector<SampleRow> added;
    if (reached) {
      step.decision = "reached";
    } else if (room <= 0) {
      step.decision = "budget";
    } else {
      const int batch = static_cast<int>(std::min<long>(args.batch, room));
      // One seed per step: the study's, mixed with the number of samples it starts from.
      const std::uint64_t seed = config.seed ^ (0xD1B54A32D192ED03ULL * static_cast<std::uint64_t>(samples.size()));
      added = analysis::choose_refinement_points(config, store, batch, seed);
      step.decision = fmt::format("added {}", added.size());
    }
    store.record_refine_step(step);
    if (!added.empty())
      store.add_samples(
          added, "refined",
          fmt::format("{} samples added by refine step {} (samples {} to {}; worst half-width {})", added.size(),
                      step.iteration, added.front().sample, added.back().sample, width_text(check.worst())));
    write_file_atomically(dir / k_design_file, exec::design_csv(config, store.samples()));
    history = store.refine_history();
    write_history(dir, history);
    print_step(step);
    if (added.empty()) {
      if (config.analysis.second_order) {
        analyze.second_order = -1;
        try {
          summary = analysis::analyze_study(analyze);
        } catch (const sobol::Stopped&) {
          return interrupted_status();
        }
        write_history(dir, history);  // the analysis folder was rewritten
      }
      print_analysis_tables(summary);
      if (reached) {
        fmt::print("refine: every S1 and ST half-width is at most {} with {} samples\n", args.target, ran.done);
        return k_exit_ok;
      }
      fmt::print("refine: the budget of {} samples is spent; worst half-width {} > {}\n", max_samples,
                 width_text(check.worst()), args.target);
      return k_exit_check_failed;
    }
    if (should_stop()) return interrupted_status();
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
