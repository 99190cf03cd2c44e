// `demsa run`, `demsa status`, `demsa analyze` (README "Usage").
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/exec/local_executor.hpp"
#include "orchestrator/exec/progress.hpp"
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/exec/slurm/executor.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/signals.hpp"

#include <fmt/core.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::exec;
using namespace demsa::analysis;

namespace {

namespace fs = std::filesystem;

struct RunArgs {
  std::string study;
  std::string dir;
  bool dry_run = false;
  bool new_study = false;
  bool no_analyze = false;
  bool quiet = false;
  bool submit_only = false;
  bool cancel_on_interrupt = false;
  double progress_interval = 10.0;
};

struct StatusArgs {
  std::string dir;
  bool json = false;
};

struct AnalyzeArgs {
  std::string dir;
  std::vector<std::string> models;
  int bootstrap = -1;
  int base = -1;
  bool second_order = false;
  bool no_second_order = false;
  bool json = false;
};

std::string read_file_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string join(const std::vector<int>& values) {
  std::string text;
  for (int v : values) {
    if (!text.empty()) text += ' ';
    text += std::to_string(v);
  }
  return text;
}

void print_tables(const AnalysisSummary& summary) {
  for (const ObservableAnalysis& o : summary.observables) fmt::print("\n{}", s1_table_text(summary, o));
  if (!summary.samples_left_out.empty()) {
    fmt::print("\nleft out of the analysis (not done): samples {}\n", join(summary.samples_left_out));
  }
  fmt::print("\ntables, metamodels and indices with confidence intervals: {}\n", summary.out_dir.string());
}

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
  if (args.submit_only && args.dry_run)
    throw UserError("--submit-only and --dry-run: a dry run submits nothing; use one of them");
  if (::isatty(STDIN_FILENO) == 1)
    options.ask_cancel = [](int in_flight) { return ask_cancel_on_interrupt(in_flight, std::cin, std::cerr); };
  if (!fs::exists(options.study_file)) throw UserError(fmt::format("{}: no such study file", args.study));
  StopFlag::install();
  const RunSummary summary = run_study(options);
  if (summary.dry_run) {
    fmt::print("{}: study valid; {} samples, design and {} cases written to {}\n", args.study, summary.samples,
               summary.samples, (summary.dir / "cases").string());
    return k_exit_ok;
  }
  if (args.submit_only) {
    fmt::print(
        "{}: {} case(s) submitted to SLURM now, {} queued or running in all; {} of {} samples done ({} "
        "recovered)\n",
        summary.dir.string(), summary.submitted, summary.left_running, summary.done, summary.samples,
        summary.recovered);
    fmt::print("`demsa status {}` or `demsa run {}` collects them as they end\n", summary.dir.string(), args.study);
    if (summary.interrupted) {
      const int sig = StopFlag::signal_number();
      return sig > 0 ? 128 + sig : k_exit_check_failed;
    }
    return k_exit_ok;
  }
  fmt::print("{}: {} of {} samples done ({} now, {} recovered), {} failed, {}\n", summary.dir.string(), summary.done,
             summary.samples, summary.done_now, summary.recovered, summary.failed, format_duration(summary.seconds));
  for (const auto& [cls, n] : summary.failures_by_class) fmt::print("  failed attempts: {} x {}\n", n, cls);
  if (!summary.failed_samples.empty()) {
    fmt::print("  failed samples (left out of the analysis; `demsa status {}` shows why): {}\n", summary.dir.string(),
               join(summary.failed_samples));
  }
  if (summary.interrupted) {
    if (summary.left_running > 0)
      fmt::print(
          "interrupted: {} SLURM task(s) keep running (not cancelled); a later `demsa run {}` or `demsa status "
          "{}` collects them\n",
          summary.left_running, args.study, summary.dir.string());
    fmt::print("interrupted: `demsa run {}` resumes the study\n", args.study);
    const int sig = StopFlag::signal_number();
    return sig > 0 ? 128 + sig : k_exit_check_failed;
  }
  if (!args.no_analyze && summary.done >= 2) {
    AnalyzeOptions analyze;
    analyze.dir = summary.dir;
    print_tables(analyze_study(analyze));
  }
  return summary.failed > 0 ? k_exit_check_failed : k_exit_ok;
}

