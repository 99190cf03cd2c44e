// The noise of a stochastic simulator from replicates (sobol/noise.hpp) and the GP whose nugget is set from it.
#include "sobol/gp.hpp"
#include "sobol/noise.hpp"
#include "sobol/random.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace demsa::sobol {
namespace {

TEST(Noise, ChiSquareQuantilesMatchScipy) {
  // scipy.stats.chi2.ppf(p, nu), scipy 1.x
  struct Case {
    double nu, lower, upper;
  };
  for (const Case& c :
       {Case{1, 0.0009820691171752555, 5.023886187314888}, Case{2, 0.05063561596857975, 7.377758908227871},
        Case{8, 2.1797307472526497, 17.534546139484647}, Case{10, 3.2469727802368413, 20.483177350807388},
        Case{30, 16.79077226556663, 46.97924224367115}, Case{200, 162.72798250184627, 241.05789550631093}}) {
    EXPECT_NEAR(chi_square_quantile(0.025, c.nu), c.lower, 1e-9 * c.upper) << c.nu;
    EXPECT_NEAR(chi_square_quantile(0.975, c.nu), c.upper, 1e-9 * c.upper) << c.nu;
  }
  EXPECT_NEAR(chi_square_cdf(5.0, 8), 0.2424238668669339, 1e-12);
  EXPECT_NEAR(chi_square_cdf(5.0, 1), 0.9746526813225317, 1e-12);
}

TEST(Noise, PooledVarianceByHand) {
  // Groups {1, 3} (SS 2), {2, 4, 6} (SS 8), {5} (no replicate): s² = 10 / 3.
  const NoiseEstimate e = pooled_noise_variance({{1, 3}, {2, 4, 6}, {5}}, 0.95);
  EXPECT_DOUBLE_EQ(e.variance, 10.0 / 3.0);
  EXPECT_EQ(e.points, 2);
  EXPECT_EQ(e.values, 5);
  EXPECT_EQ(e.dof, 3);
  EXPECT_NEAR(e.lower, 10.0 / chi_square_quantile(0.975, 3), 1e-12);
  EXPECT_NEAR(e.upper, 10.0 / chi_square_quantile(0.025, 3), 1e-9);
  EXPECT_LT(e.lower, e.variance);
  EXPECT_GT(e.upper, e.variance);
}

TEST(Noise, RefusesWhatGivesNoVariance) {
  EXPECT_THROW(pooled_noise_variance({{1}, {2}}), InputError);
  EXPECT_THROW(pooled_noise_variance({}), InputError);
  EXPECT_THROW(pooled_noise_variance({{1, std::nan("")}}), InputError);
  EXPECT_THROW(pooled_noise_variance({{1, 2}}, 1.0), InputError);
}

TEST(Noise, IntervalCoversTheTrueVarianceAtItsLevel) {
  // 400 experiments of 5 points x 3 repeats of N(mean_g, 4): the 90 % interval holds 4 in about 90 % of them
  // (binomial sd 1.5 %), the estimate is unbiased.
  Random rng(11);
  int covered = 0;
  double mean = 0;
  const int experiments = 400;
  for (int k = 0; k < experiments; ++k) {
    std::vector<std::vector<double>> groups(5);
    for (int g = 0; g < 5; ++g)
      for (int r = 0; r < 3; ++r) groups[static_cast<std::size_t>(g)].push_back(10.0 * g + 2.0 * rng.normal());
    const NoiseEstimate e = pooled_noise_variance(groups, 0.9);
    covered += e.lower <= 4.0 && 4.0 <= e.upper;
    mean += e.variance / experiments;
  }
  EXPECT_NEAR(static_cast<double>(covered) / experiments, 0.9, 0.045);
  EXPECT_NEAR(mean, 4.0, 0.25);
}

TEST(Noise, GpNuggetFromAMeasuredNoiseGivesThatNoiseVariance) {
  // y = sin(3 x1) + x2 + noise of variance 0.01 on 40 points in 2-D.
  Random rng(3);
  const int n = 40;
  Eigen::MatrixXd x(n, 2);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) {
    x(i, 0) = rng.uniform();
    x(i, 1) = rng.uniform();
    y(i) = std::sin(3.0 * x(i, 0)) + x(i, 1) + 0.1 * rng.normal();
  }
  const double variance = (y.array() - y.mean()).square().mean();
  GpOptions options;
  options.nugget = true;
  options.noise_share = 0.01 / variance;
  GaussianProcess gp(options);
  gp.fit(x, y);
  // The model's noise variance σ² τ is the measured one (fixed point to 1e-3).
  EXPECT_NEAR(gp.process_variance() * gp.nugget(), 0.01, 2e-5);
  EXPECT_FALSE(gp.interpolates());
  // Without a nugget a measured noise is refused.
  GpOptions bad;
  bad.noise_share = 0.1;
  EXPECT_THROW(GaussianProcess{bad}, InputError);
}

}  // namespace
}  // namespace demsa::sobol
