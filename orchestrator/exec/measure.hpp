#pragma once
// The observables of a finished case folder, measured as its experiment measures them (Experiment::measure) from the
// case's files and the case.json it was written with: `demsa run`, `calibrate --verify` and `demsa measure` all
// measure a case through this one function, so a case run by hand is measured exactly as a study would measure it.
#include "orchestrator/experiments/experiment.hpp"
#include "orchestrator/study/parameters.hpp"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace demsa::exec {

/// Measures the finished case folder `folder`: its case.json names the experiment, whose measure() reads the case's
/// files. Throws util::UserError on a missing or malformed case.json, and postprocess::ParseError / InputError on a
/// dump or plate file that cannot be measured.
std::map<std::string, double> measure_case(const std::filesystem::path& folder);
/// The same under the case.json `doc` instead of the folder's (a study measured again under new measurement
/// settings, remeasure.hpp); messages name the folder's case.json.
std::map<std::string, double> measure_case(const std::filesystem::path& folder, const nlohmann::json& doc);

/// One observable of a measured case, as the study stores it.
struct MeasuredValue {
  study::Observable observable;  ///< name, label, units (experiments::describe_observable)
  double value = 0.0;            ///< in observable.stored_unit
};

/// What `demsa measure CASE` prints: the case's experiment and its observables by name.
struct CaseMeasurement {
  std::string experiment;
  std::vector<MeasuredValue> values;
};

/// measure_case(folder), with each value described.
CaseMeasurement measure_case_described(const std::filesystem::path& folder);

/// `demsa measure CASE --photograph FILE`: the finished case folder against a laboratory file of its experiment (a
/// drum's photograph), the two superimposed in `picture` (default: CASE/lab_overlay.png). Throws util::UserError when
/// the case's experiment has no laboratory file or the file is not of its kind.
experiments::LabComparison compare_case_with_lab_file(const std::filesystem::path& folder,
                                                      const std::filesystem::path& file,
                                                      std::filesystem::path picture = {});

/// Refuses (util::UserError naming MeasureReportOptions.overlay), before anything is measured, a `picture` whose folder
/// does not exist or cannot be written, that is a folder, the laboratory file itself, one of the case's run outputs, or
/// an existing file that is not a PNG: the overlay is written over it.
void check_overlay_path(const std::filesystem::path& picture, const std::filesystem::path& lab_file,
                        const std::filesystem::path& folder, const experiments::Experiment& experiment);

/// What `demsa measure PATH` prints, as text and as JSON.
struct MeasureReport {
  std::string text;
  std::string json;
};

/// What `demsa measure` measures: a finished case folder (measure_case_described), a regular file measured as a
/// laboratory file by the experiment whose files have its extension (experiments::for_lab_file), or, with `lab_file`,
/// the case folder against that laboratory file (compare_case_with_lab_file, the two superimposed in `overlay`).
struct MeasureReportOptions {
  std::filesystem::path path;      ///< a case folder or a laboratory file
  std::filesystem::path lab_file;  ///< empty: `path` alone
  std::filesystem::path overlay;   ///< with `lab_file`: the PNG of the two superimposed (empty: CASE/lab_overlay.png)
};

/// Measures what the options name. Throws util::UserError for a regular file that no experiment measures.
MeasureReport measure_report(const MeasureReportOptions& options);

}  // namespace demsa::exec
