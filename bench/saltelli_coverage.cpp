// Honesty of the confidence intervals of `demsa sensitivity --saltelli` over scrambling seeds
// (docs/explanation/benchmarks.md, "Confidence intervals on QMC Saltelli designs"): for Ishigami (d = 3), Sobol' G (d =
// 8) and a 7-D polynomial, at a total base N, the percentile bootstrap of one scrambled design against Student-t
// intervals from R independently scrambled replicates of N/R rows. Prints, per function and method, the coverage of the
// 95% intervals of S1 and ST (over every input and seed), the mean interval width, the mean |error| of the estimate and
// their ratio. Also the RMS error of one design at a base that is not a power of two against the power of two below it.
//
// usage: build/bench/saltelli_coverage [BASE] [SEEDS]   (defaults 1024 50)
#include "sobol/saltelli.hpp"
#include "tests/sobol/analytic.hpp"

#include <fmt/core.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

namespace {

using namespace demsa::sobol;

struct TestFunction {
  std::string name;
  int dimension;
  std::function<Eigen::VectorXd(const Eigen::MatrixXd&)> f;
  std::vector<double> s1, st;
};

// Π_k (1 + c_k (3 u_k² - 1)): E[3u² - 1] = 0 and Var = 4/5 on U(0,1), so V_k = 0.8 c_k², V = Π(1 + V_k) - 1,
// S1_k = V_k / V, ST_k = V_k Π_{j≠k} (1 + V_j) / V (the product form of Sobol' 1993).
const std::vector<double> k_poly_c{1.0, 0.8, 0.6, 0.4, 0.3, 0.2, 0.1};

Eigen::VectorXd polynomial(const Eigen::MatrixXd& u) {
  Eigen::VectorXd y(u.rows());
  for (Eigen::Index i = 0; i < u.rows(); ++i) {
    double p = 1.0;
    for (std::size_t k = 0; k < k_poly_c.size(); ++k) {
      const double x = u(i, static_cast<Eigen::Index>(k));
      p *= 1.0 + k_poly_c[k] * (3.0 * x * x - 1.0);
    }
    y(i) = p;
  }
  return y;
}

std::vector<TestFunction> functions() {
  std::vector<TestFunction> out;
  out.push_back({"Ishigami (d = 3)", 3, demsa::sobol::test::ishigami, demsa::sobol::test::k_ishigami_s1,
                 demsa::sobol::test::k_ishigami_st});
  const std::vector<double> a{0, 1, 4.5, 9, 99, 99, 99, 99};
  TestFunction g{
      "Sobol' G (d = 8)", 8, [a](const Eigen::MatrixXd& u) { return demsa::sobol::test::sobol_g(u, a); }, {}, {}};
  demsa::sobol::test::sobol_g_indices(a, g.s1, g.st);
  out.push_back(g);
  TestFunction p{"polynomial (d = 7)", 7, polynomial, {}, {}};
  std::vector<double> v;
  double prod = 1.0;
  for (const double c : k_poly_c) {
    v.push_back(0.8 * c * c);
    prod *= 1.0 + v.back();
  }
  for (const double vk : v) {
    p.s1.push_back(vk / (prod - 1.0));
    p.st.push_back(vk * prod / (1.0 + vk) / (prod - 1.0));
  }
  out.push_back(p);
  return out;
}

struct Score {
  int covered = 0, count = 0;
  double width = 0.0, error = 0.0, squared = 0.0;
};

Score score(const TestFunction& f, int base, int replicates, int bootstrap, int seeds) {
  Score s;
  for (int seed = 1; seed <= seeds; ++seed) {
    SaltelliOptions o;
    o.base = base;
    o.dimension = f.dimension;
    o.seed = static_cast<std::uint64_t>(seed);
    o.replicates = replicates;
    SobolOptions so;
    so.interval = replicates > 1 ? SaltelliInterval::replicates : SaltelliInterval::bootstrap;
    so.bootstrap = bootstrap;
    so.seed = static_cast<std::uint64_t>(seed);
    const SobolResult r = sobol_indices(f.f, saltelli_design(o), so);
    for (std::size_t k = 0; k < f.s1.size(); ++k)
      for (const auto& [e, truth] : {std::pair{r.first[k], f.s1[k]}, std::pair{r.total[k], f.st[k]}}) {
        s.covered += e.lower <= truth && truth <= e.upper;
        s.width += e.upper - e.lower;
        s.error += std::abs(e.value - truth);
        s.squared += (e.value - truth) * (e.value - truth);
        ++s.count;
      }
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const int base = argc > 1 ? std::atoi(argv[1]) : 1024;
  const int seeds = argc > 2 ? std::atoi(argv[2]) : 50;
  if (base < 16 || seeds < 1) {
    fmt::print(stderr, "usage: saltelli_coverage [BASE >= 16] [SEEDS >= 1]\n");
    return 2;
  }
  fmt::print(
      "| function | intervals | coverage of 95% intervals | mean width | mean abs error | width / error | half-width / "
      "error |\n");
  fmt::print("|---|---|---|---|---|---|---|\n");
  for (const TestFunction& f : functions()) {
    const auto row = [&](const std::string& label, int replicates, int bootstrap) {
      const Score s = score(f, base, replicates, bootstrap, seeds);
      fmt::print("| {} | {} | {:.3f} | {:.4f} | {:.4f} | {:.1f} | {:.2f} |\n", f.name, label,
                 static_cast<double>(s.covered) / s.count, s.width / s.count, s.error / s.count, s.width / s.error,
                 s.width / s.error / 2);
    };
    row("bootstrap of one design (200 resamples)", 1, 200);
    for (const int r : {8, 16, 32})
      if (base % r == 0 && base / r >= 2) row(fmt::format("Student-t, {} replicates of {}", r, base / r), r, 0);
  }
  fmt::print("\nRMS error of S1 and ST of one design (no interval), {} seeds:\n", seeds);
  for (const TestFunction& f : functions())
    for (const int n : {1000, 1024, 10000, 8192, 16384}) {
      const Score s = score(f, n, 1, 0, seeds);
      fmt::print("  {} at N = {}: {:.2e}\n", f.name, n, std::sqrt(s.squared / s.count));
    }
  return 0;
}
