// Sobol' indices of metamodels: exact RSM indices against QMC and against a hand-computed polynomial, and the
// design bootstrap.
#include "sobol/design.hpp"
#include "sobol/error.hpp"
#include "sobol/gp.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/rsm.hpp"
#include "sobol/stop.hpp"
#include "tests/sobol/analytic.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace demsa::sobol {
namespace {

TEST(RsmExact, KnownPolynomial) {
  // f = L1(u1) + 2 L1(u2) + L1(u1) L1(u2) + 0 u3 with orthonormal L1 = √3(2u-1): V = 1 + 4 + 1 = 6,
  // S1 = [1/6, 4/6, 0], S12 = 1/6, ST = [2/6, 5/6, 0].
  const Eigen::MatrixXd x = latin_hypercube(40, 3, 2);
  Eigen::VectorXd y(40);
  for (int i = 0; i < 40; ++i) {
    const double a = legendre01(1, x(i, 0)), b = legendre01(1, x(i, 1));
    y(i) = 5.0 + a + 2.0 * b + a * b;
  }
  PolynomialRsm rsm(2);
  rsm.fit(x, y);
  const SobolResult r = rsm_exact_indices(rsm);
  EXPECT_EQ(r.method, "rsm-exact");
  EXPECT_NEAR(r.variance, 6.0, 1e-10);
  EXPECT_NEAR(r.mean, 5.0, 1e-10);
  EXPECT_NEAR(r.first[0].value, 1.0 / 6, 1e-10);
  EXPECT_NEAR(r.first[1].value, 4.0 / 6, 1e-10);
  EXPECT_NEAR(r.first[2].value, 0.0, 1e-10);
  EXPECT_NEAR(r.total[0].value, 2.0 / 6, 1e-10);
  EXPECT_NEAR(r.total[1].value, 5.0 / 6, 1e-10);
  ASSERT_EQ(r.second.size(), 3u);
  EXPECT_NEAR(r.second[0].s.value, 1.0 / 6, 1e-10);
  EXPECT_NEAR(r.residual.value, 1.0 / 6, 1e-10);
}

TEST(RsmExact, EqualsQmcEstimateAtBase2To16) {
  // A cubic fitted to Ishigami data in 4-D: its exact indices against Saltelli QMC on the same polynomial.
  const Eigen::MatrixXd x = latin_hypercube(120, 4, 3);
  PolynomialRsm rsm(3);
  rsm.fit(x, test::ishigami(x));
  const SobolResult exact = rsm_exact_indices(rsm);
  SaltelliOptions so;
  so.base = 1 << 16;
  so.dimension = 4;
  so.second_order = true;
  so.seed = 5;
  SobolOptions o;
  o.second_order = true;
  o.interval = SaltelliInterval::none;
  const SobolResult qmc =
      sobol_indices([&rsm](const Eigen::MatrixXd& u) { return rsm.predict(u); }, saltelli_design(so), o);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(exact.first[k].value, qmc.first[k].value, 1e-3) << k;
    EXPECT_NEAR(exact.total[k].value, qmc.total[k].value, 1e-3) << k;
  }
  for (std::size_t p = 0; p < exact.second.size(); ++p)
    EXPECT_NEAR(exact.second[p].s.value, qmc.second[p].s.value, 1e-3) << p;
  EXPECT_NEAR(exact.variance, qmc.variance, 1e-3 * exact.variance);
}

TEST(MetamodelSobol, DesignBootstrapGivesIntervalsAroundTheEstimate) {
  const Eigen::MatrixXd x = latin_hypercube(60, 3, 4);
  Eigen::VectorXd y(60);
  for (int i = 0; i < 60; ++i) y(i) = 4.0 * x(i, 0) + std::sin(3.0 * x(i, 1)) + 0.2 * x(i, 2);
  for (const char* name : {"rsm2", "rbf-cubic"}) {
    SCOPED_TRACE(name);
    auto m = make_metamodel(name);
    m->fit(x, y);
    MetamodelSobolOptions o;
    o.base = 2048;
    o.bootstrap = 40;
    o.second_order = true;
    const SobolResult r = metamodel_sobol(*m, o);
    EXPECT_EQ(r.bootstrap, 40);
    EXPECT_EQ(r.second.size(), 3u);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LT(r.first[k].lower, r.first[k].upper);
      EXPECT_LE(r.first[k].lower, r.first[k].value + 1e-12);
      EXPECT_GE(r.first[k].upper, r.first[k].value - 1e-12);
    }
    // Analytic: V1 = 16/12 = 1.333, V2 = var(sin 3u) = 0.1981, V3 = 0.04/12.
    const double v1 = 16.0 / 12, v2 = 0.5 - std::sin(6.0) / 12.0 - std::pow((1 - std::cos(3.0)) / 3.0, 2),
                 v3 = 0.04 / 12;
    EXPECT_NEAR(r.first[0].value, v1 / (v1 + v2 + v3), 0.01);
    EXPECT_NEAR(r.first[1].value, v2 / (v1 + v2 + v3), 0.01);
  }
}

