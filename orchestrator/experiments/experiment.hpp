#pragma once
// An experiment is a plug-in, as a LAMMPS pair or fix style is: one descriptor (this struct) says everything demsa
// needs to know of it — its settings rows, how it writes a case, how it measures a finished case, its observables
// and their units, what it leaves in the case folder, its figures in the report and its ParaView surfaces — and one
// list (registry.hpp) holds the descriptors. The rest of demsa asks the registry; no code outside
// orchestrator/experiments/ switches on an experiment's name. ARCHITECTURE.md, "Adding an experiment", is the
// recipe.
#include "orchestrator/experiments/angle_of_repose.hpp"
#include "orchestrator/experiments/case_files.hpp"
#include "orchestrator/experiments/case_report.hpp"
#include "orchestrator/experiments/case_tool.hpp"
#include "orchestrator/experiments/physics.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/failure_class.hpp"
#include "orchestrator/study/parameters.hpp"
#include "orchestrator/study/settings.hpp"
#include "postprocess/dump.hpp"
#include "postprocess/vtk.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace demsa::experiments {

/// What an experiment's case writer adds to case.json and tells the runner.
struct CaseWritten {
  long particles = 0;                 ///< atoms the case creates (the lost-particle check counts against it)
  nlohmann::ordered_json assembly;    ///< case.json "assembly": how the particles were drawn
  nlohmann::ordered_json experiment;  ///< case.json under the experiment's name: its schedule and measurement
};

/// One case of an experiment between drawing its particles and writing its files: the common writer
/// (cases/case_writer.hpp) draws it first, since its smallest particle sets the time step, checks the LIGGGHTS limits,
/// and only then lets it write.
class CaseDraft {
 public:
  virtual ~CaseDraft() = default;
  /// The smallest particle radius of the case [m] (its Rayleigh time sets the time step).
  virtual double smallest_radius() const = 0;
  /// Writes the experiment's files into `dir` (in.liggghts, its includes, particle data, geometry) and its variables
  /// into `params` (written as params.liggghts after the common ones); the folder exists.
  virtual CaseWritten write(const study::Material& material, const TimestepChoice& timestep, Params& params,
                            const std::filesystem::path& dir) const = 0;
};

/// A case output the runner judges a failure (beyond a missing final dump and lost particles).
struct OutputProblem {
  study::FailureClass failure = study::FailureClass::missing_dump;
  std::string message;
  /// The outputs of a case that ran to its end say the settings cannot reach the goal (a load the servo plate never
  /// reached in its cap): a run on one rank repeats itself to the last digit, so a retry ends the same way.
  bool final = false;
};

/// What one written case costs by its schedule (exec/cost.hpp adds them up into a study's bill). An atom-step is one
/// atom advanced by one time step: LIGGGHTS's work per step grows with the atoms present, so `atom_steps` is the sum
/// over the schedule's runs of steps × atoms present (the `S steps with M atoms` of its log's `Loop time` lines).
struct CaseCost {
  /// The schedule's cap: every run to its end with every atom it creates (with the atoms that can stay in the case,
  /// when it removes the others: a pile's pedestal carries only so many)
  double atom_steps = 0.0;
  long steps = 0;      ///< time steps of the whole schedule (its cap)
  long particles = 0;  ///< atoms at the end of the schedule when none is removed
  /// The case may end before its cap (a settling or stop criterion) or lose atoms on purpose (particles removed):
  /// the estimate then takes the ratio of actual to cap from the study's finished cases.
  bool may_end_early = false;
  std::string schedule;  ///< one line: how the cap was counted ("9 discs of 953 atoms, then 14 appended...")
  /// What the case is expected to cost when its experiment has a measured model of when it ends (0: none, the bill
  /// takes the cap): the servo oedometer's simulated time per load (oedometer/cost.cpp). At most `atom_steps`. The
  /// study's finished cases then correct it by their ratio of actual to expected.
  double expected_atom_steps = 0.0;
  std::string expected;  ///< one line: how `expected_atom_steps` was counted and where its constants were measured
  /// How many finished cases the model weighs as against the study's own (Bühlmann's credibility k: one case's
  /// variance of actual / expected over the model's variance from study to study): the finished cases' ratio counts
  /// n / (n + k).
  double expected_weight = 0.0;
  /// The experiment's atom-steps per CPU-second over the standard run's (exec/cost.hpp) with the same LIGGGHTS on the
  /// same machine, measured (1: none measured): the bill's rate before the study has one of its own.
  double rate_factor = 1.0;
  std::string rate_factor_source;  ///< one line: the studies and the standard run it was measured from
};