/// `demsa status` on a SLURM study that no demsa runs: commits the runs whose tasks have ended (one look, no
/// waiting), submits and cancels nothing. Returns the number of runs that ended; 0 when there was nothing to do or
/// the study is not a SLURM study. A problem here (no sbatch on this machine, squeue failing, the study file no
/// longer parsing) is reported on stderr and leaves status read-only.
int collect_submitted(const fs::path& dir) {
  const fs::path frozen = dir / "study.toml";
  try {
    if (StudyLock::holder(dir) != 0) return 0;
    if (Store::open_read_only((dir / "study.db").string()).counts().running == 0) return 0;
    ExecutorKind kind = ExecutorKind::local;
    try {
      kind = load_study(frozen).run.executor;
    } catch (const std::exception&) {
      return 0;  // status still works on a study whose file no longer parses here
    }
    if (kind != ExecutorKind::slurm) return 0;
    RunOptions options;
    options.study_file = frozen;
    options.dir = dir;
    options.collect_only = true;
    options.quiet = true;
    options.should_stop = [] { return false; };
    const RunSummary summary = run_study(options);
    if (summary.collected > 0)
      fmt::print(stderr, "collected {} ended SLURM task(s): {} committed; {} still queued or running\n",
                 summary.collected, summary.done_now, summary.left_running);
    return summary.collected;
  } catch (const std::exception& e) {
    fmt::print(stderr, "demsa: warning: submitted runs not collected: {}\n", e.what());
    return 0;
  }
}

int do_status(const StatusArgs& args) {
  const fs::path dir = args.dir;
  const fs::path db = dir / "study.db";
  if (!fs::exists(db)) throw UserError(fmt::format("{}: not a study folder (no study.db)", dir.string()));
  const int collected = collect_submitted(dir);
  const Store store = Store::open_read_only(db.string());
  const StoreCounts c = store.counts();
  const long holder = StudyLock::holder(dir);
  // Failures: the latest failed run of each sample that is not done.
  std::map<int, RunRow> failures;
  std::map<int, bool> done;
  for (const RunRow& r : store.runs()) {
    if (r.state == RunState::done) done[r.sample] = true;
    if (r.state == RunState::failed) failures[r.sample] = r;
  }
  int parallel = 1;
  try {
    const StudyConfig config = load_study(dir / "study.toml");
    if (config.run.executor == ExecutorKind::local) parallel = local_parallel(config.run, machine_cores());
  } catch (const std::exception&) {
    parallel = 1;  // status still works on a study whose file no longer parses here
  }
  const double eta = estimate_remaining(c.samples - c.done - (holder ? 0 : c.failed), parallel, c.mean_done_wall);
  if (args.json) {
    nlohmann::json j{{"dir", dir.string()},  {"study", store.study_name()}, {"samples", c.samples},
                     {"done", c.done},       {"running", c.running},        {"failed", c.failed},
                     {"pending", c.pending}, {"attempts", c.attempts},      {"mean_case_seconds", c.mean_done_wall},
                     {"eta_seconds", eta},   {"active_pid", holder},        {"collected", collected}};
    nlohmann::json list = nlohmann::json::array();
    for (const auto& [sample, r] : failures) {
      if (done.count(sample)) continue;
      list.push_back({{"sample", sample},
                      {"attempt", r.attempt},
                      {"class", to_string(r.failure)},
                      {"message", r.message},
                      {"exit_code", r.exit_code},
                      {"log_tail", r.log_tail}});
    }
    j["failures"] = list;
    fmt::print("{}\n", j.dump(2));
    return k_exit_ok;
  }
  fmt::print("study {} in {}\n", store.study_name(), dir.string());
  fmt::print("samples {}: done {}, running {}, failed {}, pending {} ({} attempts)\n", c.samples, c.done, c.running,
             c.failed, c.pending, c.attempts);
  fmt::print("demsa run: {}\n", holder ? fmt::format("active (pid {})", holder) : std::string("not running"));
  if (c.mean_done_wall > 0)
    fmt::print("mean case time {}; ETA {}\n", format_duration(c.mean_done_wall),
               eta < 0 ? std::string("?") : format_duration(eta));
  for (const auto& [sample, r] : failures) {
    if (done.count(sample)) continue;
    fmt::print("  sample {} attempt {}: {}: {}\n", sample, r.attempt, to_string(r.failure), r.message);
  }
  return k_exit_ok;
}