TEST(MetamodelSobol, TooFewRefitsLeaveTheEstimateWithoutAnInterval) {
  // Five points in 3-D: an RBF with a linear tail needs five distinct points here, and a resample of five keeps
  // all five in only 5!/5^5 = 4% of the draws. The estimate of the full fit stands, without an interval, and says
  // why.
  const Eigen::MatrixXd x = latin_hypercube(5, 3, 11);
  Eigen::VectorXd y(5);
  for (int i = 0; i < 5; ++i) y(i) = 2.0 * x(i, 0) + x(i, 1);
  auto m = make_metamodel("rbf-cubic");
  m->fit(x, y);
  MetamodelSobolOptions o;
  o.base = 512;
  o.bootstrap = 40;
  const SobolResult r = metamodel_sobol(*m, o);
  MetamodelSobolOptions plain = o;
  plain.bootstrap = 0;
  const SobolResult without = metamodel_sobol(*m, plain);
  EXPECT_EQ(r.bootstrap, 0);
  EXPECT_NE(r.note.find("no interval: only "), std::string::npos) << r.note;
  EXPECT_NE(r.note.find(" of 40 design-bootstrap refits of rbf-cubic succeeded"), std::string::npos) << r.note;
  EXPECT_TRUE(without.note.empty());
  for (int k = 0; k < 3; ++k) {
    EXPECT_DOUBLE_EQ(r.first[k].value, without.first[k].value);
    EXPECT_DOUBLE_EQ(r.first[k].lower, r.first[k].value);
    EXPECT_DOUBLE_EQ(r.first[k].upper, r.first[k].value);
  }
}

TEST(MetamodelSobol, OptionsAreValidated) {
  MetamodelSobolOptions o;
  o.base = 1;
  EXPECT_THROW(o.validate(), InputError);
  o.base = 64;
  o.confidence = 0.0;
  EXPECT_THROW(o.validate(), InputError);
}

TEST(MetamodelSobol, IntervalsCarryTheQmcErrorOfTheEstimate) {
  // A quadratic RSM fitted to an exact quadratic: every refit gives the same polynomial, so the metamodel is
  // certain and what is left is the QMC error of the estimate at N = 64. Its exact indices are known
  // (rsm_exact_indices); the intervals, from refits on independently scrambled designs, must cover them.
  const Eigen::MatrixXd x = latin_hypercube(80, 3, 9);
  Eigen::VectorXd y(80);
  for (int i = 0; i < 80; ++i) y(i) = 3.0 * x(i, 0) + 2.0 * x(i, 1) * x(i, 1) + x(i, 0) * x(i, 2) + 0.5 * x(i, 2);
  auto m = make_metamodel("rsm2");
  m->fit(x, y);
  const SobolResult exact = rsm_exact_indices(dynamic_cast<const PolynomialRsm&>(*m));
  int covered = 0, total = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    MetamodelSobolOptions o;
    o.base = 64;
    o.bootstrap = 40;
    o.seed = seed;
    o.exact_for_rsm = false;
    const SobolResult r = metamodel_sobol(*m, o);
    for (int k = 0; k < 3; ++k) {
      covered += r.first[k].lower <= exact.first[k].value && exact.first[k].value <= r.first[k].upper;
      covered += r.total[k].lower <= exact.total[k].value && exact.total[k].value <= r.total[k].upper;
      total += 2;
    }
  }
  EXPECT_GE(covered, 0.85 * total) << covered << " of " << total;
}

namespace posterior {

// f = 4 u1 + sin(3 u2) + 0.2 u3 (the function of DesignBootstrapGivesIntervalsAroundTheEstimate): additive, so
// S1 = ST = V_k / V with V1 = 16/12, V2 = var(sin 3u), V3 = 0.04/12.
Eigen::VectorXd f(const Eigen::MatrixXd& x) {
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = 4.0 * x(i, 0) + std::sin(3.0 * x(i, 1)) + 0.2 * x(i, 2);
  return y;
}
std::vector<double> truth() {
  const double v1 = 16.0 / 12, v2 = 0.5 - std::sin(6.0) / 12.0 - std::pow((1 - std::cos(3.0)) / 3.0, 2), v3 = 0.04 / 12;
  return {v1 / (v1 + v2 + v3), v2 / (v1 + v2 + v3), v3 / (v1 + v2 + v3)};
}
double max_half_width(const SobolResult& r) {
  double w = 0.0;
  for (const auto* v : {&r.first, &r.total})
    for (const IndexEstimate& e : *v) w = std::max(w, 0.5 * (e.upper - e.lower));
  return w;
}
// A response that turns over along u1 (sin 2πu1), which a GP cannot extrapolate from a part of u1's range.
Eigen::VectorXd wavy(const Eigen::MatrixXd& x) {
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    y(i) = std::sin(2.0 * 3.14159265358979323846 * x(i, 0)) + 0.5 * std::sin(3.0 * x(i, 1)) + 0.2 * x(i, 2);
  return y;
}
SobolResult indices(const Eigen::MatrixXd& x, std::uint64_t seed, MetamodelInterval interval, bool turning = false) {
  GpOptions g;
  g.starts = 2;
  GaussianProcess gp(g);
  gp.fit(x, turning ? wavy(x) : f(x));
  MetamodelSobolOptions o;
  o.base = 1024;
  o.bootstrap = 100;
  o.seed = seed;
  o.interval = interval;
  return metamodel_sobol(gp, o);
}

}  // namespace posterior

