#pragma once
// Noise of a stochastic simulator measured from replicates: at each of several input points the simulator was run
// more than once with only its random seed changed (a DEM pile built from another random packing), and the spread
// within a point is the noise. Pooled within-point variance (one-way analysis of variance, e.g. Montgomery,
// "Design and Analysis of Experiments", 8th ed. 2013, §3.3: the error mean square MS_E = SS_E / (N − a)) with the
// chi-square interval of a normal variance (ibid. §2.4.3; Casella & Berger, "Statistical Inference", 2nd ed. 2002,
// Example 9.2.10): ν s²/σ² ~ χ²_ν, so [ν s²/χ²_{ν,1−α/2}, ν s²/χ²_{ν,α/2}] holds σ² with probability 1 − α when the
// noise is normal with one variance at every point.
#include <vector>

namespace demsa::sobol {

struct NoiseEstimate {
  double variance = 0.0;    ///< pooled within-point variance s² = Σ_g Σ_i (y_gi − ȳ_g)² / ν
  double lower = 0.0;       ///< ν s² / χ²_{ν, (1+c)/2}
  double upper = 0.0;       ///< ν s² / χ²_{ν, (1−c)/2}
  int points = 0;           ///< groups with at least two values
  int values = 0;           ///< values in those groups
  int dof = 0;              ///< ν = Σ_g (n_g − 1)
  double confidence = 0.0;  ///< c, the level of [lower, upper]
};

/// The pooled within-point variance of `groups` (the values of each point; a group of fewer than two values adds
/// nothing) with its chi-square interval at level `confidence` in (0, 1). Throws InputError when no group has two
/// values, a value is not finite or the confidence is outside (0, 1).
NoiseEstimate pooled_noise_variance(const std::vector<std::vector<double>>& groups, double confidence = 0.95);

/// Distribution function of the chi-square distribution with nu > 0 degrees of freedom: the regularised lower
/// incomplete gamma function P(nu/2, x/2), by its series for x < a + 1 and its continued fraction otherwise
/// (Press et al., "Numerical Recipes", 3rd ed. 2007, §6.2).
double chi_square_cdf(double x, double nu);
/// Quantile p in (0, 1) of the chi-square distribution with nu > 0 degrees of freedom, by bisection on
/// chi_square_cdf (to 1e-12 relative).
double chi_square_quantile(double p, double nu);

}  // namespace demsa::sobol