int do_analyze(const AnalyzeArgs& args) {
  AnalyzeOptions options;
  options.dir = args.dir;
  options.metamodels = args.models;
  options.bootstrap = args.bootstrap;
  options.base_samples = args.base;
  if (args.second_order) options.second_order = 1;
  if (args.no_second_order) options.second_order = 0;
  const AnalysisSummary summary = analyze_study(options);
  if (args.json) {
    fmt::print("{}\n", read_file_text(summary.out_dir / "analysis.json"));
  } else {
    print_tables(summary);
  }
  return k_exit_ok;
}

}  // namespace

void register_run_commands(CLI::App& app, CliState& state) {
  auto run_args = std::make_shared<RunArgs>();
  CLI::App* run = app.add_subcommand("run", "Run a whole study, resumable: skips finished cases, retries failed ones");
  run->add_option("study", run_args->study, "Study file (TOML)")->required();
  run->add_option("--dir", run_args->dir, "Study folder (default: the study file's name without .toml)");
  run->add_flag("--dry-run", run_args->dry_run, "Validate and write the design and every case; run nothing");
  run->add_flag("--new", run_args->new_study,
                "Discard the store, design, cases and analysis in the study folder and start a new study");
  run->add_flag("--no-analyze", run_args->no_analyze, "Do not run the analysis at the end");
  run->add_flag("--quiet", run_args->quiet, "No progress output");
  run->add_flag("--submit-only", run_args->submit_only,
                "SLURM: submit every case still to do and return; a later `demsa run` or `demsa status` collects");
  run->add_flag("--cancel-on-interrupt", run_args->cancel_on_interrupt,
                "SLURM: scancel the tasks in flight on Ctrl-C (default: ask when stdin is a terminal, else leave "
                "them running)");
  run->add_option("--progress-interval", run_args->progress_interval,
                  "Seconds between progress lines when stderr is not a terminal")
      ->check(CLI::PositiveNumber);
  run->callback([&state, run_args] { state.exit_code = do_run(*run_args); });

  auto status_args = std::make_shared<StatusArgs>();
  CLI::App* status = app.add_subcommand(
      "status", "Counts by state, failures with their class, ETA; on a SLURM study, first collects ended tasks");
  status->add_option("dir", status_args->dir, "Study folder")->required();
  status->add_flag("--json", status_args->json, "Machine-readable output");
  status->callback([&state, status_args] { state.exit_code = do_status(*status_args); });

  auto analyze_args = std::make_shared<AnalyzeArgs>();
  CLI::App* analyze =
      app.add_subcommand("analyze", "Metamodels and Sobol' indices on a study's observables (writes analysis/)");
  analyze->add_option("dir", analyze_args->dir, "Study folder")->required();
  analyze->add_option("--models", analyze_args->models, "Metamodels (default: the study's [analysis] metamodels)");
  analyze->add_option("--bootstrap", analyze_args->bootstrap, "Design-bootstrap refits for the intervals")
      ->check(CLI::NonNegativeNumber);
  analyze->add_option("--base", analyze_args->base, "QMC base sample size N")->check(CLI::Range(2, 1 << 24));
  analyze->add_flag("--second-order", analyze_args->second_order, "Also compute S2");
  analyze->add_flag("--no-second-order", analyze_args->no_second_order, "Do not compute S2");
  analyze->add_flag("--json", analyze_args->json, "Print analysis.json");
  analyze->callback([&state, analyze_args] { state.exit_code = do_analyze(*analyze_args); });
}

}  // namespace demsa::cli