TEST(MetamodelSobol, GpPosteriorIntervalCoversTheTruthAndShrinksWithPoints) {
  // A GP of a smooth 3-D function: the posterior interval must hold the true indices on most of 5 designs of 20
  // points, and narrow by more than half from 12 to 40 points (the posterior variance falls faster than 1/√n for a
  // smooth function).
  const std::vector<double> t = posterior::truth();
  int covered = 0, total = 0;
  double width_12 = 0.0, width_40 = 0.0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const SobolResult r = posterior::indices(latin_hypercube(20, 3, seed), seed, MetamodelInterval::gp_posterior);
    EXPECT_EQ(r.bootstrap, 100);
    EXPECT_NE(r.note.find("GP-posterior interval"), std::string::npos) << r.note;
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(r.first[k].lower, r.first[k].value);
      EXPECT_GE(r.first[k].upper, r.first[k].value);
      covered += r.first[k].lower <= t[k] && t[k] <= r.first[k].upper;
      covered += r.total[k].lower <= t[k] && t[k] <= r.total[k].upper;
      total += 2;
    }
    width_12 += posterior::max_half_width(
        posterior::indices(latin_hypercube(12, 3, seed), seed, MetamodelInterval::gp_posterior));
    width_40 += posterior::max_half_width(
        posterior::indices(latin_hypercube(40, 3, seed), seed, MetamodelInterval::gp_posterior));
  }
  EXPECT_GE(covered, 0.8 * total) << covered << " of " << total;
  EXPECT_LT(width_40, 0.5 * width_12) << width_40 / 5 << " against " << width_12 / 5;
}

TEST(MetamodelSobol, GpPosteriorIntervalSeesWhereThePointsAre) {
  // 20 points: spread over the cube, or with u1 crowded into [0, 0.4], of a response that turns over along u1. The
  // GP cannot know the response over the rest of u1's range: its posterior interval must be wider than for the
  // spread design, by more than a design bootstrap of the same two designs tells them apart.
  const Eigen::MatrixXd spread = latin_hypercube(20, 3, 4);
  Eigen::MatrixXd crowded = spread;
  crowded.col(0) *= 0.4;
  const auto width = [](const Eigen::MatrixXd& x, MetamodelInterval interval) {
    return posterior::max_half_width(posterior::indices(x, 4, interval, true));
  };
  const double posterior_spread = width(spread, MetamodelInterval::gp_posterior);
  const double posterior_crowded = width(crowded, MetamodelInterval::gp_posterior);
  const double bootstrap_spread = width(spread, MetamodelInterval::design_bootstrap);
  const double bootstrap_crowded = width(crowded, MetamodelInterval::design_bootstrap);
  EXPECT_GT(posterior_crowded, 3.0 * posterior_spread) << posterior_crowded << " against " << posterior_spread;
  EXPECT_GT(posterior_crowded / posterior_spread, bootstrap_crowded / bootstrap_spread)
      << bootstrap_crowded << " against " << bootstrap_spread;
}

TEST(MetamodelSobol, IntervalMethodNames) {
  EXPECT_EQ(metamodel_interval_from_string("gp-posterior"), MetamodelInterval::gp_posterior);
  EXPECT_EQ(to_string(MetamodelInterval::design_bootstrap), "design-bootstrap");
  try {
    metamodel_interval_from_string("posterior");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("valid: gp-posterior, design-bootstrap"), std::string::npos) << e.what();
  }
  MetamodelSobolOptions o;
  o.qmc_replicates = 1;
  EXPECT_THROW(o.validate(), InputError);
  o.qmc_replicates = 2;
  o.features = 0;
  EXPECT_THROW(o.validate(), InputError);
}

TEST(MetamodelSobol, StopRequestEndsTheRefits) {
  const Eigen::MatrixXd x = latin_hypercube(40, 2, 4);
  Eigen::VectorXd y(40);
  for (int i = 0; i < 40; ++i) y(i) = x(i, 0) + std::sin(3.0 * x(i, 1));
  auto m = make_metamodel("rbf-cubic");
  m->fit(x, y);
  MetamodelSobolOptions o;
  o.base = 128;
  o.bootstrap = 1000000;
  int polls = 0;
  o.stop = [&polls] { return ++polls > 30; };
  EXPECT_THROW(metamodel_sobol(*m, o), Stopped);
  EXPECT_EQ(polls, 31);
}

}  // namespace
}  // namespace demsa::sobol
