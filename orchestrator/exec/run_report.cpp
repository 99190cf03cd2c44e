#include "orchestrator/exec/run_report.hpp"

#include "orchestrator/exec/cost.hpp"
#include "orchestrator/exec/liggghts_locator.hpp"
#include "orchestrator/exec/progress.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <filesystem>

namespace demsa::exec {

void RunReportOptions::validate(const RunOptions& run) const {
  using util::UserError;
  if (run.submit_only && run.dry_run)
    throw UserError("RunOptions.submit_only and RunOptions.dry_run: a dry run submits nothing; use one of them");
  if (json && !run.dry_run)
    throw UserError("RunReportOptions.json goes with RunOptions.dry_run: the estimate of a study as JSON");
  if (probe != 0.0 && !run.dry_run)
    throw UserError(
        "RunReportOptions.probe goes with RunOptions.dry_run: a short run of the first case that measures the "
        "study's own rate");
  if (probe != 0.0) check_probe_budget(probe);
  if (!std::filesystem::exists(run.study_file))
    throw UserError(fmt::format("{}: no such study file", run.study_file.string()));
}

std::string remeasure_text(const RunSummary& summary) {
  if (!summary.remeasured) return {};
  const RemeasureSummary& m = *summary.remeasured;
  const std::string head =
      fmt::format("{}: only how cases are measured changed ({}): ", summary.dir.string(), util::join(m.keys, "; "));
  if (summary.dry_run) return head + "`demsa run` measures the finished cases again from their files\n";
  return head + fmt::format(
                    "{} finished case(s) measured again from their files, {} of them measured now that had "
                    "failed, {} failed to measure\n",
                    m.measured, m.recovered, m.failed);
}

std::string run_summary_text(const RunSummary& summary, const std::string& study, bool submitted_only) {
  const std::string dir = summary.dir.string();
  if (submitted_only)
    return fmt::format(
        "{}: {} case(s) submitted to SLURM now, {} queued or running in all; {} of {} samples done ({} "
        "recovered)\n`demsa status {}` or `demsa run {}` collects them as they end\n",
        dir, summary.submitted, summary.left_running, summary.done, summary.samples, summary.recovered, dir, study);
  std::string text = fmt::format("{}: {} of {} samples done ({} now, {} recovered), {} failed, {}\n", dir, summary.done,
                                 summary.samples, summary.done_now, summary.recovered, summary.failed,
                                 format_duration(summary.seconds));
  if (summary.replicates > 0)
    text += fmt::format("  replicate cases (DEM noise): {} of {} done\n", summary.replicates_done, summary.replicates);
  for (const auto& [cls, n] : summary.failures_by_class) text += fmt::format("  failed attempts: {} x {}\n", n, cls);
  if (!summary.failed_samples.empty())
    text += fmt::format("  failed samples (left out of the analysis; `demsa status {}` shows why): {}\n", dir,
                        util::join(summary.failed_samples));
  if (summary.interrupted) {
    if (summary.left_running > 0)
      text += fmt::format(
          "interrupted: {} SLURM task(s) keep running (not cancelled); a later `demsa run {}` or `demsa status "
          "{}` collects them\n",
          summary.left_running, study, dir);
    text += fmt::format("interrupted: `demsa run {}` resumes the study\n", study);
  }
  return text;
}

DryRunReport dry_run_report(const std::string& study, const RunSummary& summary, double probe,
                            const std::function<void(const std::string&)>& before_probe) {
  study::StudyConfig config = experiments::load_study(study);
  resolve_liggghts(config, probe != 0.0);
  if (probe != 0.0) {
    if (before_probe)
      before_probe(fmt::format("probing: the first case runs for at most {:g} s (LIGGGHTS on 1 case, {} rank(s))",
                               probe, config.run.ranks));
    probe_study(config, summary.dir, probe);
  }
  const StudyEstimate estimate = estimate_study(config, summary.dir, StudyCostOptions{});
  nlohmann::ordered_json j{{"study", study},
                           {"dir", summary.dir.string()},
                           {"samples", summary.samples},
                           {"cases", summary.samples + summary.replicates}};
  j["estimate"] = estimate_json(estimate)["estimate"];
  DryRunReport report;
  report.json = j.dump(2) + "\n";
  report.text = fmt::format("{}: study valid; {} samples, design and {} cases written to {}\n", study, summary.samples,
                            summary.samples + summary.replicates, (summary.dir / "cases").string());
  report.text += estimate_text(estimate);
  return report;
}

}  // namespace demsa::exec
