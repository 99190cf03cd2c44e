// `demsa analyze` (docs/reference/command-line.md): metamodels and Sobol' indices on a study's observables, written to
// analysis/. SIGINT/SIGTERM stop it within a step of its loops (exit 128 + N) before it writes any file; an analysis in
// which no observable got indices is written (it records why) and exits 2.
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "orchestrator/util/signals.hpp"
#include "sobol/stop.hpp"

#include <fmt/core.h>

#include <memory>
#include <string>
#include <vector>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::analysis;

namespace {

struct AnalyzeArgs {
  std::string dir;
  std::vector<std::string> models;
  int bootstrap = -1;
  int base = -1;
  bool second_order = false;
  bool no_second_order = false;
  bool json = false;
};

int do_analyze(const AnalyzeArgs& args) {
  AnalyzeOptions options;
  options.dir = args.dir;
  options.metamodels = args.models;
  options.bootstrap = args.bootstrap;
  options.base_samples = balanced_base_samples(args.base, "AnalyzeOptions.base_samples",
                                               warnings_with_option_names({{"base_samples", "--base"}}));
  if (args.second_order) options.second_order = 1;
  if (args.no_second_order) options.second_order = 0;
  // A `demsa run` holding the study would leave an analysis of the samples done so far: refused, as a second run is.
  const auto lock = study::hold_study_for_results(options.dir);
  StopFlag::install();
  options.should_stop = [] { return StopFlag::raised(); };
  AnalysisSummary summary;
  try {
    summary = analyze_study(options);
  } catch (const sobol::Stopped&) {
    fmt::print(stderr, "demsa: analysis of {} stopped by signal {}; nothing written\n", args.dir,
               StopFlag::signal_number());
    return k_exit_signal_base + StopFlag::signal_number();
  }
  if (args.json)
    fmt::print("{}\n", read_file(summary.out_dir / study::k_analysis_json));
  else
    fmt::print("{}", analysis::analysis_tables_text(summary));
  if (const std::string failure = analysis_failure(summary); !failure.empty()) throw UserError(failure);
  return k_exit_ok;
}

}  // namespace

void register_analyze_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<AnalyzeArgs>();
  CLI::App* analyze =
      app.add_subcommand("analyze", "Metamodels and Sobol' indices on a study's observables (writes analysis/)");
  analyze->add_option("dir", args->dir, "Study folder")->required();
  analyze->add_option("--models", args->models, "Metamodels (default: the study's [analysis] metamodels)");
  analyze->add_option("--bootstrap", args->bootstrap, "Design-bootstrap refits for the intervals")
      ->check(non_negative_number());
  analyze->add_option("--base", args->base, "QMC base sample size N")->check(number_in(2, 1 << 24));
  analyze->add_flag("--second-order", args->second_order, "Also compute S2");
  analyze->add_flag("--no-second-order", args->no_second_order, "Do not compute S2");
  analyze->add_flag("--json", args->json, "Print analysis.json");
  analyze->callback([&state, args] { state.exit_code = do_analyze(*args); });
}

}  // namespace demsa::cli
