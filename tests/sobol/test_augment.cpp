// Growing designs: the Sobol' continuation is the fresh design's next rows, an LHS extension keeps the new points
// in empty strata and in [0,1], and its maximin distance stands beside a fresh design's; the variance-driven batch
// goes where a GP knows least and keeps its distance from the design.
#include "sobol/augment.hpp"
#include "sobol/design.hpp"
#include "sobol/error.hpp"
#include "sobol/gp.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

namespace demsa::sobol {
namespace {

Eigen::MatrixXd stack(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  Eigen::MatrixXd x(a.rows() + b.rows(), a.cols());
  x.topRows(a.rows()) = a;
  x.bottomRows(b.rows()) = b;
  return x;
}

TEST(Augment, SobolContinuationEqualsTheFreshDesignsNextRows) {
  for (const std::uint64_t seed : {1u, 7u, 12345u}) {
    const Eigen::MatrixXd fresh = scrambled_sobol(48, 5, seed);
    const Eigen::MatrixXd first = scrambled_sobol(20, 5, seed);
    const Eigen::MatrixXd next = extend_sobol(20, 28, 5, seed);
    EXPECT_EQ(stack(first, next), fresh) << "seed " << seed;
  }
}

TEST(Augment, SobolContinuationRefusesBadCounts) {
  EXPECT_THROW(extend_sobol(-1, 4, 3, 1), InputError);
  EXPECT_THROW(extend_sobol(4, 0, 3, 1), InputError);
  EXPECT_THROW(extend_sobol(4, 4, 41, 1), InputError);
}

TEST(Augment, LhsExtensionKeepsNewPointsInEmptyStrataAndInBounds) {
  for (const int added : {1, 7, 20, 45}) {
    DesignOptions o;
    o.kind = DesignKind::lhs_maximin;
    o.samples = 20;
    o.dimension = 6;
    o.seed = 3;
    const Eigen::MatrixXd old = make_design(o, false).points;
    const Eigen::MatrixXd add = extend_lhs(old, added, 99);
    ASSERT_EQ(add.rows(), added);
    ASSERT_EQ(add.cols(), 6);
    const int total = 20 + added;
    for (Eigen::Index k = 0; k < 6; ++k) {
      std::set<long> old_strata, new_strata;
      for (Eigen::Index i = 0; i < old.rows(); ++i) old_strata.insert(static_cast<long>(std::floor(old(i, k) * total)));
      for (Eigen::Index i = 0; i < add.rows(); ++i) {
        ASSERT_GE(add(i, k), 0.0);
        ASSERT_LT(add(i, k), 1.0);
        const long s = static_cast<long>(std::floor(add(i, k) * total));
        EXPECT_FALSE(old_strata.count(s)) << "new point " << i << " input " << k << " in an occupied stratum";
        EXPECT_TRUE(new_strata.insert(s).second) << "two new points in stratum " << s << " of input " << k;
      }
    }
  }
}

TEST(Augment, LhsExtensionIsDeterministicInItsSeed) {
  const Eigen::MatrixXd old = latin_hypercube(15, 4, 8);
  EXPECT_EQ(extend_lhs(old, 9, 5), extend_lhs(old, 9, 5));
  EXPECT_NE(extend_lhs(old, 9, 5), extend_lhs(old, 9, 6));
}

// An extended maximin design against fresh designs of the same total size: its minimum distance stays above the
// median of plain LHS (what an extension without the maximin search gives, roughly) and near the fresh maximin
// LHS'. Medians over 9 seeds.
TEST(Augment, ExtendedLhsIsAsSpaceFillingAsAFreshLhs) {
  std::vector<double> extended, fresh_plain, fresh_maximin, random_fill;
  for (std::uint64_t seed = 1; seed <= 9; ++seed) {
    DesignOptions o;
    o.kind = DesignKind::lhs_maximin;
    o.samples = 30;
    o.dimension = 7;
    o.seed = seed;
    const Eigen::MatrixXd old = make_design(o, false).points;
    extended.push_back(min_distance(stack(old, extend_lhs(old, 30, seed + 100))));
    // The naive extension: random points in the empty strata, no search.
    LhsExtensionOptions naive;
    naive.candidates = 1;
    naive.swaps_per_point = 0;
    random_fill.push_back(min_distance(stack(old, extend_lhs(old, 30, seed + 100, naive))));
    fresh_plain.push_back(min_distance(latin_hypercube(60, 7, seed)));
    o.samples = 60;
    fresh_maximin.push_back(min_distance(make_design(o, false).points));
  }
  const auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  EXPECT_GT(median(extended), median(fresh_plain));
  EXPECT_GT(median(extended), median(random_fill));
  EXPECT_GT(median(extended), 0.75 * median(fresh_maximin));
}

TEST(Augment, LhsExtensionRefusesBadInput) {
  const Eigen::MatrixXd old = latin_hypercube(10, 3, 1);
  EXPECT_THROW(extend_lhs(old, 0, 1), InputError);
  Eigen::MatrixXd outside = old;
  outside(2, 1) = 1.5;
  EXPECT_THROW(extend_lhs(outside, 3, 1), InputError);
  LhsExtensionOptions bad;
  bad.candidates = 0;
  EXPECT_THROW(extend_lhs(old, 3, 1, bad), InputError);
}

// A GP trained on points crowded in the lower half of [0,1]^2 knows least about the upper half: the batch goes
// there, its points keep apart from each other, and all are inside the cube.
TEST(Augment, VarianceSelectionGoesWhereTheGpKnowsLeast) {
  Eigen::MatrixXd x = latin_hypercube(24, 2, 4);
  x.col(1) *= 0.5;
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = std::sin(3 * x(i, 0)) + x(i, 1) * x(i, 1);
  GaussianProcess gp;
  gp.fit(x, y);
  VarianceSelectionOptions o;
  o.batch = 5;
  o.candidates = 500;
  o.seed = 2;
  for (const SelectionCriterion criterion : {SelectionCriterion::integrated_variance, SelectionCriterion::variance}) {
    SCOPED_TRACE(criterion == SelectionCriterion::variance ? "variance" : "integrated variance");
    o.criterion = criterion;
    const Eigen::MatrixXd chosen = select_by_variance({&gp}, x, o);
    ASSERT_EQ(chosen.rows(), 5);
    for (Eigen::Index i = 0; i < chosen.rows(); ++i) {
      EXPECT_GT(chosen(i, 1), 0.5) << "point " << i;
      EXPECT_LE(chosen(i, 0), 1.0);
      EXPECT_GE(chosen(i, 0), 0.0);
    }
    // Later picks see the earlier ones (the GP's variance with them added) and keep apart.
    EXPECT_GT(min_distance(chosen), 0.05);
    EXPECT_EQ(select_by_variance({&gp}, x, o), chosen);
  }
}

TEST(Augment, VarianceSelectionRefusesNoModel) {
  const Eigen::MatrixXd x = latin_hypercube(10, 2, 1);
  EXPECT_THROW(select_by_variance({}, x, {}), InputError);
  VarianceSelectionOptions o;
  o.candidates = 2;
  o.batch = 3;
  EXPECT_THROW(o.validate(), InputError);
}

}  // namespace
}  // namespace demsa::sobol