/// A figure of one case in the report: its caption, the file stem of its plot, and the plot's data.
struct CaseFigure {
  std::string caption;
  std::string stem;  ///< file name without extension inside report/
  CaseFigureData data;
};

/// The report's section on one case (the sample closest to the experiment's target).
struct CaseReport {
  std::string heading;
  std::vector<std::string> paragraphs;
  std::vector<CaseTable> tables;
  std::vector<CaseFigure> figures;
  std::vector<std::string> notes;  ///< what could not be shown, and why
};

/// Where the report looks first: the observable whose value picks the case shown, and the value aimed at (none: the
/// median of the study's values).
struct ReportFocus {
  std::string observable;
  std::optional<double> value;
};

/// A named surface of a case for ParaView (exec/case_vtk.hpp writes NAME.vtp).
struct CaseSurface {
  std::string name;  ///< "pedestal", "box"
  /// None: the case has no such surface yet (an oedometer's plate before its first load), and a NAME.vtp of an earlier
  /// state is removed.
  std::optional<postprocess::Surface> surface;
};

/// A hidden demsa command that runs a case of the experiment in-process (Experiment::drivers).
struct Driver {
  std::string_view command;      ///< "drive-oedometer"
  std::string_view description;  ///< for `demsa --help` of developers
  int (*run)(const std::filesystem::path& case_dir);
};

/// One value of a laboratory file, under the name of a case's observable (stored units).
struct LabValue {
  std::string name;
  double value = 0.0;
  std::optional<double> uncertainty;  ///< ± in the same unit, when the file gives one (a surface's band)
};

/// What `demsa measure FILE` reads from a laboratory file of an experiment (a drum's photograph), measured by the code
/// that measures its cases.
struct LabMeasurement {
  std::vector<LabValue> values;
  std::vector<std::string> notes;  ///< how it was measured: the settings file used, the geometry
};

/// A finished case set beside a laboratory file of its experiment (`demsa measure CASE --photograph FILE`).
struct LabComparison {
  double mismatch_m2 = 0.0;       ///< the area where the two disagree about material [m²]
  std::string region;             ///< where it is counted ("within 0.77 R")
  std::filesystem::path picture;  ///< the two superimposed (written)
  /// The laboratory file measured on its own, as `demsa measure FILE` reads it (written beside `picture`, its stem
  /// followed by "_photograph"): what the comparison stands on. Empty when the experiment draws none.
  std::filesystem::path lab_picture;
};

/// The defaults of the descriptor's optional hooks: an experiment states only what differs.
inline std::map<std::string, std::string> no_retired_keys() { return {}; }
inline std::string no_driver_command(const study::StudyConfig&) { return {}; }
inline std::vector<Driver> no_drivers() { return {}; }
inline long no_removed_particles(const std::filesystem::path&) { return 0; }

/// The descriptor of one experiment. Every hook is a plain function of the experiment's folder; none may be null
/// unless its comment says so. A hook with a default (`= ...`) may be left out of an experiment's initialiser.
struct Experiment {
  std::string_view name;     ///< the value of `[study] experiment`, the key of its section in case.json: "pile"
  std::string_view summary;  ///< for the docs of `[study] experiment`: "angle of repose of a pile, paper §3"

