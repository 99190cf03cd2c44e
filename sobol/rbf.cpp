#include "sobol/rbf.hpp"

#include <fmt/core.h>
#include <Eigen/LU>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace demsa::sobol {

namespace {

/// φ as a function of r² (avoids a square root for the thin plate).
double phi_of_r2(MetamodelKind kind, double r2) {
  if (r2 <= 0.0) return 0.0;
  if (kind == MetamodelKind::rbf_cubic) return r2 * std::sqrt(r2);  // r³
  return r2 * std::log(r2);                                         // r² log r²
}

}  // namespace

RbfInterpolant::RbfInterpolant(MetamodelKind kind) : m_kind(kind) {
  assert(kind == MetamodelKind::rbf_cubic || kind == MetamodelKind::rbf_tps);
}

double RbfInterpolant::phi(double r) const { return phi_of_r2(m_kind, r * r); }

void RbfInterpolant::fit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  const Eigen::Index d = x.cols();
  store_training_data(x, y, static_cast<int>(std::max<Eigen::Index>(d, 1) + 2));
  check_no_duplicates(x);
  const Eigen::Index n = x.rows();
  const Eigen::Index m = n + d + 1;
  // Saddle-point system [Φ P; Pᵀ 0] [w; c] = [y; 0] (Wendland 2005, Theorem 8.21).
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m, m);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = i + 1; j < n; ++j) {
      a(i, j) = phi_of_r2(m_kind, (x.row(i) - x.row(j)).squaredNorm());
      a(j, i) = a(i, j);
    }
    a(i, n) = 1.0;
    a(n, i) = 1.0;
    for (Eigen::Index k = 0; k < d; ++k) {
      a(i, n + 1 + k) = x(i, k);
      a(n + 1 + k, i) = x(i, k);
    }
  }
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  rhs.head(n) = y;
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  if (!lu.isInvertible())
    throw NumericalError(
        fmt::format("{}: the interpolation system is singular (rank {} of {}): the {} samples lie on "
                    "a hyperplane or are too few for the linear tail",
                    name(), lu.rank(), m, n));
  const Eigen::MatrixXd inverse = lu.inverse();
  const Eigen::VectorXd solution = inverse * rhs;
  const double residual = (a * solution - rhs).norm();
  if (!(residual <= 1e-6 * (rhs.norm() + 1.0)))
    throw NumericalError(
        fmt::format("{}: the interpolation system is too ill-conditioned (residual {:.3g})", name(), residual));
  m_weights = solution.head(n);
  m_tail = solution.tail(d + 1);
  // Rippa 1999: the LOO error at x_i is w_i / (M⁻¹)_ii for the full interpolation matrix M.
  m_loo.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) m_loo(i) = m_weights(i) / inverse(i, i);
  m_fitted = true;
}

void RbfInterpolant::restore(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& weights,
                             const Eigen::VectorXd& tail) {
  if (weights.size() != x.rows())
    throw InputError(fmt::format("{}: {} weights for {} centres", name(), weights.size(), x.rows()));
  if (tail.size() != x.cols() + 1)
    throw InputError(
        fmt::format("{}: {} tail coefficients for {} inputs (needs {})", name(), tail.size(), x.cols(), x.cols() + 1));
  fit(x, y);
  m_weights = weights;
  m_tail = tail;
}

Eigen::VectorXd RbfInterpolant::predict(const Eigen::MatrixXd& x) const {
  assert(m_fitted && x.cols() == m_x.cols());
  const Eigen::Index d = m_x.cols();
  Eigen::VectorXd out(x.rows());
  // Blocks of rows: squared distances by |a|² + |b|² - 2 a·b as one matrix product.
  const Eigen::Index block = 2048;
  const Eigen::VectorXd centre_norm = m_x.rowwise().squaredNorm();
  for (Eigen::Index start = 0; start < x.rows(); start += block) {
    const Eigen::Index rows = std::min(block, x.rows() - start);
    const Eigen::MatrixXd xb = x.middleRows(start, rows);
    Eigen::MatrixXd r2 = -2.0 * xb * m_x.transpose();
    r2.colwise() += xb.rowwise().squaredNorm();
    r2.rowwise() += centre_norm.transpose();
    for (Eigen::Index j = 0; j < r2.cols(); ++j)
      for (Eigen::Index i = 0; i < rows; ++i) r2(i, j) = phi_of_r2(m_kind, std::max(r2(i, j), 0.0));
    Eigen::VectorXd v = r2 * m_weights;
    v.array() += m_tail(0);
    v += xb * m_tail.tail(d);
    out.segment(start, rows) = v;
  }
  return out;
}

MetamodelSummary RbfInterpolant::summary() const {
  assert(m_fitted);
  // An interpolant reproduces its data: the fitted values are y itself.
  MetamodelSummary s = base_summary(m_y, static_cast<int>(m_weights.size() + m_tail.size()));
  return s;
}

std::unique_ptr<Metamodel> RbfInterpolant::refit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) const {
  auto copy = std::make_unique<RbfInterpolant>(m_kind);
  copy->fit(x, y);
  return copy;
}

}  // namespace demsa::sobol
