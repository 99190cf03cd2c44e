#pragma once
// Calibration on metamodels (ARCHITECTURE.md "sobol/"): find x in a box of [0,1]^d minimising the weighted misfit
//   J(x) = Σ_k w_k ((m_k(x) - t_k) / s_k)²
// between metamodel predictions m_k and targets t_k (s_k a scale, e.g. the measurement's uncertainty or the
// target itself), by a global NLopt pass followed by a local one from its best point (NLopt: Johnson, "The NLopt
// nonlinear-optimization package"; DIRECT-L: Gablonsky & Kelley 2001; BOBYQA: Powell 2009).
#include "sobol/metamodel.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace demsa::sobol {

/// One measured value to match with one fitted metamodel.
struct CalibrationTarget {
  std::string name;                  ///< observable name (for messages and results)
  const Metamodel* model = nullptr;  ///< fitted metamodel of this observable (not owned)
  double value = 0.0;                ///< target t_k
  double weight = 1.0;               ///< w_k >= 0
  double scale = 1.0;                ///< s_k > 0
};

enum class GlobalAlgorithm { direct_l, crs2, isres, mlsl_lds, none };
/// "direct-l" | "crs2" | "isres" | "mlsl-lds" | "none"; throws InputError listing the valid names.
GlobalAlgorithm global_algorithm_from_string(const std::string& name);
std::string to_string(GlobalAlgorithm algorithm);

enum class LocalAlgorithm { bobyqa, nelder_mead, sbplx, cobyla, none };
/// "bobyqa" | "nelder-mead" | "sbplx" | "cobyla" | "none"; throws InputError listing the valid names.
LocalAlgorithm local_algorithm_from_string(const std::string& name);
std::string to_string(LocalAlgorithm algorithm);

struct CalibrationOptions {
  /// Box on the unit cube, one entry per input; empty: [0,1] for every input. lower < upper, both in [0,1].
  std::vector<double> lower;
  std::vector<double> upper;
  GlobalAlgorithm global = GlobalAlgorithm::direct_l;  ///< global pass (none: skip it)
  LocalAlgorithm local = LocalAlgorithm::bobyqa;       ///< local pass from the global optimum (none: skip it)
  int global_evaluations = 4000;                       ///< budget of the global pass, >= 1
  int local_evaluations = 2000;                        ///< budget of the local pass, >= 1
  double tolerance = 1e-10;                            ///< relative tolerance on x for the local pass, > 0
  std::uint64_t seed = 12345;                          ///< NLopt's seed (stochastic global algorithms)
  void validate(int dimension) const;                  ///< throws InputError naming the field, value and rule
};

/// Plain data (serialise every field).
struct CalibrationResult {
  std::vector<double> x;            ///< optimum on the unit cube (map with sobol/scaling.hpp)
  std::vector<std::string> names;   ///< target names
  std::vector<double> targets;      ///< t_k
  std::vector<double> predictions;  ///< m_k(x)
  double misfit = 0.0;              ///< J(x)
  double global_misfit = 0.0;       ///< J after the global pass
  int evaluations = 0;              ///< misfit evaluations, both passes
  std::string global_algorithm;
  std::string local_algorithm;
  std::uint64_t seed = 0;
};

/// Throws InputError for no targets, an unfitted model, models of different dimensions, a bad weight or scale.
CalibrationResult calibrate(const std::vector<CalibrationTarget>& targets, const CalibrationOptions& options);

}  // namespace demsa::sobol
