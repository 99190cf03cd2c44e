#pragma once
// What DIR/analysis/analysis.json holds (written by `demsa analyze`, read back by the report), as plain data, and
// its one JSON form:
//
//   {"study", "parameters": [name, ...], "samples_used": [sample, ...], "samples_left_out": [sample, ...],
//    "seed", "bootstrap", "base_samples", "second_order", "confidence",
//    "observables": [{"name", "samples", "mean", "sd", ["error",]
//                     "models": [{"model", "ok": true, "quality": metamodel, "sobol": Sobol' result}
//                                or {"model", "ok": false, "error"[, "quality"]}, ...]}, ...]}
//
// A model with "ok" false has no indices: its fit failed ("error" says why), or it was fitted ("quality" present) and
// its indices were not computed: a model whose leave-one-out Q² is not finite ("Q² not computable: ...") cannot be
// judged, so it ranks no parameter (study_analysis.hpp).
// "error" is present when the observable itself could not be analysed (a constant observable); "models" is then
// empty. "noise" is present when the study's replicate cases measured the observable ([design] replicates):
//   {"variance", "lower", "upper", "confidence", "points", "values", "dof", "share", "share_lower", "share_upper",
//    "largest_s1", "dominates", "nugget_share"} (NoiseAnalysis).
//
// with the metamodel and Sobol' result forms of sobol_json.hpp (S1, ST and S2 keyed by parameter name).
// Non-finite numbers are written as null and read back as NaN.
#include "sobol/metamodel.hpp"
#include "sobol/noise.hpp"
#include "sobol/saltelli.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demsa::analysis {

/// One metamodel fitted to one observable.
struct ModelAnalysis {
  std::string model;                ///< "rsm2", "rbf-cubic", ...
  bool ok = false;                  ///< false: no indices (the fit failed, or Q² is not computable), see `error`
  bool fitted = false;              ///< the fit succeeded: `quality` holds its R², Q², ... (also when not ok)
  std::string error;                ///< why (too few samples for the model, singular system, ...)
  sobol::MetamodelSummary quality;  ///< R², adjusted R², Q², ...
  sobol::SobolResult indices;       ///< S1, ST, S2, residual with intervals
};

/// The DEM noise of one observable, measured from the study's replicate cases ([design] replicates): the pooled
/// within-point variance (sobol/noise.hpp) and its share of the observable's variance over the design.
struct NoiseAnalysis {
  sobol::NoiseEstimate estimate;  ///< noise variance with its chi-square interval, points, values, dof
  double share = 0.0;             ///< noise variance / variance of the observable over the design samples (sd²)
  double share_lower = 0.0;       ///< estimate.lower / sd² (the design variance taken as known)
  double share_upper = 0.0;       ///< estimate.upper / sd²
  double largest_s1 = 0.0;        ///< the largest S1 of the metamodel of best Q² (NaN when none was fitted)
  /// share > 0.5 or share > largest_s1: the noise explains more of the observable's variance than the parameters
  /// together, or than any one of them (noise_dominates()).
  bool dominates = false;
  double nugget_share = 0.0;  ///< noise variance / the training outputs' variance: the GP's measured nugget
};

/// The flag of NoiseAnalysis::dominates: share > 0.5, or share > largest_s1 (a NaN largest_s1 never flags).
bool noise_dominates(double share, double largest_s1);

/// The one JSON form of a noise (analysis.json's "noise", `demsa sensitivity --json`'s): every field of
/// NoiseAnalysis, non-finite numbers as null.
nlohmann::json noise_json(const NoiseAnalysis& noise);

struct ObservableAnalysis {
  std::string name;             ///< observable name ("angle", "settlement_1", ...)
  int samples = 0;              ///< done samples with this observable
  double mean = 0.0, sd = 0.0;  ///< of the observable over those samples
  std::string error;            ///< why the observable has no analysis at all ("" when it has one), e.g. constant
  std::vector<ModelAnalysis> models;
  std::optional<NoiseAnalysis> noise;  ///< when the study has replicates that measured this observable
};

struct AnalysisSummary {
  std::filesystem::path out_dir;        ///< DIR/analysis (not in the JSON: the folder the file was read from)
  std::string study;                    ///< study name
  std::vector<std::string> parameters;  ///< varied parameters, in the study's order
  std::vector<int> samples_used;        ///< done samples
  std::vector<int> samples_left_out;    ///< not done (failed or never run)
  /// Done samples stored as unsettled (still moving at the end: study::unsettled_samples), analysed all the same,
  /// and the same as a list for people with their drifts (experiments::unsettled_text).
  std::vector<int> samples_unsettled;
  std::string unsettled;
  std::vector<ObservableAnalysis> observables;
  std::uint64_t seed = 0;  ///< the study seed, used for the QMC designs and the bootstrap
  int bootstrap = 0;
  int base_samples = 0;
  bool second_order = false;
  double confidence = 0.0;  ///< level of the Sobol' intervals
};

/// The text of analysis.json (two-space indentation, a final newline).
std::string analysis_to_json(const AnalysisSummary& summary);

/// analysis.json read back; out_dir is the file's folder. Throws util::UserError naming the file when it cannot be
/// read or is not an analysis file.
AnalysisSummary read_analysis(const std::filesystem::path& file);

}  // namespace demsa::analysis
