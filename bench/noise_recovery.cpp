// The noise half of issue #18's bench: a noisy 7-D synthetic simulator with known noise variance, its noise variance
// recovered from replicates (sobol/noise.hpp) at P points x R repeats, over seeds; and what the measured nugget
// does to the GP (sobol/gp.hpp, GpOptions::noise_share) against an estimated one, judged against the noise-free
// function. Not a timing: prints a Markdown table for docs/explanation/benchmarks.md.
//
// Simulator: y = G(x) + ε, G Sobol's g-function (Saltelli & Sobol' 1995; Saltelli et al., "Global Sensitivity
// Analysis. The Primer", 2008, §3.6) on [0,1]^7 with a = (0, 1, 4.5, 9, 99, 99, 99), Var G = Π(1 + V_i) − 1,
// V_i = 1 / (3 (1 + a_i)²); ε ~ N(0, σ²) with σ² = share/(1 − share) Var G, so that σ² is `share` of Var y.
//
//   noise_recovery [--seeds K] [--share S]
#include "sobol/design.hpp"
#include "sobol/gp.hpp"
#include "sobol/noise.hpp"
#include "sobol/random.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

using namespace demsa::sobol;

constexpr std::array<double, 7> k_a{0.0, 1.0, 4.5, 9.0, 99.0, 99.0, 99.0};

double g_function(const Eigen::RowVectorXd& x) {
  double y = 1.0;
  for (int i = 0; i < 7; ++i)
    y *= (std::abs(4.0 * x(i) - 2.0) + k_a[static_cast<std::size_t>(i)]) / (1.0 + k_a[static_cast<std::size_t>(i)]);
  return y;
}

