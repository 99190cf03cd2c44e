#pragma once
// Radial-basis-function interpolation with a linear polynomial tail (paper §5: the cubic ψ_T(r) = r³ and the thin
// plate ψ_P(r) = r² log r²; Wendland 2005, ch. 8): s(x) = Σ_i w_i φ(|x - x_i|) + c_0 + Σ_k c_k x_k with
// Σ_i w_i p(x_i) = 0 for every linear p. Solved as one symmetric saddle-point system by a full-pivoting LU.
// Leave-one-out residuals in closed form by Rippa's rule (Rippa 1999, Adv. Comput. Math. 11): e_i = w_i /
// (M^-1)_ii, M the full interpolation matrix.
#include "sobol/metamodel.hpp"

#include <Eigen/Core>

namespace demsa::sobol {

class RbfInterpolant final : public Metamodel {
 public:
  /// kind is rbf_cubic or rbf_tps (asserted).
  explicit RbfInterpolant(MetamodelKind kind);

  MetamodelKind kind() const override { return m_kind; }
  /// Needs d + 2 distinct points not all on one hyperplane (else NumericalError "singular").
  void fit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) override;
  Eigen::VectorXd predict(const Eigen::MatrixXd& x) const override;
  Eigen::VectorXd loo_residuals() const override { return m_loo; }
  MetamodelSummary summary() const override;
  std::unique_ptr<Metamodel> refit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) const override;
  bool interpolates() const override { return true; }

  /// A model saved to a file: refits to (x, y) (deterministic: the same LOO residuals and summary), then predicts
  /// with the saved weights w_i (one per row of x) and tail c_0..c_d. Throws InputError for wrong sizes.
  void restore(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& weights,
               const Eigen::VectorXd& tail);
  /// φ(r) of this kind.
  double phi(double r) const;
  const Eigen::VectorXd& weights() const { return m_weights; }  ///< w_i
  const Eigen::VectorXd& tail() const { return m_tail; }        ///< c_0, c_1..c_d

 private:
  MetamodelKind m_kind;
  Eigen::VectorXd m_weights;
  Eigen::VectorXd m_tail;
  Eigen::VectorXd m_loo;
};

}  // namespace demsa::sobol
