// A study's cases as the runner writes them, and a study measured again after a change of measurement settings
// (remeasure.hpp).
#include "orchestrator/exec/remeasure.hpp"

#include "orchestrator/exec/measure.hpp"
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/process.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <exception>
#include <utility>

namespace demsa::exec {

namespace fs = std::filesystem;
using namespace demsa::study;
using util::write_file_atomically;

std::map<int, StudyCase> study_cases(const Store& store, std::vector<int>* order) {
  std::map<int, StudyCase> cases;
  for (const SampleRow& s : store.samples()) {
    cases[s.sample] = StudyCase{s, std::nullopt};
    if (order) order->push_back(s.sample);
  }
  for (const ReplicateRow& r : store.replicates()) {
    cases[r.sample] = StudyCase{SampleRow{r.sample, r.unit, r.physical}, r};
    if (order) order->push_back(r.sample);
  }
  return cases;
}

cases::CaseRequest case_request(const StudyConfig& config, const StudyCase& study_case) {
  cases::CaseRequest request = cases::request_from_unit_point(config, study_case.sample.sample, study_case.sample.unit);
  request.demsa_executable = util::self_executable();
  if (study_case.replicate) {
    request.replicate_point = study_case.replicate->point;
    request.replicate_repeat = study_case.replicate->repeat;
    request.assembly_seed = study_case.replicate->seed;
  }
  return request;
}

namespace {

/// A LIGGGHTS input without its comments ('#' to the end of a line) and blank lines: what LIGGGHTS reads of it.
std::string without_comments(const std::string& text) {
  std::string out;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    std::string line = text.substr(start, std::min(text.find('#', start), end) - start);
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    if (!line.empty()) out += line + "\n";
    start = end + 1;
  }
  return out;
}

/// The files of the case `written` that LIGGGHTS would read differently from `folder`'s (or that `folder` lacks):
/// compared without their comments, which name docs and may change between versions of demsa. case.json (what is
/// measured) and run.sh (which LIGGGHTS binary runs it) are left out.
std::vector<std::string> differing_inputs(const fs::path& written, const fs::path& folder) {
  std::vector<std::string> differ;
  for (const fs::directory_entry& e : fs::directory_iterator(written)) {
    const std::string name = e.path().filename().string();
    if (name == k_case_json || name == k_case_run_script) continue;
    const fs::path there = folder / name;
    if (!fs::is_regular_file(there) ||
        without_comments(util::read_file(there)) != without_comments(util::read_file(e.path())))
      differ.push_back(name);
  }
  return differ;
}

}  // namespace

RemeasureSummary remeasure_study(const StudyConfig& config, Store& store, const fs::path& dir,
                                 const std::vector<std::string>& changed) {
  RemeasureSummary summary;
  summary.keys = changed;
  const std::map<int, StudyCase> cases = study_cases(store);
  // The latest run of each case: only a done one, or one that ran and failed in its measurement, has files to read.
  std::map<int, RunRow> latest;
  for (const RunRow& run : store.runs()) latest[run.sample] = run;
  struct Planned {
    int sample = 0;
    RemeasuredCase result;
    fs::path folder;
    std::string case_json;
  };
  std::vector<Planned> planned;
  const fs::path scratch = dir / ".remeasure";
  fs::remove_all(scratch);
  for (const auto& [sample, run] : latest) {
    const bool done = run.state == RunState::done;
    if (!done && !(run.state == RunState::failed && run.failure == FailureClass::measurement)) continue;
    const auto it = cases.find(sample);
    if (it == cases.end()) continue;
    const fs::path folder = case_dir(dir, sample);
    // The case as the new settings write it, beside its folder: every LIGGGHTS input must be the one that ran.
    const fs::path written = scratch / fs::path(folder).filename();
    cases::write_case(config, case_request(config, it->second), written);
    const std::vector<std::string> differ = differing_inputs(written, folder);
    if (!differ.empty())
      throw util::UserError(fmt::format(
          "{}: the study file changes how case {} is written ({} differ{}), not only how it is measured: run it "
          "again with `demsa run --new`, or choose another --dir",
          dir.string(), sample, util::join(differ), differ.size() == 1 ? "s" : ""));
    Planned p;
    p.sample = sample;
    p.folder = folder;
    p.case_json = util::read_file(written / k_case_json);
    p.result.run = run.id;
    // The case's own files, measured under the case.json the new settings write (the folder's is replaced below).
    const nlohmann::json doc = experiments::read_case_json(written);
    try {
      p.result.observables = measure_case(folder, doc);
      p.result.message = "measured again under the study file's new measurement settings";
      if (!done) ++summary.recovered;
    } catch (const std::exception& e) {
      if (done && !fs::exists(folder / k_case_log))
        throw util::UserError(
            fmt::format("{}: case {} is done but its files are gone ({}), so it cannot be measured "
                        "again: run the study again with `demsa run --new`, or choose another --dir",
                        dir.string(), sample, e.what()));
      p.result.message = e.what();
      ++summary.failed;
    }
    ++summary.measured;
    planned.push_back(std::move(p));
  }
  // Commit: the store first (one transaction), then each case's case.json and result.json. A demsa stopped in between
  // leaves an older case.json in a case the store counts as measured anew; nothing reads it but a later measurement.
  std::vector<RemeasuredCase> results;
  for (const Planned& p : planned) results.push_back(p.result);
  store.record_remeasured(
      design_hash(config), results,
      fmt::format("{} finished case(s) measured again ({} failed, {} measured now that had failed): {}",
                  summary.measured, summary.failed, summary.recovered, util::join(changed, "; ")));
  for (const Planned& p : planned) {
    write_file_atomically(p.folder / k_case_json, p.case_json);
    if (p.result.observables) {
      nlohmann::json result;
      result["sample"] = p.sample;
      result["run"] = p.result.run;
      result["observables"] = *p.result.observables;
      result["remeasured"] = true;
      write_file_atomically(p.folder / k_result_file, result.dump(2) + "\n");
    } else {
      fs::remove(p.folder / k_result_file);  // not done any more: the runner runs it again
    }
  }
  fs::remove_all(scratch);
  return summary;
}

}  // namespace demsa::exec
