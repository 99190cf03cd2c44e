#pragma once
// `demsa analyze DIR` (paper §5–6): from the observables committed in a study's store, fits every
// metamodel the study names to each observable on the unit cube, reports R², adjusted R² and leave-one-out Q², and
// computes Sobol' S1, ST (and S2 when asked) with confidence intervals (sobol/metamodel_sobol.hpp: exact Legendre
// indices for the RSMs, QMC with a design bootstrap otherwise). Failed samples are left out and listed.
//
// Files written to DIR/analysis/:
//   observables.csv                 sample, unit-cube values, physical values, one column per observable
//   metamodels.json                 per observable and model: quality (R², adj. R², Q², RMSE_LOO) or the error
//   sobol_<model>.csv / .json       per observable: S1, ST with intervals per parameter (+ S2 in the JSON)
//   models/<observable>.<model>.json every fitted metamodel as a self-contained file (model_file.hpp), for
//                                   `demsa predict`
//   replicates.csv                  with [design] replicates: point, repeat (0: the design case), sample, assembly
//                                   seed, one column per observable
//   table_<observable>.csv          the paper's Tables 4–7 layout: one row per metamodel with indices, S1 per
//                                   parameter and the residual 1 − ΣS1
//   analysis.json                   everything above in one document (samples used, failed samples, settings;
//                                   analysis_json.hpp)
//
// An observable that is constant over its samples (up to round-off: sobol::negligible_variance) has no metamodel and
// no Sobol' index: it is reported as an error of that observable (ObservableAnalysis::error, in analysis.json, the
// printed tables and a warning on standard error) and the other observables are analysed. When no observable gets
// indices from any metamodel, nothing was analysed: analysis_failure() says why, and the commands exit with an
// error after writing the files that record it.
//
// A metamodel whose leave-one-out Q² is not finite (an RSM fitted on as many samples as its terms: it passes through
// every sample and each leave-one-out residual is 0/0; analysis/fit.hpp unmeasurable_error) cannot be judged: it gets
// no Sobol' index (ModelAnalysis::ok false, `fitted` true, its quality kept) and its error, its row of the printed
// table, says "Q² not computable: ..." with a warning on standard error; it is never the best metamodel. When it
// was the only metamodel, analysis_failure() names it.
//
// DEM noise: with [design] replicates, each observable's noise variance is pooled from the replicated points (their
// design case and replicate cases: measured_noise), the GP's nugget is set from it (with_measured_noise), and its
// share of the observable's variance over the design is reported beside the indices (ObservableAnalysis::noise),
// flagged when it dominates (noise_dominates). The metamodels are trained on the design's samples only: replicates
// at a few points would weigh those points more and break the space-filling design that Q² and the design bootstrap
// assume.
//
// Stopping: options.should_stop is polled between observables, metamodels, refits and QMC blocks; once it returns
// true analyze_study throws sobol::Stopped before writing anything, so the folder keeps what it held before.
#include "orchestrator/analysis/analysis_json.hpp"
#include "orchestrator/study/store.hpp"

#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace demsa::analysis {

struct AnalyzeOptions {
  std::filesystem::path dir;            ///< study folder (holds study.toml and study.db)
  std::vector<std::string> metamodels;  ///< empty: the study's [analysis] metamodels
  int bootstrap = -1;                   ///< design-bootstrap refits; -1: the study's value; >= 0 otherwise
  int base_samples = -1;                ///< QMC base N; -1: the study's value; >= 2 otherwise
  int second_order = -1;                ///< S2: -1 the study's setting, 0 no, 1 yes
  std::function<bool()> should_stop;    ///< polled in the long loops; true stops them (empty: never)
  void validate() const;                ///< throws std::invalid_argument naming the field
};

/// The noise of `observable` measured from the study's replicate cases: at each replicated point its design case
/// (the study seed's packing) and its replicates, pooled (sobol::pooled_noise_variance at `confidence`); the share
/// divides by design_sd², the observable's variance over the design samples. Nothing when there are no replicates
/// or no point has two done cases with the observable. largest_s1 is NaN and dominates false (the analysis fills
/// them once the metamodels are fitted).
std::optional<NoiseAnalysis> measured_noise(const std::vector<study::ReplicateRow>& replicates,
                                            const std::map<int, std::map<std::string, double>>& observables,
                                            const std::string& observable, double confidence, double design_sd);

/// `options` with the GP's nugget set from a measured noise (sobol::GpOptions::noise_share = the noise variance over
/// the population variance of `y`, the training outputs); `options` as they are without a noise.
sobol::MetamodelOptions with_measured_noise(sobol::MetamodelOptions options, const std::optional<NoiseAnalysis>& noise,
                                            const Eigen::VectorXd& y);

/// The error of a fitted metamodel whose leave-one-out Q² is not computable ("" when it is): "Q² not computable: "
/// with analysis/fit.hpp unmeasurable_error's reason and what to do.
std::string unmeasurable_text(const sobol::MetamodelSummary& quality);

/// Runs the analysis and writes DIR/analysis/. Throws util::UserError when the folder is not a study or fewer than two
/// samples are done.
AnalysisSummary analyze_study(const AnalyzeOptions& options);

/// A QMC base N as a scrambled Sobol' sequence is balanced: `base` rounded up to a power of two, as [analysis]
/// base_samples and `design saltelli --base` are (Owen 1997; the error at N = 10000 against 8192:
/// docs/explanation/benchmarks.md). `warn` is told when it rounds, naming `field` (AnalyzeOptions.base_samples,
/// DataSensitivityOptions.base). A base <= 0 (the study's value, or none given) is returned as it is.
int balanced_base_samples(int base, const std::string& field, const std::function<void(const std::string&)>& warn);

/// Why nothing was analysed ("" when at least one metamodel of one observable gave indices): one line per observable
/// with its error, or with the errors of its metamodels.
std::string analysis_failure(const AnalysisSummary& summary);

/// One line on the noise of an observable (share with its interval, noise variance, points, cases, degrees of
/// freedom), and a second line "NOISE DOMINATES ..." when it does.
std::string noise_text(const NoiseAnalysis& noise);

/// The paper's table (Tables 4–7) for one observable as aligned text: a header with the parameter names and
/// "Res", one row per metamodel that worked with its S1 values and residual 1 − ΣS1, and R² and Q² columns.
std::string s1_table_text(const AnalysisSummary& summary, const ObservableAnalysis& observable);

/// What `demsa run`, `analyze` and `refine` print after an analysis: the S1 table of every observable, the samples
/// left out and unsettled, and where the analysis is.
std::string analysis_tables_text(const AnalysisSummary& summary);

}  // namespace demsa::analysis
