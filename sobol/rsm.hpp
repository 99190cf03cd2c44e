#pragma once
// Polynomial response surface of total degree 1..3 (paper §5, "quadratic and cubic polynomial response surface",
// ref. [1] Forrester & Keane / Jin et al.), least squares by column-pivoting QR (never normal equations).
//
// The basis is the tensor product of orthonormal shifted Legendre polynomials on [0,1],
//   L0 = 1, L1 = √3 (2u-1), L2 = √5 (6u²-6u+1), L3 = √7 (20u³-30u²+12u-1),
// restricted to total degree <= p. It spans exactly the monomials of total degree <= p, so the fit is the usual
// RSM; the orthonormal basis makes the Sobol' decomposition of the fitted polynomial exact for uniform inputs on
// [0,1]^d (Sudret 2008, "Global sensitivity analysis using polynomial chaos expansions", eq. 32-33).
#include "sobol/metamodel.hpp"

#include <Eigen/Core>

#include <vector>

namespace demsa::sobol {

/// Orthonormal shifted Legendre polynomial of degree 0..3 at u.
double legendre01(int degree, double u);

class PolynomialRsm final : public Metamodel {
 public:
  explicit PolynomialRsm(int degree);  ///< 1, 2 or 3 (asserted)

  MetamodelKind kind() const override;
  void fit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) override;
  Eigen::VectorXd predict(const Eigen::MatrixXd& x) const override;
  /// e_i / (1 - h_ii) with h_ii the hat-matrix diagonal (Allen's PRESS; Myers & Montgomery, §2.7).
  Eigen::VectorXd loo_residuals() const override;
  MetamodelSummary summary() const override;
  std::unique_ptr<Metamodel> refit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) const override;
  bool interpolates() const override { return false; }

  int degree() const { return m_degree; }
  /// Multi-indices of the basis (one row of degrees per term, the constant first). Valid after fit().
  const std::vector<std::vector<int>>& terms() const { return m_terms; }
  /// Coefficients on the orthonormal Legendre basis, aligned with terms(). Valid after fit().
  const Eigen::VectorXd& coefficients() const { return m_coefficients; }
  /// A model saved to a file: refits to (x, y) (deterministic: the same terms, LOO residuals and summary), then
  /// predicts with the saved `coefficients` (the file's numbers, bit for bit). Throws InputError when their count
  /// is not C(d + p, p).
  void restore(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& coefficients);
  /// Number of terms of total degree <= p in d dimensions: C(d + p, p).
  static int term_count(int dimension, int degree);

 private:
  Eigen::MatrixXd basis(const Eigen::MatrixXd& x) const;

  int m_degree;
  std::vector<std::vector<int>> m_terms;
  Eigen::VectorXd m_coefficients;
  Eigen::VectorXd m_loo;
  Eigen::VectorXd m_fitted_values;
};

}  // namespace demsa::sobol
