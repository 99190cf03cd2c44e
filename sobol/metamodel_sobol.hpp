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
#include "sobol/metamodel.hpp"
#include "sobol/rsm.hpp"
#include "sobol/saltelli.hpp"

#include <cstdint>

namespace demsa::sobol {

/// Exact S1, ST, S2 (all pairs) and residual of a fitted RSM; method "rsm-exact", intervals collapsed to the value.
SobolResult rsm_exact_indices(const PolynomialRsm& rsm);

struct MetamodelSobolOptions {
  int base = 16384;            ///< N of the QMC Saltelli design, >= 2
  bool second_order = false;   ///< compute S2
  int bootstrap = 100;         ///< design-bootstrap refits B, >= 0 (0: no interval)
  double confidence = 0.95;    ///< interval level, in (0, 1)
  std::uint64_t seed = 12345;  ///< seed of the QMC design and of the resampling
  bool exact_for_rsm = true;   ///< use rsm_exact_indices for an RSM (and its refits) instead of QMC
  StopCheck stop;              ///< polled between refits and evaluated blocks (empty: never stops)
  void validate() const;       ///< throws InputError naming the field, value and rule
};

/// Indices of a fitted metamodel (method "rsm-exact" or "metamodel-qmc"), intervals from the design bootstrap.
/// When fewer than half of the refits succeed (too few or too clustered training points), the estimates stand
/// without intervals: `bootstrap` is 0 and `note` says how many refits succeeded. Throws NumericalError when the
/// metamodel is constant up to round-off (negligible_variance), Stopped when options.stop says so.
SobolResult metamodel_sobol(const Metamodel& fitted, const MetamodelSobolOptions& options);

}  // namespace demsa::sobol