  // ---------------------------------------------------------------- the study file
  /// Its sections (docs order) with their prose for docs/reference/study-file.md.
  std::vector<study::SettingSection> (*sections)();
  /// Its rows (settings.hpp, built with setting_row.hpp).
  std::vector<study::Setting> (*settings)();
  /// The rules that tie its keys together, checked when one of its sections is read; may be null.
  void (*check)(const study::StudyConfig& config, const study::SectionCheck& at) = nullptr;
  /// Keys an earlier demsa read in its sections, each with its hint.
  std::map<std::string, std::string> (*retired_keys)() = no_retired_keys;

  // ---------------------------------------------------------------- the case
  /// Draws the case's particles (identical for every sample: they depend only on the settings and `assembly_seed`).
  std::unique_ptr<CaseDraft> (*draft)(const study::StudyConfig& config, std::uint64_t assembly_seed);
  /// The LIGGGHTS limits of the experiment that the sample breaks, one sentence each (beyond the common ones of
  /// physics.hpp); may be null.
  std::vector<std::string> (*limit_violations)(const study::StudyConfig& config, const study::Material& material,
                                               const TimestepChoice& timestep) = nullptr;
  /// The hidden demsa command that runs the case in-process instead of LIGGGHTS on in.liggghts ("" for LIGGGHTS),
  /// e.g. the trial-step oedometer's `drive-oedometer`: one of `drivers`.
  std::string (*driver_command)(const study::StudyConfig& config) = no_driver_command;
  /// The hidden commands of its in-process drivers (`demsa NAME CASE_DIR`, started by run.sh under mpirun), each with
  /// its one-line description and the function that runs a case folder and returns the exit status.
  std::vector<Driver> (*drivers)() = no_drivers;
  /// The particle count and the largest radius the settings give (a study's lost-particle and kinetic-energy
  /// limits before any case is written) [m].
  long (*particles)(const study::StudyConfig& config);
  double (*largest_radius)(const study::StudyConfig& config);

  // ---------------------------------------------------------------- the measurement
  /// The final dump of a finished case (file name in the case folder).
  std::string_view final_dump;
  /// Every file a run writes besides log.liggghts and screen.txt (the final dump among them), for the messages that
  /// name a case folder's outputs.
  std::vector<std::string> (*run_outputs)();
  /// The observables of a finished case folder, from its files and its case.json (`case_json`, already read):
  /// the analysed ones of observables() and any recorded ones. Throws postprocess::ParseError / InputError on a file
  /// that cannot be measured and util::UserError on a case.json that lacks what it needs.
  std::map<std::string, double> (*measure)(const std::filesystem::path& folder, const nlohmann::json& case_json);
  /// The observables the analysis fits, in table order, as the settings give them.
  std::vector<study::Observable> (*observables)(const study::StudyConfig& config);
  /// Every observable name it may store (analysed or recorded only), with label and unit: the catalogue of
  /// describe_observable(). A name may be a pattern's instance (settlement_K): `describe` answers for any name.
  std::optional<study::Observable> (*describe)(std::string_view name);
  /// Particles a finished case removed on purpose (not lost), from its folder; 0 when it removes none.
  long (*removed_particles)(const std::filesystem::path& folder) = no_removed_particles;
  /// A problem with the outputs of a case that ran cleanly (an oedometer load not reached), or none; may be null.
  std::optional<OutputProblem> (*check_outputs)(const std::filesystem::path& folder,
                                                const study::StudyConfig& config) = nullptr;

