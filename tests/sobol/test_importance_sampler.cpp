// Adaptive importance sampling against analytic posteriors: narrow in a few directions of seven and flat in the
// others, the case where the ensemble sampler's walkers mix slowly.
#include "sobol/error.hpp"
#include "sobol/importance_sampler.hpp"
#include "sobol/random.hpp"

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <vector>

namespace demsa::sobol {
namespace {

constexpr int k_d = 7;
constexpr double k_z90 = 1.6448536269514722;  // the standard normal's 95 % quantile

/// n uniform points of the unit box in k_d dimensions and the density's log at each.
struct Start {
  Eigen::MatrixXd points;
  Eigen::VectorXd log_density;
};
Start uniform_start(const BatchLogDensity& f, int n = 16384) {
  Random random(99);
  Start s{Eigen::MatrixXd(n, k_d), Eigen::VectorXd()};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < k_d; ++j) s.points(i, j) = random.uniform();
  s.log_density = f(s.points);
  return s;
}

const std::vector<double> k_lower(k_d, 0.0), k_upper(k_d, 1.0);

/// Independent Gaussians on parameters 1 and 3 (means m1, m3, sd s), flat in the other five.
BatchLogDensity two_narrow(double m1, double m3, double s) {
  return [=](const Eigen::MatrixXd& x) {
    return Eigen::VectorXd(-0.5 * ((x.col(1).array() - m1).square() + (x.col(3).array() - m3).square()) / (s * s));
  };
}

TEST(ImportanceSampler, TwoNarrowDirectionsOfSevenMatchTheAnalyticIntervals) {
  // Widths 0.033 of the box: the incline's two angles pin μ_PW and μ_R,PW about this tightly; the 16,384 prior
  // points carry an effective sample size of a few.
  const BatchLogDensity f = two_narrow(0.3, 0.62, 0.01);
  const Start start = uniform_start(f);
  const Eigen::ArrayXd w = (start.log_density.array() - start.log_density.maxCoeff()).exp();
  EXPECT_LT(w.sum() * w.sum() / w.square().sum(), 100.0) << "the prior points alone carry this posterior";
  const ImportanceResult r = adaptive_importance_sample(f, k_lower, k_upper, start.points, start.log_density, {});
  ASSERT_TRUE(r.converged) << "ess " << r.ess << " after " << r.rounds << " rounds";
  EXPECT_GE(r.ess, 400.0);
  const auto [a05, a95] = r.interval(1);
  EXPECT_NEAR(a05, 0.3 - k_z90 * 0.01, 0.003);
  EXPECT_NEAR(a95, 0.3 + k_z90 * 0.01, 0.003);
  const auto [b05, b95] = r.interval(3);
  EXPECT_NEAR(b05, 0.62 - k_z90 * 0.01, 0.003);
  EXPECT_NEAR(b95, 0.62 + k_z90 * 0.01, 0.003);
  // The flat directions keep their 90 % of the box.
  for (const int j : {0, 2, 4, 5, 6}) {
    const auto [q05, q95] = r.interval(j);
    EXPECT_NEAR(q05, 0.05, 0.03) << "parameter " << j;
    EXPECT_NEAR(q95, 0.95, 0.03) << "parameter " << j;
  }
  EXPECT_NEAR(r.weights.sum(), 1.0, 1e-12);
  EXPECT_EQ(r.points.rows() % 16384, 0) << "whole rounds of draws are kept";
}

TEST(ImportanceSampler, RoundsArePooledWhenOneAloneFallsShort) {
  // No round of 4096 draws can hold an effective size of 6000: the last rounds pooled must, with the same intervals.
  const BatchLogDensity f = two_narrow(0.3, 0.62, 0.01);
  const Start start = uniform_start(f);
  ImportanceOptions o;
  o.draws = 4096;
  o.min_ess = 6000;
  const ImportanceResult r = adaptive_importance_sample(f, k_lower, k_upper, start.points, start.log_density, o);
  ASSERT_TRUE(r.converged) << "ess " << r.ess << " after " << r.rounds << " rounds";
  EXPECT_GE(r.ess, 6000.0);
  EXPECT_GE(r.points.rows(), 2 * 4096);
  EXPECT_EQ(r.points.rows() % 4096, 0);
  EXPECT_NEAR(r.weights.sum(), 1.0, 1e-12);
  const auto [a05, a95] = r.interval(1);
  EXPECT_NEAR(a05, 0.3 - k_z90 * 0.01, 0.002);
  EXPECT_NEAR(a95, 0.3 + k_z90 * 0.01, 0.002);
}

TEST(ImportanceSampler, ARidgeAcrossTwoParametersIsFollowedByTheFittedCovariance) {
  // a + b is pinned (sd 0.005), a - b less (sd 0.05): a correlated posterior, a = (s + t) / 2 with sd
  // sqrt(0.005² + 0.05²) / 2 in each of a and b.
  const BatchLogDensity f = [](const Eigen::MatrixXd& x) {
    const Eigen::ArrayXd s = x.col(0).array() + x.col(1).array() - 1.0;
    const Eigen::ArrayXd t = x.col(0).array() - x.col(1).array() - 0.1;
    return Eigen::VectorXd(-0.5 * (s.square() / (0.005 * 0.005) + t.square() / (0.05 * 0.05)));
  };
  const Start start = uniform_start(f);
  const ImportanceResult r = adaptive_importance_sample(f, k_lower, k_upper, start.points, start.log_density, {});
  ASSERT_TRUE(r.converged) << "ess " << r.ess;
  const double sd = std::sqrt(0.005 * 0.005 + 0.05 * 0.05) / 2.0;
  const auto [a05, a95] = r.interval(0);
  EXPECT_NEAR(a05, 0.55 - k_z90 * sd, 0.005);
  EXPECT_NEAR(a95, 0.55 + k_z90 * sd, 0.005);
  const auto [b05, b95] = r.interval(1);
  EXPECT_NEAR(b05, 0.45 - k_z90 * sd, 0.005);
  EXPECT_NEAR(b95, 0.45 + k_z90 * sd, 0.005);
}

TEST(ImportanceSampler, APosteriorCutByTheBoxKeepsItsTruncatedQuantiles) {
  // A Gaussian of sd 0.02 centred on the box's edge at 0: the posterior is its half; its 5 % and 95 % quantiles are
  // the half-normal's, 0.02 · 0.0627 and 0.02 · 1.96.
  const BatchLogDensity f = [](const Eigen::MatrixXd& x) {
    return Eigen::VectorXd(-0.5 * x.col(2).array().square() / (0.02 * 0.02));
  };
  const Start start = uniform_start(f);
  const ImportanceResult r = adaptive_importance_sample(f, k_lower, k_upper, start.points, start.log_density, {});
  ASSERT_TRUE(r.converged) << "ess " << r.ess;
  const auto [q05, q95] = r.interval(2);
  EXPECT_NEAR(q05, 0.02 * 0.0627, 0.001);
  EXPECT_NEAR(q95, 0.02 * 1.96, 0.003);
  // The Gaussian is truncated to the box: every draw lies inside it.
  EXPECT_GE(r.points.minCoeff(), 0.0);
  EXPECT_LE(r.points.maxCoeff(), 1.0);
}

TEST(ImportanceSampler, TooFewRoundsForAVeryNarrowPosteriorIsNotConverged) {
  // Widths of 3e-6 in all seven directions: one round from the prior's spacing cannot find it.
  const BatchLogDensity f = [](const Eigen::MatrixXd& x) {
    return Eigen::VectorXd(-0.5 * (x.array() - 0.4).square().rowwise().sum() / 1e-12);
  };
  const Start start = uniform_start(f);
  ImportanceOptions one;
  one.rounds = 1;
  const ImportanceResult r = adaptive_importance_sample(f, k_lower, k_upper, start.points, start.log_density, one);
  EXPECT_FALSE(r.converged);
  EXPECT_LT(r.ess, 400.0);
  EXPECT_EQ(r.rounds, 1);
  const ImportanceResult empty;
  EXPECT_TRUE(std::isnan(empty.interval(0).first) && std::isnan(empty.interval(0).second));
}

TEST(ImportanceSampler, SeededRunsAreIdenticalAndSeedsDiffer) {
  const BatchLogDensity f = two_narrow(0.5, 0.5, 0.02);
  const Start start = uniform_start(f, 2000);
  ImportanceOptions o;
  o.draws = 4000;
  const ImportanceResult a = adaptive_importance_sample(f, k_lower, k_upper, start.points, start.log_density, o);
  const ImportanceResult b = adaptive_importance_sample(f, k_lower, k_upper, start.points, start.log_density, o);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.weights, b.weights);
  o.seed = 2;
  const ImportanceResult c = adaptive_importance_sample(f, k_lower, k_upper, start.points, start.log_density, o);
  EXPECT_NE(a.points, c.points);
}

