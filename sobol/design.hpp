#pragma once
// Designs of experiments on the unit cube [0,1]^d (rows are samples, columns are inputs): Latin hypercubes (paper
// §5: "The DOE is performed with the Latin-Hypercube-sampling"), optimised Latin hypercubes, a scrambled Sobol'
// sequence, and the space-filling metrics used to compare them. Scale the result to physical bounds with
// sobol/scaling.hpp. Every random choice comes from Options::seed, echoed in the result.
#include <Eigen/Core>

#include <cstdint>
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
  /// Optimised LHS: outer iterations of the enhanced stochastic evolutionary algorithm (Jin, Chen, Sudjianto 2005),
  /// >= 1. The search also stops at time_limit.
  int iterations = 200;
  double time_limit = 5.0;  ///< optimised LHS: wall-clock budget [s], > 0
  /// Throws InputError naming the field, its value and the rule.
  void validate() const;
};

/// Space-filling quality of a design on [0,1]^d.
struct DesignMetrics {
  double min_distance = 0.0;  ///< smallest Euclidean distance between two points
  double phi_p = 0.0;         ///< φ_p = (Σ_{i<j} d_ij^-p)^(1/p) (Morris & Mitchell 1995), smaller is better
  double phi_p_power = 50.0;  ///< the p used
  double centred_l2 = 0.0;    ///< centred L2 discrepancy C2 (Hickernell 1998, eq. 5.1c; the root), smaller is better
};

struct DesignResult {
  Eigen::MatrixXd points;  ///< n x d, in [0,1]
  DesignKind kind = DesignKind::lhs;
  std::uint64_t seed = 0;  ///< the seed used (Options::seed)
  DesignMetrics metrics;   ///< metrics of `points`
  int iterations = 0;      ///< optimisation iterations done (0 for unoptimised designs)
  double seconds = 0.0;    ///< wall-clock time spent building the design
};

/// Builds the design described by `options` (validated first).
DesignResult make_design(const DesignOptions& options);

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

double min_distance(const Eigen::MatrixXd& points);
double phi_p(const Eigen::MatrixXd& points, double p = 50.0);
double centred_l2_discrepancy(const Eigen::MatrixXd& points);
DesignMetrics design_metrics(const Eigen::MatrixXd& points, double phi_p_power = 50.0);

}  // namespace demsa::sobol
