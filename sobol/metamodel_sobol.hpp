#pragma once
// Sobol' indices of fitted metamodels (paper §6: "the Sobol' indices are determined with the metamodels"):
//   - exactly for a polynomial RSM from its orthonormal Legendre coefficients (Sudret 2008, eq. 32-33):
//       V = Σ_{α≠0} c_α², S_u = Σ_{supp α = u} c_α² / V, ST_i = Σ_{α_i>0} c_α² / V;
//   - for any metamodel by QMC on a Saltelli design (sobol/saltelli.hpp), with a *design bootstrap*: the model is
//     refitted on B resamples of its training points and the indices recomputed, so that the interval carries the
//     metamodel's own uncertainty. The estimate is from the full fit; the interval is the percentile interval of the
//     B replicates moved so that their median sits on the estimate (refits see fewer distinct points, which shifts
//     the replicates; only their spread is used). Each refit is evaluated on its own, independently scrambled
//     Saltelli design of the same N (randomised QMC, Owen 1997; L'Ecuyer & Lemieux 2002), so that the spread also
//     carries the QMC integration error of the estimate, which one shared design would leave out.
//     Interpolators (RBF, GP without nugget) are refitted on the distinct points of each resample (duplicates would
//     make their systems singular); an RSM keeps the duplicates. A GP keeps its hyperparameters (Metamodel::refit).
//   - for a Gaussian process, on request (MetamodelSobolOptions::interval), with the *GP-posterior* interval instead
//   (Le Gratiet, Cannamela & Iooss
//     2014, "A Bayesian approach for global sensitivity analysis of (expensive) computer codes with Gaussian process
//     metamodels", SIAM/ASA J. Uncertainty Quantification 2, 336-363, §3; Marrel, Iooss, Laurent & Roustant 2009,
//     Reliability Engineering & System Safety 94, 742-751): B joint draws of the GP's posterior (its latent function,
//     at the fitted hyperparameters, GaussianProcess::posterior_draws) on the stacked QMC design, the indices of each
//     draw, and the percentile interval of the B draws moved so that their median sits on the estimate (the indices
//     of the posterior mean, as for the other metamodels). That is the uncertainty of the indices that is due to the
//     metamodel not knowing the response between its points: it shrinks where points reduce the posterior
//     variance, which is what the refinement batches target, whereas a design bootstrap shrinks as 1/√n wherever the
//     points are. The integration error of the QMC estimator is added in quadrature to each side (the two errors
//     are independent, law of total variance as in Le Gratiet et al. §3.3): its standard deviation is that of the
//     posterior mean's indices over `qmc_replicates` independently scrambled designs of the same N (randomised QMC,
//     Owen 1997), times the normal quantile of the level. Other metamodels keep the design bootstrap.
#include "sobol/metamodel.hpp"
#include "sobol/rsm.hpp"
#include "sobol/saltelli.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace demsa::sobol {

/// Exact S1, ST, S2 (all pairs) and residual of a fitted RSM; method "rsm-exact", intervals collapsed to the value.
SobolResult rsm_exact_indices(const PolynomialRsm& rsm);

/// How the interval of a metamodel's QMC indices is obtained.
enum class MetamodelInterval {
  /// GP-posterior draws for a Gaussian process (Le Gratiet et al. 2014), the design bootstrap for other metamodels.
  gp_posterior,
  /// The design bootstrap for every metamodel.
  design_bootstrap,
};
/// "gp-posterior" | "design-bootstrap"; throws InputError listing the valid names.
MetamodelInterval metamodel_interval_from_string(const std::string& name);
std::string to_string(MetamodelInterval interval);
/// The canonical names, in enum order.
std::vector<std::string> metamodel_interval_names();

struct MetamodelSobolOptions {
  int base = 16384;           ///< N of the QMC Saltelli design, >= 2
  bool second_order = false;  ///< compute S2
  /// Design-bootstrap refits, or GP-posterior draws, B >= 0 (0: no interval).
  int bootstrap = 100;
  /// See the top of this file. The design bootstrap by default: the GP-posterior interval, at the fitted
  /// hyperparameters, covered the true indices less often than its level in docs/explanation/benchmarks.md.
  MetamodelInterval interval = MetamodelInterval::design_bootstrap;
  int features = 1000;         ///< random Fourier features of the GP-posterior draws, >= 1
  int qmc_replicates = 8;      ///< scrambled designs behind the QMC error of the GP-posterior interval, >= 2
  double confidence = 0.95;    ///< interval level, in (0, 1)
  std::uint64_t seed = 12345;  ///< seed of the QMC design and of the resampling
  bool exact_for_rsm = true;   ///< use rsm_exact_indices for an RSM (and its refits) instead of QMC
  StopCheck stop;              ///< polled between refits and evaluated blocks (empty: never stops)
  void validate() const;       ///< throws InputError naming the field, value and rule
};

/// Indices of a fitted metamodel (method "rsm-exact" or "metamodel-qmc"), intervals from the design bootstrap or, for
/// a GP with options.interval = gp_posterior, from its posterior draws (the result's note says which).
/// When fewer than half of the refits succeed (too few or too clustered training points), the estimates stand
/// without intervals: `bootstrap` is 0 and `note` says how many refits succeeded. Throws NumericalError when the
/// metamodel is constant up to round-off (negligible_variance), Stopped when options.stop says so.
SobolResult metamodel_sobol(const Metamodel& fitted, const MetamodelSobolOptions& options);

}  // namespace demsa::sobol