TEST(ImportanceSampler, BadOptionsAndInputsNameTheValue) {
  const BatchLogDensity f = two_narrow(0.5, 0.5, 0.1);
  const Start start = uniform_start(f, 500);
  const auto message = [&](const ImportanceOptions& o, const Eigen::MatrixXd& points, const Eigen::VectorXd& log_d) {
    try {
      adaptive_importance_sample(f, k_lower, k_upper, points, log_d, o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  ImportanceOptions o;
  o.draws = 10;
  EXPECT_NE(message(o, start.points, start.log_density).find("draws 10"), std::string::npos);
  o = {};
  o.defensive = 1.0;
  EXPECT_NE(message(o, start.points, start.log_density).find("defensive 1"), std::string::npos);
  o = {};
  o.inflation = 0.5;
  EXPECT_NE(message(o, start.points, start.log_density).find("inflation 0.5"), std::string::npos);
  o = {};
  o.min_ess = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(o, start.points, start.log_density).find("min_ess"), std::string::npos);
  const Eigen::VectorXd nowhere =
      Eigen::VectorXd::Constant(start.points.rows(), -std::numeric_limits<double>::infinity());
  EXPECT_NE(message({}, start.points, nowhere).find("no starting point has a finite density"), std::string::npos);
  EXPECT_NE(message({}, start.points.leftCols(3), start.log_density).find("points 500 × 3"), std::string::npos);
}

TEST(ImportanceSampler, WeightedIntervalWalksTheGivenOrderToEachQuantile) {
  // Rows out of order in column 1; weights 1..4 of total 10: the CDF in value order is 0.3, 0.4, 0.6, 1.0.
  Eigen::MatrixXd points(4, 2);
  points << 9, 0.7, 9, 0.1, 9, 0.4, 9, 0.9;
  const Eigen::VectorXd weights = (Eigen::VectorXd(4) << 2.0, 3.0, 1.0, 4.0).finished();
  const std::vector<Eigen::Index> order{1, 2, 0, 3};
  const auto [q05, q95] = weighted_interval(points, 1, order, weights, 10.0);
  EXPECT_DOUBLE_EQ(q05, 0.1);
  EXPECT_DOUBLE_EQ(q95, 0.9);
  const auto [q35, q55] = weighted_interval(points, 1, order, weights, 10.0, 0.35, 0.55);
  EXPECT_DOUBLE_EQ(q35, 0.4);
  EXPECT_DOUBLE_EQ(q55, 0.7);
  const auto [a, b] = weighted_interval(points, 1, {}, weights, 10.0);
  EXPECT_TRUE(std::isnan(a) && std::isnan(b));
}

}  // namespace
}  // namespace demsa::sobol
