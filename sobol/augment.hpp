#pragma once
// Growing a design on [0,1]^d without touching its points (`demsa extend`, a raised `[design] samples`), and
// choosing the points of a refinement step (`demsa refine`).
//
//   - extend_sobol: the next points of the scrambled Sobol' sequence: rows start..start+added-1 of
//     scrambled_sobol(start + added, d, seed), which are the rows a fresh design of that size has there (the
//     scrambling does not depend on the number of points).
//   - extend_lhs: a Latin-hypercube extension in the spirit of Vořechovský's hierarchical refinement of LHS
//     (M. Vořechovský, "Hierarchical refinement of Latin hypercube samples", Computer-Aided Civil and
//     Infrastructure Engineering 30(5), 394-411, 2015; Sallaberry, Helton & Hora 2008 for the doubling case): the
//     axis of every input is cut into n + m strata, the existing n points occupy at most n of them, and each new
//     point takes one empty stratum per input (so no two new points share a stratum and none shares one with an
//     old point: at least m strata per input are empty). Which empty strata, and how they pair up across inputs, is
//     chosen for the maximin criterion φ_p (Morris & Mitchell 1995) of the whole design: the best of `candidates`
//     random pairings, then a local search of column swaps between new points and exchanges with unused empty
//     strata, kept when φ_p over the pairs that involve a new point decreases (the same moves as the ESE optimiser
//     of design.cpp, Jin, Chen & Sudjianto 2005, greedy acceptance).
//   - select_by_variance: a batch of points where Gaussian-process metamodels are least sure — by default the
//     largest reduction of the integrated predictive variance (Cohn 1996, "ALC" in Gramacy & Lee 2009, Technometrics
//     51(2); the IMSE of Sacks, Welch, Mitchell & Wynn 1989, Statistical Science 4(4), §5), or the largest
//     predictive variance itself (their "maximum MSE", ALM), summed over the metamodels after dividing each by its
//     process variance, among the points of a space-filling candidate set that keep a minimum distance to every
//     point already in the design. A batch is chosen one point at a time: the predictive variance of a GP with
//     fixed hyperparameters depends on the input locations only, so each chosen point is added to the training
//     inputs (with its own prediction as output) before the next is chosen — exact, not an approximation
//     (the "kriging believer" of Ginsbourger, Le Riche & Carraro 2010 is exact for the variance).
#include "sobol/gp.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace demsa::sobol {

/// The `added` points that follow the first `start` points of scrambled_sobol(., d, seed). Throws InputError when
/// start < 0, added < 1 or the dimension is outside 1..40.
Eigen::MatrixXd extend_sobol(int start, int added, int dimension, std::uint64_t seed);

struct LhsExtensionOptions {
  int candidates = 64;        ///< random pairings of the empty strata, the best by φ_p kept, >= 1
  int swaps_per_point = 40;   ///< local-search moves per new point, >= 0
  double phi_p_power = 50.0;  ///< p of φ_p, >= 1
  bool centred = false;       ///< new points at the centre of their strata (for an lhs-centred design)
  void validate() const;      ///< throws InputError naming the field
};

/// `added` new points (rows) for `existing` (n x d, every value in [0,1]), each in an empty stratum of the n + added
/// strata of every input, the pairing chosen for the maximin criterion of the whole design. Deterministic in `seed`.
/// Throws InputError for added < 1, an empty dimension or a value outside [0,1].
Eigen::MatrixXd extend_lhs(const Eigen::MatrixXd& existing, int added, std::uint64_t seed,
                           const LhsExtensionOptions& options = {});

/// φ_p over the pairs of `points` that involve at least one of its rows >= first_new (Morris & Mitchell 1995 eq.
/// 2.3 restricted to those pairs): the criterion extend_lhs minimises.
double phi_p_of_new(const Eigen::MatrixXd& points, Eigen::Index first_new, double p = 50.0);

/// What a refinement batch maximises.
enum class SelectionCriterion {
  /// The reduction of the predictive variance integrated over the cube that observing the point would bring
  /// (Cohn 1996, "Neural network exploration using optimal experiment design"; "ALC" in Gramacy & Lee 2009; the
  /// IMSE criterion of Sacks et al. 1989 §5 one point at a time): mean over reference points x of
  /// k_n(x, c)² / (σ_n²(c) + τ), posterior covariances of the GP in units of its process variance. The Sobol'
  /// indices are integrals over the cube, which this criterion serves; it keeps away from the corners where the
  /// pointwise variance is largest but that weigh little in the integrals.
  integrated_variance,
  /// The predictive variance at the point itself (maximum MSE, Sacks et al. 1989; "ALM" in Gramacy & Lee 2009).
  variance,
};

struct VarianceSelectionOptions {
  SelectionCriterion criterion = SelectionCriterion::integrated_variance;
  int reference = 500;    ///< reference points (a Latin hypercube) of integrated_variance, >= 1
  int batch = 4;          ///< points to choose, >= 1
  int candidates = 2000;  ///< space-filling candidate points (a Latin hypercube), >= batch
  /// A candidate closer than this fraction of the design's typical spacing to any design or chosen point is not
  /// taken; the spacing is the mean nearest-neighbour distance of the existing points scaled by (n/(n+batch))^(1/d).
  double min_distance_fraction = 0.5;
  std::uint64_t seed = 12345;  ///< seed of the candidate set
  void validate() const;       ///< throws InputError naming the field
};

/// `options.batch` points (rows) chosen by the largest summed criterion of `models` (fitted GPs on the same inputs,
/// those of `existing`; each in units of its process variance), one at a time as described at the top of this
/// file. When the
/// minimum-distance constraint leaves no candidate, it is halved until one qualifies. Throws InputError for no
/// model, an unfitted model, or a dimension that differs from existing's.
Eigen::MatrixXd select_by_variance(const std::vector<const GaussianProcess*>& models, const Eigen::MatrixXd& existing,
                                   const VarianceSelectionOptions& options);

}  // namespace demsa::sobol
