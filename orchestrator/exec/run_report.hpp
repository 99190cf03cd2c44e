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
