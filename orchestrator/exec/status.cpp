#include "orchestrator/exec/status.hpp"

#include "orchestrator/exec/liggghts_locator.hpp"
#include "orchestrator/exec/local_executor.hpp"
#include "orchestrator/exec/progress.hpp"
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/observables.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"

#include <fmt/core.h>

#include <exception>
#include <map>

namespace demsa::exec {

using namespace demsa::study;

namespace {

namespace fs = std::filesystem;

/// On a SLURM study that no demsa runs: commits the runs whose tasks have ended (one look, no waiting), submits and
/// cancels nothing. Returns the number of runs that ended; 0 when there was nothing to do or the study is not a SLURM
/// study. A problem here (no sbatch on this machine, squeue failing, the study file no longer parsing) is a warning
/// on stderr and leaves status read-only: the counts are still worth showing.
int collect_submitted(const fs::path& dir) {
  const fs::path frozen = dir / k_frozen_study;
  try {
    if (StudyLock::holder(dir) != 0) return 0;
    if (Store::open_read_only((dir / k_store_file).string()).counts().running == 0) return 0;
    ExecutorKind kind = ExecutorKind::local;
    try {
      kind = experiments::load_study(frozen).run.executor;
    } catch (const util::UserError&) {
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
      util::log::info("collected {} ended SLURM task(s): {} committed; {} still queued or running", summary.collected,
                      summary.done_now, summary.left_running);
    return summary.collected;
  } catch (const std::exception& e) {
    util::log::warn("submitted runs not collected: {}", e.what());
    return 0;
  }
}

}  // namespace

StudyStatus study_status(const fs::path& dir) {
  const fs::path db = dir / k_store_file;
  if (!fs::exists(db)) throw util::UserError(fmt::format("{}: not a study folder (no study.db)", dir.string()));
  StudyStatus status;
  status.dir = dir;
  status.collected = collect_submitted(dir);
  const Store store = Store::open_read_only(db.string());
  status.study = store.study_name();
  const StoreCounts& c = status.counts = store.counts();
  status.holder = StudyLock::holder(dir);
  // Failures: the latest failed run of each sample that is not done.
  std::map<int, RunRow> failures;
  std::map<int, bool> done;
  for (const RunRow& r : store.runs()) {
    if (r.state == RunState::done) done[r.sample] = true;
    if (r.state == RunState::failed) failures[r.sample] = r;
  }
  for (const auto& [sample, r] : failures)
    if (!done.count(sample)) status.failures.push_back(r);
  int parallel = 1;
  // The bill (exec/cost.hpp): from the cached rate or the study's finished cases; status never runs LIGGGHTS.
  try {
    StudyConfig config = experiments::load_study(dir / k_frozen_study);
    if (config.run.executor == ExecutorKind::local) parallel = local_parallel(config.run, machine_cores());
    resolve_liggghts(config, false);
    status.bill = estimate_study(config, dir, StudyCostOptions{.measure_rate = false});
  } catch (const util::UserError&) {
    parallel = 1;  // status still works on a study whose file no longer parses here
  }
  // Piles that reached settle_time still moving: counted, but flagged.
  const std::map<int, std::map<std::string, double>> observables = store.observables();
  status.unsettled = unsettled_samples(observables);
  if (!status.unsettled.empty()) status.unsettled_text = experiments::unsettled_text(observables);
  status.eta = estimate_remaining(
      c.samples + c.replicates - c.done - c.replicates_done - (status.holder ? 0 : c.failed + c.replicates_failed),
      parallel, c.mean_done_wall);
  if (status.bill) status.case_costs = store.case_costs();
  return status;
}

nlohmann::json study_status_json(const StudyStatus& s) {
  const StoreCounts& c = s.counts;
  nlohmann::json j{{"dir", s.dir.string()}, {"study", s.study},       {"samples", c.samples},
                   {"done", c.done},        {"running", c.running},   {"failed", c.failed},
                   {"pending", c.pending},  {"attempts", c.attempts}, {"mean_case_seconds", c.mean_done_wall},
                   {"eta_seconds", s.eta},  {"active_pid", s.holder}, {"collected", s.collected}};
  nlohmann::json list = nlohmann::json::array();
  for (const RunRow& r : s.failures)
    list.push_back({{"sample", r.sample},
                    {"attempt", r.attempt},
                    {"class", to_string(r.failure)},
                    {"message", r.message},
                    {"exit_code", r.exit_code},
                    {"log_tail", r.log_tail}});
  j["failures"] = list;
  if (c.replicates > 0)
    j["replicates"] = {{"cases", c.replicates},
                       {"done", c.replicates_done},
                       {"running", c.replicates_running},
                       {"failed", c.replicates_failed}};
  j["unsettled"] = s.unsettled;
  if (s.bill) j["estimate"] = estimate_json(*s.bill)["estimate"];
  return j;
}

std::string study_status_text(const StudyStatus& s) {
  const StoreCounts& c = s.counts;
  std::string text = fmt::format("study {} in {}\n", s.study, s.dir.string());
  text += fmt::format("samples {}: done {}, running {}, failed {}, pending {} ({} attempts)\n", c.samples, c.done,
                      c.running, c.failed, c.pending, c.attempts);
  if (c.replicates > 0)
    text += fmt::format("replicate cases {} (DEM noise): done {}, running {}, failed {}, pending {}\n", c.replicates,
                        c.replicates_done, c.replicates_running, c.replicates_failed,
                        c.replicates - c.replicates_done - c.replicates_running - c.replicates_failed);
  text +=
      fmt::format("demsa run: {}\n", s.holder ? fmt::format("active (pid {})", s.holder) : std::string("not running"));
  if (c.mean_done_wall > 0)
    text += fmt::format("mean case time {}; ETA {}\n", format_duration(c.mean_done_wall),
                        s.eta < 0 ? std::string("?") : format_duration(s.eta));
  for (const RunRow& r : s.failures)
    text += fmt::format("  sample {} attempt {}: {}: {}\n", r.sample, r.attempt, to_string(r.failure), r.message);
  if (!s.unsettled.empty())
    text +=
        fmt::format("unsettled {} of {} done: sample {} still moving at the end of settling (measured and counted)\n",
                    s.unsettled.size(), c.done, s.unsettled_text);
  if (s.bill) {
    text += estimate_text(*s.bill);
    if (!s.case_costs.empty())
      text += fmt::format("predicted against actual, per finished case:\n{}", predicted_vs_actual_table(s.case_costs));
  }
  return text;
}

}  // namespace demsa::exec
