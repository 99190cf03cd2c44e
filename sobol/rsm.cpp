#include "sobol/rsm.hpp"

#include <fmt/core.h>
#include <Eigen/QR>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace demsa::sobol {

namespace {

/// Multi-indices of total degree <= p in d dimensions, by increasing degree (the constant first).
std::vector<std::vector<int>> multi_indices(int d, int p) {
  std::vector<std::vector<int>> out;
  std::vector<int> alpha(static_cast<std::size_t>(d), 0);
  for (int total = 0; total <= p; ++total) {
    // All alpha with |alpha| = total, in lexicographic order of (alpha_0, alpha_1, ...) descending.
    auto recurse = [&](auto&& self, int k, int left) -> void {
      if (k == d - 1) {
        alpha[static_cast<std::size_t>(k)] = left;
        out.push_back(alpha);
        return;
      }
      for (int a = left; a >= 0; --a) {
        alpha[static_cast<std::size_t>(k)] = a;
        self(self, k + 1, left - a);
      }
    };
    recurse(recurse, 0, total);
  }
  return out;
}

}  // namespace

double legendre01(int degree, double u) {
  const double t = 2.0 * u - 1.0;  // Legendre on [-1,1], scaled by sqrt(2n+1) to be orthonormal for U(0,1)
  switch (degree) {
    case 0:
      return 1.0;
    case 1:
      return std::sqrt(3.0) * t;
    case 2:
      return std::sqrt(5.0) * 0.5 * (3.0 * t * t - 1.0);
    case 3:
      return std::sqrt(7.0) * 0.5 * (5.0 * t * t * t - 3.0 * t);
    default:
      assert(false && "legendre01: degree 0..3");
      return 0.0;
  }
}

PolynomialRsm::PolynomialRsm(int degree) : m_degree(degree) { assert(degree >= 1 && degree <= 3); }

MetamodelKind PolynomialRsm::kind() const {
  return m_degree == 1 ? MetamodelKind::rsm1 : (m_degree == 2 ? MetamodelKind::rsm2 : MetamodelKind::rsm3);
}

int PolynomialRsm::term_count(int dimension, int degree) {
  // C(d + p, p)
  long c = 1;
  for (int k = 1; k <= degree; ++k) c = c * (dimension + k) / k;
  return static_cast<int>(c);
}

Eigen::MatrixXd PolynomialRsm::basis(const Eigen::MatrixXd& x) const {
  const Eigen::Index n = x.rows(), d = x.cols();
  // Tabulate L_k(x_ij) once, then multiply per term.
  std::vector<Eigen::MatrixXd> table;
  for (int k = 0; k <= m_degree; ++k) {
    Eigen::MatrixXd t(n, d);
    for (Eigen::Index j = 0; j < d; ++j)
      for (Eigen::Index i = 0; i < n; ++i) t(i, j) = legendre01(k, x(i, j));
    table.push_back(std::move(t));
  }
  Eigen::MatrixXd f = Eigen::MatrixXd::Ones(n, static_cast<Eigen::Index>(m_terms.size()));
  for (std::size_t t = 0; t < m_terms.size(); ++t)
    for (Eigen::Index j = 0; j < d; ++j) {
      const int a = m_terms[t][static_cast<std::size_t>(j)];
      if (a > 0) f.col(static_cast<Eigen::Index>(t)).array() *= table[static_cast<std::size_t>(a)].col(j).array();
    }
  return f;
}

void PolynomialRsm::fit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  const int d = static_cast<int>(x.cols());
  const int terms = term_count(std::max(d, 1), m_degree);
  store_training_data(x, y, terms);
  m_terms = multi_indices(d, m_degree);
  assert(static_cast<int>(m_terms.size()) == terms);
  const Eigen::MatrixXd f = basis(x);
  // Least squares by column-pivoting Householder QR (never the normal equations).
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(f);
  if (qr.rank() < terms)
    throw NumericalError(
        fmt::format("{}: the design matrix is singular (rank {} for {} terms): the {} samples do not "
                    "determine a degree-{} polynomial in {} inputs; use more or better spread "
                    "samples, or a lower degree",
                    name(), qr.rank(), terms, x.rows(), m_degree, d));
  m_coefficients = qr.solve(y);
  m_fitted_values = f * m_coefficients;
  // Hat-matrix diagonal h_ii = |row i of Q1|², Q1 the thin orthogonal factor.
  const Eigen::MatrixXd q1 = qr.householderQ() * Eigen::MatrixXd::Identity(x.rows(), terms);
  const Eigen::VectorXd h = q1.rowwise().squaredNorm();
  m_loo.resize(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const double r = y(i) - m_fitted_values(i);
    m_loo(i) = h(i) < 1.0 - 1e-10 ? r / (1.0 - h(i)) : std::numeric_limits<double>::quiet_NaN();
  }
  m_fitted = true;
}

void PolynomialRsm::restore(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& coefficients) {
  const int terms = term_count(std::max(static_cast<int>(x.cols()), 1), m_degree);
  if (coefficients.size() != terms)
    throw InputError(fmt::format("{}: {} coefficients for {} terms (degree {} in {} inputs)", name(),
                                 coefficients.size(), terms, m_degree, x.cols()));
  fit(x, y);
  m_coefficients = coefficients;
}

Eigen::VectorXd PolynomialRsm::predict(const Eigen::MatrixXd& x) const {
  assert(m_fitted && x.cols() == m_x.cols());
  // Blocks of rows keep the basis matrix small (rsm3 in 7-D has 120 terms per row).
  Eigen::VectorXd out(x.rows());
  const Eigen::Index block = 4096;
  for (Eigen::Index start = 0; start < x.rows(); start += block) {
    const Eigen::Index rows = std::min(block, x.rows() - start);
    out.segment(start, rows) = basis(x.middleRows(start, rows)) * m_coefficients;
  }
  return out;
}

Eigen::VectorXd PolynomialRsm::loo_residuals() const {
  assert(m_fitted);
  return m_loo;
}

MetamodelSummary PolynomialRsm::summary() const {
  assert(m_fitted);
  const int terms = static_cast<int>(m_terms.size());
  MetamodelSummary s = base_summary(m_fitted_values, terms);
  const int n = s.samples;
  s.adjusted_r2 = n > terms ? 1.0 - (1.0 - s.r2) * (n - 1.0) / static_cast<double>(n - terms)
                            : std::numeric_limits<double>::quiet_NaN();
  s.parameters.push_back({"degree", static_cast<double>(m_degree)});
  return s;
}

std::unique_ptr<Metamodel> PolynomialRsm::refit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) const {
  auto copy = std::make_unique<PolynomialRsm>(m_degree);
  copy->fit(x, y);
  return copy;
}

}  // namespace demsa::sobol