double g_variance() {
  double v = 1.0;
  for (double a : k_a) v *= 1.0 + 1.0 / (3.0 * (1.0 + a) * (1.0 + a));
  return v - 1.0;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Ratios recovered / true noise variance over `seeds` seeds at P points x R repeats (the points: the first P of a
/// 64-point LHS; the repeats: fresh noise draws at the same point).
struct Recovery {
  std::vector<double> ratios;
  int covered = 0;  ///< seeds whose 95 % chi-square interval held the true variance
};

Recovery recover(int points, int repeats, int seeds, double sigma2) {
  Recovery r;
  for (int seed = 1; seed <= seeds; ++seed) {
    const Eigen::MatrixXd x = latin_hypercube(64, 7, static_cast<std::uint64_t>(seed));
    // A noise stream of its own per seed and configuration.
    Random noise(1000 + 7919 * static_cast<std::uint64_t>(seed) + 31 * static_cast<std::uint64_t>(points) +
                 static_cast<std::uint64_t>(repeats));
    std::vector<std::vector<double>> groups(static_cast<std::size_t>(points));
    for (int p = 0; p < points; ++p)
      for (int k = 0; k < repeats; ++k)
        groups[static_cast<std::size_t>(p)].push_back(g_function(x.row(p)) + std::sqrt(sigma2) * noise.normal());
    const NoiseEstimate e = pooled_noise_variance(groups, 0.95);
    r.ratios.push_back(e.variance / sigma2);
    r.covered += e.lower <= sigma2 && sigma2 <= e.upper;
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 5;
  double share = 0.2;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--seeds")
      seeds = std::atoi(argv[i + 1]);
    else if (flag == "--share")
      share = std::atof(argv[i + 1]);
  }
  const double var_g = g_variance();
  const double sigma2 = share / (1.0 - share) * var_g;
  fmt::print("7-D g-function, Var G = {:.5f}; noise variance {:.5f} ({:.0f} % of Var y); {} seeds\n\n", var_g, sigma2,
             100.0 * share, seeds);
  fmt::print(
      "| P points | R repeats | extra cases P(R−1) | dof | recovered/true per seed | median | max |ratio − 1| | "
      "95 % CI held |\n|---|---|---|---|---|---|---|---|\n");
  for (const auto& [points, repeats] :
       std::vector<std::pair<int, int>>{{4, 3}, {8, 3}, {16, 3}, {16, 5}, {32, 3}, {32, 5}, {64, 3}, {64, 5}}) {
    const Recovery r = recover(points, repeats, seeds, sigma2);
    std::string per_seed;
    double worst = 0.0;
    for (double q : r.ratios) {
      per_seed += (per_seed.empty() ? "" : ", ") + fmt::format("{:.2f}", q);
      worst = std::max(worst, std::abs(q - 1.0));
    }
    fmt::print("| {} | {} | {} | {} | {} | {:.2f} | {:.2f} | {}/{} |\n", points, repeats, points * (repeats - 1),
               points * (repeats - 1), per_seed, median(r.ratios), worst, r.covered, seeds);
  }

  // The GP on n noisy design points: nugget set from the noise measured at 16 x 5 replicates (the first 16 design
  // points and 4 more runs of each), against the nugget estimated by likelihood; RMSE against the noise-free G at 2000
  // test points, relative to sd G. Medians over the seeds.
  fmt::print(
      "\n| design points n | GP nugget | median σ²τ / true noise variance | median RMSE vs noise-free G / sd G | "
      "seeds where it is the smaller RMSE |\n|---|---|---|---|---|\n");
  const Eigen::MatrixXd test = latin_hypercube(2000, 7, 999);
  Eigen::VectorXd truth(test.rows());
  for (Eigen::Index i = 0; i < test.rows(); ++i) truth(i) = g_function(test.row(i));
  for (const int n : {24, 64}) {
    std::array<std::vector<double>, 2> ratio, rmse;
    for (int seed = 1; seed <= seeds; ++seed) {
      const Eigen::MatrixXd x = latin_hypercube(n, 7, static_cast<std::uint64_t>(seed));
      Random noise(5000 + static_cast<std::uint64_t>(seed));
      Eigen::VectorXd y(x.rows());
      for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = g_function(x.row(i)) + std::sqrt(sigma2) * noise.normal();
      std::vector<std::vector<double>> groups(16);
      for (int p = 0; p < 16; ++p) {
        groups[static_cast<std::size_t>(p)].push_back(y(p));
        for (int k = 1; k < 5; ++k)
          groups[static_cast<std::size_t>(p)].push_back(g_function(x.row(p)) + std::sqrt(sigma2) * noise.normal());
      }
      const NoiseEstimate e = pooled_noise_variance(groups, 0.95);
      const double var_y = (y.array() - y.mean()).square().mean();
      for (const int measured : {0, 1}) {
        GpOptions options;
        options.nugget = true;
        options.max_nugget = 1.0;
        if (measured) options.noise_share = e.variance / var_y;
        GaussianProcess gp(options);
        gp.fit(x, y);
        const Eigen::VectorXd predicted = gp.predict(test);
        ratio[static_cast<std::size_t>(measured)].push_back(gp.process_variance() * gp.nugget() / sigma2);
        rmse[static_cast<std::size_t>(measured)].push_back(std::sqrt((predicted - truth).array().square().mean()) /
                                                           std::sqrt(var_g));
      }
    }
    for (const int measured : {0, 1}) {
      int smaller = 0;
      for (int k = 0; k < seeds; ++k)
        smaller += rmse[static_cast<std::size_t>(measured)][static_cast<std::size_t>(k)] <
                   rmse[static_cast<std::size_t>(1 - measured)][static_cast<std::size_t>(k)];
      fmt::print("| {} | {} | {:.2f} | {:.3f} | {}/{} |\n", n, measured ? "from replicates (16 x 5)" : "estimated",
                 median(ratio[static_cast<std::size_t>(measured)]), median(rmse[static_cast<std::size_t>(measured)]),
                 smaller, seeds);
    }
  }
  return 0;
}
