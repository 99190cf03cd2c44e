#pragma once
// Designs of experiments on the unit cube [0,1]^d (rows are samples, columns are inputs): Latin hypercubes (paper
// §5: "The DOE is performed with the Latin-Hypercube-sampling"), optimised Latin hypercubes, a scrambled Sobol'
// sequence, and the space-filling metrics used to compare them. Scale the result to physical bounds with
// sobol/scaling.hpp. Every random choice comes from Options::seed, echoed in the result.
#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace demsa::sobol {

enum class DesignKind {
  lhs,          ///< plain LHS: a uniform random point inside each stratum (McKay, Beckman, Conover 1979)
  lhs_centred,  ///< LHS with every point at the centre of its stratum
  lhs_maximin,  ///< LHS optimised for the maximin criterion φ_p (Morris & Mitchell 1995), p = Options::phi_p_power
  lhs_cl2,      ///< LHS optimised for the centred L2 discrepancy (Hickernell 1998)
  sobol,        ///< scrambled Sobol' sequence (random linear matrix scrambling + digital shift, Matoušek 1998)
};

/// "lhs" | "lhs-centred" (also "lhs-centered") | "lhs-maximin" | "lhs-cl2" | "sobol"; throws InputError listing the
/// valid names.
DesignKind design_kind_from_string(const std::string& name);
std::string to_string(DesignKind kind);
/// The canonical names, in enum order.
std::vector<std::string> design_kind_names();

/// Optimised-LHS criteria by name: "maximin" | "cl2" (for `demsa design lhs --criterion`). Throws InputError listing
/// the valid names. Returns lhs_maximin or lhs_cl2.
DesignKind lhs_criterion_from_string(const std::string& name);

struct DesignOptions {
  DesignKind kind = DesignKind::lhs;  ///< which design
  int samples = 16;                   ///< number of points n, >= 2 (>= 1 for sobol)
  int dimension = 2;                  ///< number of inputs d, 1..k_max_sobol_dimension for sobol, >= 1 otherwise
  std::uint64_t seed = 12345;         ///< seed of every random choice
  double phi_p_power = 50.0;          ///< p of the φ_p criterion, >= 1 (Morris & Mitchell use 50)
  // Optimised LHS. The budget is counted in iterations, so that the seed alone fixes the design: the search ends
  // after `iterations` outer iterations of the enhanced stochastic evolutionary algorithm (Jin, Chen, Sudjianto
  // 2005), or earlier once the best criterion has improved by less than stall_tolerance (relative) over the last
  // stall_iterations of them. 160 x 7 maximin: about 1 s on one core, minimum distance 0.62-0.64 for seeds 1-20.
  int iterations = 200;           ///< maximum outer iterations, >= 1
  int stall_iterations = 25;      ///< window of the no-improvement stop, >= 1
  double stall_tolerance = 1e-3;  ///< relative improvement over the window below which the search stops, in [0, 1)
  /// Safety stop [s], > 0 (infinity: none). When it ends the search (DesignResult::stop == time_limit) the design
  /// depends on the machine's speed and load, no longer on the seed alone: callers warn.
  double time_limit = std::numeric_limits<double>::infinity();
  /// Throws InputError naming the field, its value and the rule.
  void validate() const;
};

/// Largest number of samples of an optimised LHS: the optimiser keeps n x n tables of pairs (two for maximin, one
/// for cl2, 8 bytes an entry: 270 MB at this size).
inline constexpr int k_max_optimised_lhs_samples = 4096;

/// Largest design whose pair metrics (φ_p, centred L2 discrepancy), which take O(n²) time, design_metrics computes;
/// the minimum distance, O(n) memory and near O(n log n) time, is computed at every size.
inline constexpr Eigen::Index k_max_pair_metric_samples = 16384;

/// Space-filling quality of a design on [0,1]^d. Distances are Euclidean on the unit cube, between the points as
/// they are (an LHS point sits at a uniform random place inside its stratum, or at its centre for lhs-centred).
struct DesignMetrics {
  double min_distance = 0.0;  ///< smallest Euclidean distance between two points
  /// φ_p = (Σ_{i<j} d_ij^-p)^(1/p) (Morris & Mitchell 1995), smaller is better; absent above
  /// k_max_pair_metric_samples points.
  std::optional<double> phi_p;
  double phi_p_power = 50.0;  ///< the p used
  /// Centred L2 discrepancy C2 (Hickernell 1998, eq. 5.1c; the root), smaller is better; absent above
  /// k_max_pair_metric_samples points.
  std::optional<double> centred_l2;
};

/// Why the optimisation of an LHS ended.
enum class DesignStop {
  not_optimised,   ///< a design without optimisation
  iterations,      ///< DesignOptions::iterations done
  no_improvement,  ///< less than stall_tolerance gained over stall_iterations
  time_limit,      ///< the safety stop: the design depends on the machine's speed, not on the seed alone
};
/// "not optimised" | "iterations" | "no improvement" | "time limit".
std::string to_string(DesignStop stop);

struct DesignResult {
  Eigen::MatrixXd points;  ///< n x d, in [0,1]
  DesignKind kind = DesignKind::lhs;
  std::uint64_t seed = 0;  ///< the seed used (Options::seed)
  DesignMetrics metrics;   ///< metrics of `points` (when make_design was asked for them)
  int iterations = 0;      ///< optimisation iterations done (0 for unoptimised designs)
  DesignStop stop = DesignStop::not_optimised;
  double seconds = 0.0;  ///< wall-clock time spent building the design
};

/// Builds the design described by `options` (validated first), with its metrics when `with_metrics`.
DesignResult make_design(const DesignOptions& options, bool with_metrics = true);

/// Plain (centred = false) or centred LHS of n points in d dimensions.
Eigen::MatrixXd latin_hypercube(int samples, int dimension, std::uint64_t seed, bool centred = false);

/// Largest dimension of the Sobol' sequence (the first rows of Joe & Kuo's direction numbers kept here).
inline constexpr int k_max_sobol_dimension = 40;

/// The first n points of the unscrambled Sobol' sequence in d dimensions, starting at the origin, in Gray-code order,
/// with Joe & Kuo's direction numbers new-joe-kuo-6.21201 (Joe & Kuo 2008, SIAM J. Sci. Comput. 30, 2635-2654), 30
/// binary digits per coordinate. Throws InputError when d is outside 1..40 or n outside 1..2^30.
Eigen::MatrixXd sobol_sequence(int samples, int dimension);

/// The first n points of sobol_sequence (starting at the origin point, so that the first 2^m points form a
/// (t,m,d)-net) scrambled by a random lower-triangular binary matrix per dimension and a random digital shift
/// (Matoušek 1998, "On the L2-discrepancy for anchored boxes"; Owen 2003). Throws InputError when d > 40.
Eigen::MatrixXd scrambled_sobol(int samples, int dimension, std::uint64_t seed);

/// Smallest distance between two rows, in O(n) memory and about O(n log n) time for a space-filling design: each
/// row's neighbours searched in a k-d tree (Friedman, Bentley & Finkel 1977). Infinity for fewer than two rows.
double min_distance(const Eigen::MatrixXd& points);
/// O(n²) time, O(1) memory.
double phi_p(const Eigen::MatrixXd& points, double p = 50.0);
/// O(n² d) time, O(1) memory.
double centred_l2_discrepancy(const Eigen::MatrixXd& points);
/// Every metric; φ_p and C2 only up to k_max_pair_metric_samples points.
DesignMetrics design_metrics(const Eigen::MatrixXd& points, double phi_p_power = 50.0);

}  // namespace demsa::sobol