  // ---------------------------------------------------------------- calibration, report, ParaView
  /// The targets of `demsa calibrate` when none are given: (observable, value) pairs from the settings. Throws
  /// util::UserError naming the file and the field to give (analysis::CalibrateOptions::targets, written
  /// "CalibrateOptions.targets", which a command line writes as its option) when the settings have none.
  std::vector<std::pair<std::string, double>> (*default_targets)(const study::StudyConfig& config);
  /// The observables a laboratory measures in this experiment (an angle of repose; not a DEM pile's height, which
  /// depends on how much was poured): what `demsa plan` assumes measured when no --observe is given.
  std::vector<std::string> (*lab_observables)(const study::StudyConfig& config);
  /// The observable (and value) by which the report chooses the case it shows.
  ReportFocus (*report_focus)(const study::StudyConfig& config);
  /// The report's section on one finished case `folder` (of sample `sample`; `relative` is its path as the report
  /// names it). Throws on files it cannot read (the report notes it and goes on).
  CaseReport (*case_report)(const std::filesystem::path& folder, const std::string& relative, int sample,
                            const study::StudyConfig& config);
  /// The geometry of a finished case for ParaView, from its folder, case.json and final frame.
  std::vector<CaseSurface> (*vtk_surfaces)(const std::filesystem::path& folder, const nlohmann::json& case_json,
                                           const postprocess::DumpFrame& final_frame);

  // ---------------------------------------------------------------- cost
  /// The atom-steps of a written case by its schedule, from its case.json (`case_json`, read from `file`: its time
  /// step, its particles and what the experiment records of its schedule) and the study's settings; may be null (no
  /// estimate for the experiment). `probed` is what the study's probe learnt of the case it ran (probe_state), null
  /// without a probe: a model may take from it what no case.json knows before its run. Throws util::UserError naming
  /// `file` when case.json lacks what it needs.
  CaseCost (*case_cost)(const study::StudyConfig& config, const nlohmann::json& case_json,
                        const std::filesystem::path& file, const nlohmann::json& probed) = nullptr;
  /// What a probe (`demsa run --dry-run --probe SECONDS`) learnt of its case by the end of its budget, read from the
  /// probe's folder before it is removed (an oedometer's settled packing, once its fill is done): JSON that case_cost
  /// reads back as `probed`, null when it learnt nothing; may be null (case_cost takes nothing from a probe). Throws
  /// postprocess::ParseError on a file of the case it cannot read.
  nlohmann::json (*probe_state)(const std::filesystem::path& folder) = nullptr;

  // ---------------------------------------------------------------- laboratory files
  /// The extensions (lower case, with the dot: ".bmp") of the laboratory files it measures; none: it measures none.
  std::vector<std::string_view> lab_file_extensions = {};
  /// Measures a laboratory file (one of lab_file_extensions) under its cases' observable names, finding what else it
  /// needs beside the file; may be null when it measures none. Throws util::UserError naming the file (and the line of
  /// a settings file) on input it cannot measure.
  LabMeasurement (*measure_lab_file)(const std::filesystem::path& file) = nullptr;
  /// Compares a finished case with a laboratory file of the same setup and writes the two superimposed to `picture`
  /// (null when the experiment has no laboratory file).
  LabComparison (*compare_with_lab_file)(const std::filesystem::path& case_dir, const nlohmann::json& case_json,
                                         const std::filesystem::path& file,
                                         const std::filesystem::path& picture) = nullptr;

  // ---------------------------------------------------------------- one case outside a study run
  /// The angle of repose of a finished case as `demsa postprocess` and `demsa compare` measure it: the angle options
  /// its case.json (`case_json`, read from `file`) records, but for the caller's choices, and its base layer; null
  /// when the experiment measures no angle of repose. Throws util::UserError naming `file` (and the fields
  /// PileAngleOptions.pedestal_radius and .pedestal_top when the case records no pedestal).
  CaseAngle (*case_angle)(const nlohmann::json& case_json, const std::filesystem::path& file,
                          const ChosenAngleOptions& chosen) = nullptr;
  /// Its own tool, `demsa postprocess NAME` (case_tool.hpp): one case's files measured outside a study run; none
  /// when `make` is null.
  CaseToolEntry case_tool = {};
};

}  // namespace demsa::experiments
