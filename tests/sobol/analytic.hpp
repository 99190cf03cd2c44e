#pragma once
// Analytic test functions with known Sobol' indices, on the unit cube.
#include <Eigen/Core>

#include <cmath>
#include <vector>

namespace demsa::sobol::test {

/// Ishigami function (Ishigami & Homma 1990), a = 7, b = 0.1, x_k = -π + 2π u_k. Inputs beyond the third are inert.
inline Eigen::VectorXd ishigami(const Eigen::MatrixXd& u) {
  const double pi = 3.14159265358979323846;
  Eigen::VectorXd y(u.rows());
  for (Eigen::Index i = 0; i < u.rows(); ++i) {
    const double x1 = -pi + 2 * pi * u(i, 0), x2 = -pi + 2 * pi * u(i, 1), x3 = -pi + 2 * pi * u(i, 2);
    const double s2 = std::sin(x2);
    y(i) = std::sin(x1) + 7.0 * s2 * s2 + 0.1 * x3 * x3 * x3 * x3 * std::sin(x1);
  }
  return y;
}
/// Analytic indices of ishigami (a = 7, b = 0.1).
inline const std::vector<double> k_ishigami_s1{0.3139, 0.4424, 0.0};
inline const std::vector<double> k_ishigami_st{0.5576, 0.4424, 0.2437};
inline constexpr double k_ishigami_s13 = 0.2437;

/// Sobol' G function (Saltelli & Sobol' 1995): Π_k (|4u_k - 2| + a_k) / (1 + a_k).
inline Eigen::VectorXd sobol_g(const Eigen::MatrixXd& u, const std::vector<double>& a) {
  Eigen::VectorXd y(u.rows());
  for (Eigen::Index i = 0; i < u.rows(); ++i) {
    double p = 1.0;
    for (std::size_t k = 0; k < a.size(); ++k)
      p *= (std::abs(4.0 * u(i, static_cast<Eigen::Index>(k)) - 2.0) + a[k]) / (1.0 + a[k]);
    y(i) = p;
  }
  return y;
}
/// S1 and ST of sobol_g: V_k = 1 / (3 (1 + a_k)²), V = Π(1 + V_k) - 1, ST_k = V_k Π_{j≠k}(1 + V_j) / V.
inline void sobol_g_indices(const std::vector<double>& a, std::vector<double>& s1, std::vector<double>& st) {
  std::vector<double> v;
  double prod = 1.0;
  for (const double ak : a) {
    v.push_back(1.0 / (3.0 * (1.0 + ak) * (1.0 + ak)));
    prod *= 1.0 + v.back();
  }
  const double total = prod - 1.0;
  s1.clear();
  st.clear();
  for (const double vk : v) {
    s1.push_back(vk / total);
    st.push_back(vk * prod / (1.0 + vk) / total);
  }
}

}  // namespace demsa::sobol::test
