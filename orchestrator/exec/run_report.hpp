#pragma once
// What `demsa run` reports once run_study returns: the counts and failures of a run (or of a --submit-only
// submission) in words, and a dry run's estimate of the study's cost (exec/cost.hpp) as text or JSON.
#include "orchestrator/exec/runner.hpp"

#include <filesystem>
#include <functional>
#include <string>

namespace demsa::exec {

/// The run in words: done, recovered and failed samples, the replicate cases, failed attempts by class, the samples
/// left out and, when interrupted, how to resume. With `submitted_only` (--submit-only), what was submitted and how
/// to collect it. `study` is the study file as the user gave it.
std::string run_summary_text(const RunSummary& summary, const std::string& study, bool submitted_only);

/// When the study file changed only how cases are measured (RunSummary::remeasured): the changed keys and what was
/// measured again (or, for a dry run, that `demsa run` will); "" otherwise.
std::string remeasure_text(const RunSummary& summary);

/// What `demsa run` reports beside the run itself (RunOptions): a dry run's estimate as JSON, its probe.
struct RunReportOptions {
  bool json = false;   ///< a dry run's estimate as JSON (DryRunReport::json)
  double probe = 0.0;  ///< [s] a dry run's probe of the first case (dry_run_report); 0: none
  /// Throws util::UserError naming the fields when `run` and these do not go together: json or probe without
  /// RunOptions.dry_run, RunOptions.submit_only with it, a probe too short to measure (check_probe_budget), or a
  /// study file that does not exist.
  void validate(const RunOptions& run) const;
};

struct DryRunReport {
  std::string text;  ///< "STUDY: study valid; ..." and the estimate (estimate_text)
  std::string json;  ///< the study, its folder, samples, cases and the estimate (estimate_json)
};

/// The bill of a study whose design and cases a dry run wrote (`summary`): the written cases' schedules at the rate
/// of the LIGGGHTS the study file resolves, measured first by running its first case for at most `probe` seconds
/// when probe > 0 (probe_study; `before_probe` is told what is about to run).
DryRunReport dry_run_report(const std::string& study, const RunSummary& summary, double probe,
                            const std::function<void(const std::string&)>& before_probe);

}  // namespace demsa::exec
