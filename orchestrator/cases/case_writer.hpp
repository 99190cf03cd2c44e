#pragma once
// One LIGGGHTS case folder per sample (docs/explanation/method.md "A study" and docs/how-to/case-by-hand.md; paper
// §3–4): what every case has — a generated params.liggghts with every physical value, the system and contact includes
// (embedded in demsa from liggghts_templates/), run.sh and case.json — around what its experiment writes
// (orchestrator/experiments/: its input script, particles and geometry). A person runs it with `cd DIR && ./run.sh`.
//
// Files written by LIGGGHTS (or by the demsa command an experiment runs in-process) in the folder: log.liggghts,
// screen.txt and the experiment's final dump and outputs (study/folder.hpp and the experiment's folder name them).
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/folder.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace demsa::cases {

/// Empties the case folder `folder` for a new attempt of its case: afterwards `folder` does not exist. A task of an
/// earlier attempt may still be shutting down and writing there (a cancelled SLURM task's mpirun writing its last
/// lines), so removing the folder in place can fail ("Directory not empty") or leave its files in the new attempt:
/// the folder is renamed into the hidden `.stale/` beside it first (atomic; the old processes go on writing into the
/// renamed folder), and then everything in `.stale/` that can be removed is. Throws util::IoError when the folder
/// cannot be moved.
void clear_case_folder(const std::filesystem::path& folder);

/// What to write: one sample of a study (or a hand-set parameter tuple).
struct CaseRequest {
  int sample = 0;                          ///< sample index in the design (-1: values set by hand; null in case.json)
  std::vector<double> unit_point;          ///< the sample in [0,1]^d, ordered as config.parameters
  std::vector<double> physical;            ///< physical values, ordered as config.parameters
  std::filesystem::path demsa_executable;  ///< absolute path of demsa (run.sh of a trial-step oedometer calls it)
  std::string liggghts_version;            ///< recorded in case.json; empty: unknown
  /// A replicate case ([design] replicates): the design point it repeats (-1: not a replicate), its repeat number and
  /// the seed of its particle packing (radii and positions), used instead of the study seed. case.json records them
  /// as "replicate": {"point", "repeat", "assembly_seed"}.
  int replicate_point = -1;
  int replicate_repeat = 0;
  std::uint64_t assembly_seed = 0;
};

/// The assembly seed of repeat `repeat` (>= 1) of design point `point`: SplitMix64 (Steele, Lea, Flood, "Fast
/// splittable pseudorandom number generators", OOPSLA 2014) of the study seed, the point and the repeat, so that
/// every replicate of a study has its own packing and the same one on every machine. Never the study seed itself.
std::uint64_t replicate_assembly_seed(std::uint64_t study_seed, int point, int repeat);

/// What was written (also recorded in case.json).
struct CaseSummary {
  std::filesystem::path dir;   ///< the case folder
  study::Material material;    ///< the sample's contact parameters and density
  double dt = 0.0;             ///< time step [s]
  double rayleigh_time = 0.0;  ///< T_R of the smallest particle [s]
  std::string dt_source;       ///< "rayleigh" (fraction * T_R) or "fixed"
  long particles = 0;          ///< particles of the assembly
  std::string final_dump;      ///< file name of the final dump
};

/// What write_case does with a case folder that already holds files (for example the dump and logs of an earlier
/// ./run.sh, which would no longer match the new case.json).
enum class ExistingCaseFiles {
  rewrite,  ///< write the case's files over the folder's; files of other names stay. For callers that empty or
            ///< remove the folder themselves before (demsa run's per-sample folders on every attempt).
  refuse,   ///< throw util::UserError naming the folder and a few of its files when it is not empty (demsa case)
  remove,   ///< remove everything in the folder first (demsa case --overwrite); refused when the folder holds
            ///< the study file itself
};

/// Writes the case folder `dir` (created if missing; a folder that already holds files is handled as `existing`
/// says). Deterministic: the same study and request give byte-identical input files. Throws util::UserError when the
/// sample's settings break a LIGGGHTS limit (time step, servo speed, Young's modulus range), naming the limit and
/// the values, and when `dir` is a file or (with `refuse`) a non-empty folder. Nothing is written or removed
/// when it throws.
CaseSummary write_case(const study::StudyConfig& config, const CaseRequest& request, const std::filesystem::path& dir,
                       ExistingCaseFiles existing = ExistingCaseFiles::rewrite);

/// A CaseRequest from explicit parameter values `name=value` (names from contact_parameter_names(); the varied
/// parameters not named take the middle of their range, the others config.material). Throws util::UserError on an
/// unknown name or a value outside a varied parameter's range.
CaseRequest request_from_values(const study::StudyConfig& config,
                                const std::vector<std::pair<std::string, double>>& values);

/// A CaseRequest for a unit-cube point (ordered as config.parameters; each coordinate in [0,1]).
CaseRequest request_from_unit_point(const study::StudyConfig& config, int sample,
                                    const std::vector<double>& unit_point);

}  // namespace demsa::cases
