// Bayesian calibration on metamodels: the ensemble sampler against analytic posteriors, the diagnostics against
// processes of known autocorrelation, and a non-identified pair of parameters.
#include "sobol/design.hpp"
#include "sobol/ensemble_sampler.hpp"
#include "sobol/error.hpp"
#include "sobol/metamodel.hpp"
#include "sobol/posterior.hpp"
#include "sobol/random.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <Eigen/Dense>

#include <cmath>
#include <limits>

namespace demsa::sobol {
namespace {

/// A linear RSM fitted exactly to f(u) = c + aᵀu (its leave-one-out error is zero up to rounding).
std::unique_ptr<Metamodel> linear_model(double c, const Eigen::Vector2d& a) {
  const Eigen::MatrixXd x = latin_hypercube(20, 2, 7);
  Eigen::VectorXd y(20);
  for (int i = 0; i < 20; ++i) y(i) = c + a.dot(x.row(i).transpose());
  std::unique_ptr<Metamodel> m = make_metamodel("rsm1");
  m->fit(x, y);
  return m;
}

TEST(Posterior, LinearGaussianMatchesTheAnalyticPosteriorAtTheDefaultSampleCount) {
  // t_k = c_k + a_kᵀu + ε_k, ε_k ~ N(0, σ_k²), flat prior on a box far wider than the posterior: the posterior is
  // N(μ, Σ) with Σ⁻¹ = Σ_k a_k a_kᵀ / σ_k², μ the weighted least-squares solution.
  const std::vector<Eigen::Vector2d> a{{1.0, 1.0}, {1.0, -0.5}, {0.3, 2.0}};
  const std::vector<double> c{0.1, -0.2, 0.4};
  const std::vector<double> sigma{0.02, 0.03, 0.05};
  const Eigen::Vector2d truth(0.45, 0.55);
  std::vector<std::unique_ptr<Metamodel>> models;
  std::vector<GaussianTarget> targets;
  Eigen::Matrix2d precision = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  const std::vector<double> noise{0.01, -0.02, 0.03};
  for (size_t k = 0; k < a.size(); ++k) {
    models.push_back(linear_model(c[k], a[k]));
    const double t = c[k] + a[k].dot(truth) + noise[k];
    targets.push_back({fmt::format("t{}", k), models.back().get(), {}, t, sigma[k], 1.0});
    precision += a[k] * a[k].transpose() / (sigma[k] * sigma[k]);
    rhs += a[k] * (t - c[k]) / (sigma[k] * sigma[k]);
  }
  const Eigen::Matrix2d covariance = precision.inverse();
  const Eigen::Vector2d mean = covariance * rhs;
  ASSERT_LT(6 * std::sqrt(covariance.diagonal().maxCoeff()), 0.4);  // the box [0,1]² is far wider

  const GaussianPosterior posterior(targets, 2);
  const EnsembleOptions options;  // the default sample count
  const EnsembleResult r = sample_ensemble(posterior_function(posterior), {0.0, 0.0}, {1.0, 1.0}, options);
  const Eigen::Vector2d sampled_mean = r.draws.colwise().mean().transpose();
  const Eigen::MatrixXd centred = r.draws.rowwise() - sampled_mean.transpose();
  const Eigen::Matrix2d sampled_cov = centred.transpose() * centred / static_cast<double>(r.draws.rows() - 1);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(sampled_mean(i), mean(i), 0.03 * std::abs(mean(i))) << i;
    for (int j = 0; j < 2; ++j)
      EXPECT_NEAR(sampled_cov(i, j), covariance(i, j), 0.03 * std::sqrt(covariance(i, i) * covariance(j, j)))
          << i << "," << j;
  }
  const ChainDiagnostics d = diagnose(r);
  EXPECT_TRUE(d.converged) << d.advice;
  EXPECT_GT(d.acceptance, 0.3);
  // The MAP of a Gaussian is its mean.
  EXPECT_NEAR(r.best(0), mean(0), 0.2 * std::sqrt(covariance(0, 0)));
}

TEST(Posterior, ATargetOfTheSumLeavesBothParametersUnidentifiedAndAnticorrelated) {
  const std::unique_ptr<Metamodel> sum = linear_model(0.0, {1.0, 1.0});
  const GaussianPosterior posterior({{"sum", sum.get(), {}, 1.0, 0.02, 1.0}}, 2);
  const EnsembleResult r = sample_ensemble(posterior_function(posterior), {0.0, 0.0}, {1.0, 1.0}, {});
  const std::vector<MarginalSummary> m = summarise_marginals(r, {0.0, 0.0}, {1.0, 1.0});
  // On the line a + b = 1 each coordinate is uniform on [0,1]: 90 % of the prior's width.
  EXPECT_GT(m[0].width_ratio, 0.8);
  EXPECT_GT(m[1].width_ratio, 0.8);
  EXPECT_LT(posterior_correlation(r.draws)(0, 1), -0.95);
}

TEST(Posterior, AnIdentifiedParameterIsNarrowAndTheOtherFree) {
  const std::unique_ptr<Metamodel> first = linear_model(0.0, {1.0, 0.0});
  const GaussianPosterior posterior({{"a", first.get(), {}, 0.3, 0.01, 1.0}}, 2);
  const EnsembleResult r = sample_ensemble(posterior_function(posterior), {0.0, 0.0}, {1.0, 1.0}, {});
  const std::vector<MarginalSummary> m = summarise_marginals(r, {0.0, 0.0}, {1.0, 1.0});
  EXPECT_NEAR(m[0].q50, 0.3, 0.005);
  EXPECT_NEAR(m[0].width_ratio, 2 * 1.645 * 0.01, 0.005);
  EXPECT_NEAR(m[1].width_ratio, 0.9, 0.03);
}

TEST(Posterior, InputMapsShiftAStudyRangeIntoThePriorBox) {
  // The model sees v = 0.5 + 0.5 u: the target v = 0.7 puts u at 0.4.
  const std::unique_ptr<Metamodel> first = linear_model(0.0, {1.0, 0.0});
  GaussianTarget t{"a", first.get(), {{0, 0.5, 0.5}, {1, 0.0, 1.0}}, 0.7, 0.005, 1.0};
  const GaussianPosterior posterior({t}, 2);
  const EnsembleResult r = sample_ensemble(posterior_function(posterior), {0.0, 0.0}, {1.0, 1.0}, {});
  EXPECT_NEAR(summarise_marginals(r, {0.0, 0.0}, {1.0, 1.0})[0].q50, 0.4, 0.005);
}

TEST(Posterior, SeededRunsAreIdentical) {
  const std::unique_ptr<Metamodel> sum = linear_model(0.0, {1.0, 1.0});
  const GaussianPosterior posterior({{"sum", sum.get(), {}, 1.0, 0.1, 1.0}}, 2);
  EnsembleOptions o;
  o.steps = 50;
  o.burn_in = 10;
  const EnsembleResult a = sample_ensemble(posterior_function(posterior), {0.0, 0.0}, {1.0, 1.0}, o);
  const EnsembleResult b = sample_ensemble(posterior_function(posterior), {0.0, 0.0}, {1.0, 1.0}, o);
  EXPECT_EQ(a.draws, b.draws);
  o.seed = 2;
  const EnsembleResult c = sample_ensemble(posterior_function(posterior), {0.0, 0.0}, {1.0, 1.0}, o);
  EXPECT_NE(a.draws, c.draws);
}

TEST(Posterior, TooShortAChainIsReportedAsUnconvergedWithWhatToChange) {
  const std::unique_ptr<Metamodel> sum = linear_model(0.0, {1.0, 1.0});
  const GaussianPosterior posterior({{"sum", sum.get(), {}, 1.0, 0.02, 1.0}}, 2);
  EnsembleOptions o;
  o.steps = 40;
  o.burn_in = 0;
  const ChainDiagnostics d = diagnose(sample_ensemble(posterior_function(posterior), {0.0, 0.0}, {1.0, 1.0}, o));
  EXPECT_FALSE(d.converged);
  EXPECT_NE(d.advice.find("raise the steps per walker"), std::string::npos) << d.advice;
}

TEST(Posterior, WalkersStartedAtTheDensestPointsMissALocalModeThatTrapsAUniformStart) {
  // u0 free; (u1, u2) pinned at (0.3, 0.6) with sd 1e-5 (a 90 % width of 3.3e-5), as two precise measurements pin
  // two parameters, beside a broad local mode at (0.9, 0.1) far below it, as a metamodel's extrapolation near a
  // corner of the box makes one (calibrate's GPs on two incline angles at sd 0.0002° held two walkers at the box's
  // edge, split R̂ 1.5e4).
  // Started uniformly, walkers that begin nearer the local mode stay there; started at the densest 32 of 16384
  // uniform points, all begin near the narrow mode and converge on it.
  const double sd = 1e-5;
  const BatchLogDensity density = [&](const Eigen::MatrixXd& x) {
    const Eigen::ArrayXd global =
        -0.5 * (((x.col(1).array() - 0.3) / sd).square() + ((x.col(2).array() - 0.6) / sd).square());
    const Eigen::ArrayXd local =
        -1e8 - 0.5 * (((x.col(1).array() - 0.9) / 0.1).square() + ((x.col(2).array() - 0.1) / 0.1).square());
    return Eigen::VectorXd(global.max(local));
  };
  const std::vector<double> lower(3, 0.0), upper(3, 1.0);
  EnsembleOptions o;
  const ChainDiagnostics uniform = diagnose(sample_ensemble(density, lower, upper, o));
  EXPECT_FALSE(uniform.converged);
  EXPECT_GT(uniform.max_rhat, 2.0);
  Random draw(3);
  Eigen::MatrixXd points(16384, 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (int j = 0; j < 3; ++j) points(i, j) = draw.uniform();
  o.start = highest_density_start(points, density(points), o.walkers_for(3));
  ASSERT_EQ(o.start.rows(), 32);
  const Eigen::VectorXd start_density = density(o.start);
  for (Eigen::Index w = 1; w < start_density.size(); ++w) EXPECT_LE(start_density(w), start_density(w - 1));
  const EnsembleResult r = sample_ensemble(density, lower, upper, o);
  const ChainDiagnostics d = diagnose(r);
  EXPECT_TRUE(d.converged) << d.advice;
  const std::vector<MarginalSummary> m = summarise_marginals(r, lower, upper);
  EXPECT_NEAR(m[0].width_ratio, 0.9, 0.05);
  EXPECT_NEAR(m[1].width_ratio, 3.29 * sd, 0.3 * 3.29 * sd);
  EXPECT_NEAR(m[2].width_ratio, 3.29 * sd, 0.3 * 3.29 * sd);
  EXPECT_NEAR(m[1].q50, 0.3, sd);
  EXPECT_NEAR(m[2].q50, 0.6, sd);
  // Points of density zero are never chosen; too few finite ones are refused.
  Eigen::VectorXd few = Eigen::VectorXd::Constant(40, -std::numeric_limits<double>::infinity());
  few.head(31).setZero();
  EXPECT_THROW(highest_density_start(points.topRows(40), few, 32), InputError);
  few(39) = -1.0;
  EXPECT_EQ(highest_density_start(points.topRows(40), few, 32).row(31), points.row(39));
}

TEST(Diagnostics, IntegratedTimeOfAnAr1ProcessIsItsAnalyticValue) {
  // x_t = φ x_{t-1} + ε_t has ρ(t) = φ^t and τ = (1 + φ) / (1 - φ).
  const double phi = 0.8;
  Random rng(5);
  Eigen::MatrixXd chains(20000, 32);
  for (int w = 0; w < 32; ++w) {
    double x = rng.normal() / std::sqrt(1 - phi * phi);
    for (int t = 0; t < 20000; ++t) chains(t, w) = x = phi * x + rng.normal();
  }
  EXPECT_NEAR(integrated_time(chains), (1 + phi) / (1 - phi), 0.05 * 9.0);
  EXPECT_LT(split_rhat(chains), 1.01);
}

TEST(Diagnostics, SplitRhatFlagsChainsThatDisagreeAndADriftWithinAChain) {
  Random rng(3);
  Eigen::MatrixXd apart(1000, 4), drift(1000, 4);
  for (int w = 0; w < 4; ++w)
    for (int t = 0; t < 1000; ++t) {
      apart(t, w) = rng.normal() + (w == 0 ? 3.0 : 0.0);
      drift(t, w) = rng.normal() + t / 200.0;
    }
  EXPECT_GT(split_rhat(apart), 1.1);
  EXPECT_GT(split_rhat(drift), 1.1);
  EXPECT_EQ(integrated_time(Eigen::MatrixXd::Constant(100, 3, 2.0)), 1.0);
}

TEST(Posterior, BadOptionsAndTargetsNameTheValue) {
  const std::unique_ptr<Metamodel> sum = linear_model(0.0, {1.0, 1.0});
  EXPECT_THROW(GaussianPosterior({}, 2), InputError);
  EXPECT_THROW(GaussianPosterior({{"sum", sum.get(), {}, 1.0, -1.0, 1.0}}, 2), InputError);
  EXPECT_THROW(GaussianPosterior({{"sum", sum.get(), {}, 1.0, 0.1, -1.0}}, 2), InputError);
  EXPECT_THROW(GaussianPosterior({{"sum", sum.get(), {}, 1.0, 0.1, 1.0}}, 3), InputError);
  EnsembleOptions o;
  o.walkers = 5;
  try {
    o.validate(2);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("walkers 5"), std::string::npos);
  }
  o = {};
  o.steps = 3;
  EXPECT_THROW(o.validate(2), InputError);
  o = {};
  o.stretch = 1.0;
  EXPECT_THROW(o.validate(2), InputError);
}

TEST(Posterior, SizesThatOverflowOrExceedMemoryAreRefusedBeforeRunning) {
  const auto message = [](const EnsembleOptions& o, int d) {
    try {
      o.validate(d);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EnsembleOptions o;
  o.burn_in = 2147483548;  // burn_in + steps overflows an int
  o.steps = 100;
  EXPECT_NE(message(o, 2).find("burn-in 2147483548: 32 walkers × (2147483548 burn-in + 100 steps"), std::string::npos)
      << message(o, 2);
  o = {};
  o.burn_in = 0;
  o.steps = 100000000;  // 32 walkers × 1e8 steps × 3 values
  EXPECT_NE(message(o, 2).find("steps 100000000:"), std::string::npos) << message(o, 2);
  o.steps = 1000000;  // 9.6e7 values: in memory
  EXPECT_EQ(message(o, 2), "");
  o.steps = 1600000;  // 1.5e8 values
  EXPECT_NE(message(o, 2).find("the sampler keeps in memory: at most 1562500 steps"), std::string::npos)
      << message(o, 2);
}

}  // namespace
}  // namespace demsa::sobol
