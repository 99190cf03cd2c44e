// `demsa run` (docs/reference/command-line.md): a whole study, resumable, then its analysis.
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/exec/cost.hpp"
#include "orchestrator/exec/run_report.hpp"
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/exec/slurm/executor.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/signals.hpp"
#include "orchestrator/util/text.hpp"
#include "sobol/stop.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <iostream>
#include <memory>
#include <string>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::exec;
using namespace demsa::analysis;

namespace {

struct RunArgs {
  std::string study;
  std::string dir;
  bool dry_run = false;
  bool json = false;
  double probe = 0.0;  ///< [s] with --dry-run: run the first case this long to measure the study's rate
  bool new_study = false;
  bool no_analyze = false;
  bool quiet = false;
  bool submit_only = false;
  bool cancel_on_interrupt = false;
  double progress_interval = 10.0;
};

/// The library's fields as the options that set them.
const OptionNames k_option_names{
    {"submit_only", "--submit-only"}, {"dry_run", "--dry-run"}, {"json", "--json"}, {"probe", "--probe"}};

int do_run(const RunArgs& args) {
  RunOptions options;
  options.study_file = args.study;
  options.dir = args.dir;
  options.dry_run = args.dry_run;
  options.new_study = args.new_study;
  options.quiet = args.quiet;
  options.progress_interval = args.progress_interval;
  options.submit_only = args.submit_only;
  options.cancel_on_interrupt = args.cancel_on_interrupt;
  const RunReportOptions report_options{args.json, args.probe};
  with_option_names(k_option_names, [&] { report_options.validate(options); });
  if (::isatty(STDIN_FILENO) == 1)
    options.ask_cancel = [](int in_flight) { return ask_cancel_on_interrupt(in_flight, std::cin, std::cerr); };
  StopFlag::install();
  const RunSummary summary = with_option_names(k_option_names, [&] { return run_study(options); });
  if (!args.json) fmt::print("{}", remeasure_text(summary));
  if (summary.dry_run) {
    const DryRunReport report = dry_run_report(args.study, summary, args.probe, [&args](const std::string& note) {
      if (!args.json && !args.quiet) fmt::print(stderr, "{}\n", note);
    });
    fmt::print("{}", args.json ? report.json : report.text);
    return k_exit_ok;
  }
  fmt::print("{}", run_summary_text(summary, args.study, args.submit_only));
  if (summary.interrupted) return interrupted_status();
  if (args.submit_only) return k_exit_ok;
  if (!args.no_analyze && summary.done >= 2) {
    AnalyzeOptions analyze;
    analyze.dir = summary.dir;
    // run_study() let go of the study; the analysis holds it again, as `demsa analyze` does.
    const auto lock = study::hold_study_for_results(summary.dir);
    analyze.should_stop = [] { return StopFlag::raised(); };
    AnalysisSummary analysis;
    try {
      analysis = analyze_study(analyze);
    } catch (const sobol::Stopped&) {
      fmt::print("interrupted during the analysis (nothing written): `demsa analyze {}` runs it again\n",
                 summary.dir.string());
      return interrupted_status();
    }
    fmt::print("{}", analysis_tables_text(analysis));
    if (const std::string failure = analysis_failure(analysis); !failure.empty()) throw UserError(failure);
  }
  return summary.failed > 0 ? k_exit_check_failed : k_exit_ok;
}

}  // namespace

void register_run_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* run = app.add_subcommand("run", "Run a whole study, resumable: skips finished cases, retries failed ones");
  run->add_option("study", args->study, "Study file (TOML)")->required();
  run->add_option("--dir", args->dir, "Study folder (default: the study file's name without .toml)");
  run->add_flag("--dry-run", args->dry_run,
                "Validate and write the design and every case, print the estimate of its cost (atom-steps, CPU, wall); "
                "run nothing");
  run->add_flag("--json", args->json, "With --dry-run: print the study's estimate (atom-steps, CPU, wall) as JSON");
  run->add_option("--probe", args->probe,
                  "With --dry-run: run the study's first case for at most SECONDS here to measure its own rate (and, "
                  "if it ends, its atom-steps against its cap); later estimates use it until cases finish")
      ->check(positive_number());
  run->add_flag("--new", args->new_study,
                "Discard the store, design, cases and analysis in the study folder and start a new study");
  run->add_flag("--no-analyze", args->no_analyze, "Do not run the analysis at the end");
  run->add_flag("--quiet", args->quiet, "No progress output");
  run->add_flag("--submit-only", args->submit_only,
                "SLURM: submit every case still to do and return; a later `demsa run` or `demsa status` collects");
  run->add_flag("--cancel-on-interrupt", args->cancel_on_interrupt,
                "SLURM: scancel the tasks in flight on Ctrl-C (default: ask when stdin is a terminal, else leave "
                "them running)");
  run->add_option("--progress-interval", args->progress_interval,
                  "Seconds between progress lines when stderr is not a terminal")
      ->check(positive_number());
  run->callback([&state, args] { state.exit_code = do_run(*args); });
}

}  // namespace demsa::cli
