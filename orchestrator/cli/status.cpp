// `demsa status` (README "Usage"): counts by state, failures with their class, ETA; on a SLURM study that no demsa
// runs, first collects the tasks that have ended.
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/exec/cost.hpp"
#include "orchestrator/exec/liggghts_locator.hpp"
#include "orchestrator/exec/local_executor.hpp"
#include "orchestrator/exec/progress.hpp"
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/observables.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <exception>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::exec;

namespace {

namespace fs = std::filesystem;

struct StatusArgs {
  std::string dir;
  bool json = false;
};

/// `demsa status` on a SLURM study that no demsa runs: commits the runs whose tasks have ended (one look, no
/// waiting), submits and cancels nothing. Returns the number of runs that ended; 0 when there was nothing to do or
/// the study is not a SLURM study. A problem here (no sbatch on this machine, squeue failing, the study file no
/// longer parsing) is a warning on stderr and leaves status read-only: the counts below are still worth showing.
int collect_submitted(const fs::path& dir) {
  const fs::path frozen = dir / k_frozen_study;
  try {
    if (StudyLock::holder(dir) != 0) return 0;
    if (Store::open_read_only((dir / k_store_file).string()).counts().running == 0) return 0;
    ExecutorKind kind = ExecutorKind::local;
    try {
      kind = experiments::load_study(frozen).run.executor;
    } catch (const UserError&) {
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
      log::info("collected {} ended SLURM task(s): {} committed; {} still queued or running", summary.collected,
                summary.done_now, summary.left_running);
    return summary.collected;
  } catch (const std::exception& e) {
    log::warn("submitted runs not collected: {}", e.what());
    return 0;
  }
}

int do_status(const StatusArgs& args) {
  const fs::path dir = args.dir;
  const fs::path db = dir / k_store_file;
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
  // The bill (exec/cost.hpp): from the cached rate or the study's finished cases; status never runs LIGGGHTS.
  std::optional<StudyEstimate> bill;
  try {
    StudyConfig config = experiments::load_study(dir / k_frozen_study);
    if (config.run.executor == ExecutorKind::local) parallel = local_parallel(config.run, machine_cores());
    resolve_liggghts(config, false);
    bill = estimate_study(config, dir, StudyCostOptions{.measure_rate = false});
  } catch (const UserError&) {
    parallel = 1;  // status still works on a study whose file no longer parses here
  }
  // Piles that reached settle_time still moving: counted, but flagged.
  const std::map<int, std::map<std::string, double>> observables = store.observables();
  const std::vector<int> unsettled = unsettled_samples(observables);
  const double eta = estimate_remaining(
      c.samples + c.replicates - c.done - c.replicates_done - (holder ? 0 : c.failed + c.replicates_failed), parallel,
      c.mean_done_wall);
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
    if (c.replicates > 0)
      j["replicates"] = {{"cases", c.replicates},
                         {"done", c.replicates_done},
                         {"running", c.replicates_running},
                         {"failed", c.replicates_failed}};
    j["unsettled"] = unsettled;
    if (bill) j["estimate"] = estimate_json(*bill)["estimate"];
    fmt::print("{}\n", j.dump(2));
    return k_exit_ok;
  }
  fmt::print("study {} in {}\n", store.study_name(), dir.string());
  fmt::print("samples {}: done {}, running {}, failed {}, pending {} ({} attempts)\n", c.samples, c.done, c.running,
             c.failed, c.pending, c.attempts);
  if (c.replicates > 0)
    fmt::print("replicate cases {} (DEM noise): done {}, running {}, failed {}, pending {}\n", c.replicates,
               c.replicates_done, c.replicates_running, c.replicates_failed,
               c.replicates - c.replicates_done - c.replicates_running - c.replicates_failed);
  fmt::print("demsa run: {}\n", holder ? fmt::format("active (pid {})", holder) : std::string("not running"));
  if (c.mean_done_wall > 0)
    fmt::print("mean case time {}; ETA {}\n", format_duration(c.mean_done_wall),
               eta < 0 ? std::string("?") : format_duration(eta));
  for (const auto& [sample, r] : failures) {
    if (done.count(sample)) continue;
    fmt::print("  sample {} attempt {}: {}: {}\n", sample, r.attempt, to_string(r.failure), r.message);
  }
  if (!unsettled.empty())
    fmt::print("unsettled {} of {} done: sample {} still moving at the end of settling (measured and counted)\n",
               unsettled.size(), c.done, experiments::unsettled_text(observables));
  if (bill) {
    fmt::print("{}", estimate_text(*bill));
    if (const std::vector<CaseCostRow> rows = store.case_costs(); !rows.empty())
      fmt::print("predicted against actual, per finished case:\n{}", predicted_vs_actual_table(rows));
  }
  return k_exit_ok;
}

}  // namespace

void register_status_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<StatusArgs>();
  CLI::App* status = app.add_subcommand(
      "status", "Counts by state, failures with their class, ETA; on a SLURM study, first collects ended tasks");
  status->add_option("dir", args->dir, "Study folder")->required();
  status->add_flag("--json", args->json, "Machine-readable output");
  status->callback([&state, args] { state.exit_code = do_status(*args); });
}

}  // namespace demsa::cli
