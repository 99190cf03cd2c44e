#pragma once
// The names of everything in a study folder and of the files every case folder has (docs/explanation/method.md "A
// study"): every file name has this one home. The files of one experiment's cases (its final dump, its plate files) are
// named in its folder, orchestrator/experiments/NAME/.
#include "orchestrator/util/file_lock.hpp"

#include <filesystem>
#include <memory>
#include <string>

namespace demsa::study {

// ---------------------------------------------------------------- the study folder
inline constexpr const char* k_frozen_study = "study.toml";   ///< frozen copy of the study file
inline constexpr const char* k_store_file = "study.db";       ///< SQLite store (store.hpp)
inline constexpr const char* k_design_file = "design.csv";    ///< unit-cube and physical values per sample
inline constexpr const char* k_cases_folder = "cases";        ///< one folder per sample, case_dir()
inline constexpr const char* k_analysis_folder = "analysis";  ///< analysis/ output
inline constexpr const char* k_report_folder = "report";      ///< report/ output
inline constexpr const char* k_lock_file = ".demsa.lock";     ///< held by the demsa that runs the study
inline constexpr const char* k_cost_probe_file =
    "cost_probe.json";  ///< the probe of `run --dry-run --probe` (exec/cost.hpp)
inline constexpr const char* k_cost_probe_folder = ".cost-probe";  ///< the probe's copy of the first case

// ---------------------------------------------------------------- in the analysis folder (k_analysis_folder)
inline constexpr const char* k_analysis_json = "analysis.json";        ///< everything the analysis found
inline constexpr const char* k_observables_csv = "observables.csv";    ///< the training data
inline constexpr const char* k_replicates_csv = "replicates.csv";      ///< the replicate cases' observables
inline constexpr const char* k_metamodels_json = "metamodels.json";    ///< each metamodel's quality
inline constexpr const char* k_models_folder = "models";               ///< one file per fitted metamodel
inline constexpr const char* k_calibration_json = "calibration.json";  ///< `demsa calibrate` on the metamodels
inline constexpr const char* k_refine_csv = "refine.csv";              ///< `demsa refine`'s steps
inline constexpr const char* k_refine_json = "refine.json";            ///< the steps with their indices
// ---------------------------------------------------------------- in the posterior's folder (DIR/calibration)
inline constexpr const char* k_posterior_folder = "calibration";   ///< `demsa calibrate --method bayes`'s output
inline constexpr const char* k_posterior_json = "posterior.json";  ///< the posterior (analysis/calibration_posterior)

// ---------------------------------------------------------------- a case folder
inline constexpr const char* k_case_input = "in.liggghts";       ///< main LIGGGHTS script
inline constexpr const char* k_case_params = "params.liggghts";  ///< generated variables
inline constexpr const char* k_case_run_script = "run.sh";       ///< runs the case from its folder
inline constexpr const char* k_case_json = "case.json";          ///< what the case is (write_case)
inline constexpr const char* k_case_log = "log.liggghts";        ///< LIGGGHTS log
inline constexpr const char* k_case_screen = "screen.txt";       ///< LIGGGHTS screen output
inline constexpr const char* k_run_output_file = "run.out";      ///< stdout + stderr of ./run.sh
inline constexpr const char* k_result_file = "result.json";      ///< the committed observables
inline constexpr const char* k_case_vtk_folder = "vtk";          ///< final state for ParaView (exec/case_vtk.hpp)

/// The default study folder for a study file: the file's path without ".toml".
inline std::filesystem::path default_study_dir(const std::filesystem::path& study_file) {
  std::filesystem::path dir = study_file;
  dir.replace_extension();
  return dir;
}

/// Throws UserError "DIR: not a study folder (no study.toml and study.db); run `demsa run` first" unless `dir`
/// holds a frozen study file and a store.
void require_study_folder(const std::filesystem::path& dir);

/// Folder of a sample's case: DIR/cases/NNNNNN.
std::filesystem::path case_dir(const std::filesystem::path& study_dir, int sample);

/// Process-wide lock on a study folder (DIR/.demsa.lock, util::FileLock): one demsa at a time writes a study.
class StudyLock {
 public:
  /// Throws util::UserError naming the folder and the holder's pid when another process holds it.
  explicit StudyLock(const std::filesystem::path& dir) : m_lock(dir / k_lock_file) {}
  /// PID of the process that holds the lock on `dir`, or 0 when none does.
  static long holder(const std::filesystem::path& dir) { return util::FileLock::holder(dir / k_lock_file); }

 private:
  util::FileLock m_lock;
};

/// Holds `dir` for a command that reports on the whole study and writes its results (`demsa analyze`, `report`,
/// `calibrate`): throws util::UserError, as StudyLock does, while a `demsa run` holds it. A folder where the lock file
/// cannot be opened for writing (a read-only archive) cannot be held by a run either: it is checked, not held
/// (nullptr).
std::unique_ptr<StudyLock> hold_study_for_results(const std::filesystem::path& dir);

}  // namespace demsa::study
