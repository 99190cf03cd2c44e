#pragma once
// `demsa refine` (cli/refine.cpp), its analysis half: how sure the Sobol' indices of a study are, and where the next
// cases go.
//
//   - check_refinement: for every observable, the metamodel with the largest Q² that gave indices with intervals
//     (fit.hpp's ranking), and the largest half-width (upper − lower)/2 of its S1 and ST intervals (those of
//     `[analysis] interval`: the design bootstrap or the GP posterior, sobol/metamodel_sobol.hpp). The loop stops
//     once every observable's is at most the target W.
//   - choose_refinement_points: a Gaussian process (the study's [analysis] GP settings) fitted to each analysable
//     observable, and a batch chosen by the largest summed integrated-variance reduction (ALC: Cohn 1996; Gramacy &
//     Lee 2009) among space-filling candidates kept apart from every sample of the store (sobol::select_by_variance,
//     sobol/augment.hpp). The Sobol' indices are variance ratios of the response integrated over the cube: they
//     are surer where the metamodel's integrated variance is small (directly so for the GP-posterior interval,
//     which draws from that variance). The candidates' correlations use each GP's fitted length scales (ARD), so
//     the points spread along the inputs the response varies fastest in. When no observable admits a GP (too few
//     samples), the batch is a maximin Latin-hypercube extension of the samples instead (sobol::extend_lhs).
#include "orchestrator/analysis/analysis_json.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace demsa::analysis {

/// How sure the indices of one analysis are.
struct RefinementCheck {
  /// Per observable: the largest S1/ST interval half-width of its best metamodel; NaN when no metamodel gave
  /// intervals (a constant observable, too few samples, bootstrap 0).
  std::map<std::string, double> max_half_width;
  std::map<std::string, std::string> model;  ///< the metamodel judged, per observable ("" when none)
  /// {observable: {"model", "max_half_width", "S1": {parameter: [value, lower, upper]}, "ST": {...}}}
  std::string indices_json;
  /// Every observable has a finite half-width at most `target`.
  bool reached(double target) const;
  /// The largest half-width over the observables (NaN when one has none).
  double worst() const;
};

RefinementCheck check_refinement(const AnalysisSummary& summary);

/// `batch` new samples (indices continue the store's) in the study's bounds, chosen as described at the top of this
/// file; deterministic in `seed`.
std::vector<study::SampleRow> choose_refinement_points(const study::StudyConfig& config, const study::Store& store,
                                                       int batch, std::uint64_t seed);

/// DIR/analysis/refine.csv: one row per step (iteration, samples, decision, target, max_half_width_<observable>).
std::string refine_history_csv(const std::vector<study::RefineStep>& steps);
/// DIR/analysis/refine.json: the steps with their indices.
std::string refine_history_json(const std::vector<study::RefineStep>& steps);

}  // namespace demsa::analysis
