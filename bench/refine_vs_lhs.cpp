// `demsa refine` against a one-shot maximin LHS on a noisy 7-D simulator with known Sobol' indices
// (docs/benchmarks.md, section "Refinement against a one-shot maximin LHS"). A plain executable that drives the
// library directly, as `demsa refine` does through a study (a study would need LIGGGHTS): the refine loop of
// analysis/refinement.hpp and cli/refine.cpp — fit a GP with a nugget, Sobol' indices with the design-bootstrap
// intervals of sobol/metamodel_sobol.hpp, stop once every S1 and ST half-width is at most W, otherwise add B points
// by sobol::select_by_variance — against the smallest one-shot maximin LHS (the study's `lhs-maximin`) whose
// indices, fitted and bootstrapped the same way, reach the same widths (bisection on N, step `resolution`).
//
// Simulator: f(x) = Σ_i a_i φ(x_i) + c φ(x_1) φ(x_2) + ε, φ(u) = √2 sin(2π u) (mean 0, variance 1 on [0,1]),
// ε ~ N(0, σ²): V = Σ a_i² + c², S1_i = a_i²/V, ST_1 = (a_1² + c²)/V, ST_2 = (a_2² + c²)/V, ST_i = S1_i otherwise.
//
//   build/bench/refine_vs_lhs [FIRST_SEED] [LAST_SEED] [W] [BATCH] [INITIAL] [alc|variance]
#include "sobol/augment.hpp"
#include "sobol/design.hpp"
#include "sobol/gp.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/random.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

namespace {

using namespace demsa::sobol;

constexpr int k_d = 7;
constexpr std::array<double, k_d> k_a{1.0, 0.8, 0.6, 0.4, 0.25, 0.1, 0.0};
constexpr double k_c = 0.6;
constexpr double k_noise_sd = 0.15;

double phi(double u) { return std::numbers::sqrt2 * std::sin(2 * std::numbers::pi * u); }

Eigen::VectorXd simulate(const Eigen::MatrixXd& x, Random& rng) {
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    double v = k_c * phi(x(i, 0)) * phi(x(i, 1));
    for (int k = 0; k < k_d; ++k) v += k_a[static_cast<std::size_t>(k)] * phi(x(i, k));
    y(i) = v + k_noise_sd * rng.normal();
  }
  return y;
}

struct Truth {
  std::array<double, k_d> s1{}, st{};
};
Truth truth() {
  double v = k_c * k_c;
  for (double a : k_a) v += a * a;
  Truth t;
  for (int k = 0; k < k_d; ++k) {
    const double a2 = k_a[static_cast<std::size_t>(k)] * k_a[static_cast<std::size_t>(k)];
    t.s1[static_cast<std::size_t>(k)] = a2 / v;
    t.st[static_cast<std::size_t>(k)] = (a2 + (k < 2 ? k_c * k_c : 0.0)) / v;
  }
  return t;
}

struct Evaluation {
  double max_half_width = 0.0;
  double max_error = 0.0;  ///< largest |estimate - truth| over S1 and ST
  std::unique_ptr<GaussianProcess> gp;
};

Evaluation evaluate(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, std::uint64_t seed) {
  GpOptions gp;
  gp.nugget = true;
  gp.seed = seed;
  Evaluation e;
  e.gp = std::make_unique<GaussianProcess>(gp);
  e.gp->fit(x, y);
  MetamodelSobolOptions o;
  o.base = 1024;
  o.bootstrap = 60;
  o.seed = seed;
  const SobolResult r = metamodel_sobol(*e.gp, o);
  const Truth t = truth();
  for (int k = 0; k < k_d; ++k) {
    const auto& s1 = r.first[static_cast<std::size_t>(k)];
    const auto& st = r.total[static_cast<std::size_t>(k)];
    e.max_half_width = std::max({e.max_half_width, 0.5 * (s1.upper - s1.lower), 0.5 * (st.upper - st.lower)});
    e.max_error = std::max({e.max_error, std::abs(s1.value - t.s1[static_cast<std::size_t>(k)]),
                            std::abs(st.value - t.st[static_cast<std::size_t>(k)])});
  }
  return e;
}

Eigen::MatrixXd maximin_lhs(int n, std::uint64_t seed) {
  DesignOptions o;
  o.kind = DesignKind::lhs_maximin;
  o.samples = n;
  o.dimension = k_d;
  o.seed = seed;
  return make_design(o, false).points;
}

struct Outcome {
  int evaluations = 0;
  double half_width = 0.0;
  double error = 0.0;
};

Outcome refine(std::uint64_t seed, double target, int batch, int initial, int max_samples,
               SelectionCriterion criterion) {
  Random rng(seed * 7919 + 1);
  Eigen::MatrixXd x = maximin_lhs(initial, seed);
  Eigen::VectorXd y = simulate(x, rng);
  for (int step = 1;; ++step) {
    const Evaluation e = evaluate(x, y, seed);
    fmt::print("  refine seed {} step {:2d}: n = {:3d}  max half-width {:.4f}  max error {:.4f}\n", seed, step,
               x.rows(), e.max_half_width, e.max_error);
    std::fflush(stdout);
    if (e.max_half_width <= target || x.rows() >= max_samples)
      return {static_cast<int>(x.rows()), e.max_half_width, e.max_error};
    VarianceSelectionOptions o;
    o.criterion = criterion;
    o.candidates = 1000;
    o.batch = batch;
    o.seed = seed * 1000 + static_cast<std::uint64_t>(step);
    const Eigen::MatrixXd add = select_by_variance({e.gp.get()}, x, o);
    Eigen::MatrixXd nx(x.rows() + add.rows(), k_d);
    nx << x, add;
    Eigen::VectorXd ny(nx.rows());
    ny << y, simulate(add, rng);
    x = std::move(nx);
    y = std::move(ny);
  }
}

/// The smallest one-shot maximin LHS (to `resolution` points) whose max half-width is at most `target`: doubling
/// from `start`, then bisection (assumes the width falls with N, as it does on the median).
Outcome one_shot(std::uint64_t seed, double target, int start, int resolution, int max_samples) {
  const auto at = [&](int n) {
    Random rng(seed * 7919 + 2);
    const Eigen::MatrixXd x = maximin_lhs(n, seed + 1000);
    const Evaluation e = evaluate(x, simulate(x, rng), seed);
    fmt::print("  lhs    seed {} n = {:3d}: max half-width {:.4f}  max error {:.4f}\n", seed, n, e.max_half_width,
               e.max_error);
    std::fflush(stdout);
    return Outcome{n, e.max_half_width, e.max_error};
  };
  int lo = start;
  Outcome hi = at(start);
  if (hi.half_width <= target) return hi;
  int n = start;
  while (hi.half_width > target && n < max_samples) {
    lo = n;
    n = std::min(2 * n, max_samples);
    hi = at(n);
  }
  if (hi.half_width > target) return hi;
  while (hi.evaluations - lo > resolution) {
    const int mid = (lo + hi.evaluations) / 2;
    const Outcome m = at(mid);
    if (m.half_width <= target)
      hi = m;
    else
      lo = mid;
  }
  return hi;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace

int main(int argc, char** argv) {
  const int first = argc > 1 ? std::atoi(argv[1]) : 1;
  const int last = argc > 2 ? std::atoi(argv[2]) : 3;
  const double target = argc > 3 ? std::atof(argv[3]) : 0.05;
  const int batch = argc > 4 ? std::atoi(argv[4]) : 10;
  const int initial = argc > 5 ? std::atoi(argv[5]) : 30;
  const SelectionCriterion criterion = argc > 6 && std::string(argv[6]) == "variance"
                                           ? SelectionCriterion::variance
                                           : SelectionCriterion::integrated_variance;
  const int max_samples = 1200;
  std::vector<double> refined, shots, ratios, seconds_refine, seconds_shot;
  for (int seed = first; seed <= last; ++seed) {
    const auto s = static_cast<std::uint64_t>(seed);
    auto t0 = std::chrono::steady_clock::now();
    const Outcome r = refine(s, target, batch, initial, max_samples, criterion);
    auto t1 = std::chrono::steady_clock::now();
    const Outcome o = one_shot(s, target, initial, 5, max_samples);
    auto t2 = std::chrono::steady_clock::now();
    const double sr = std::chrono::duration<double>(t1 - t0).count();
    const double so = std::chrono::duration<double>(t2 - t1).count();
    fmt::print(
        "seed {}: refine {} evaluations (half-width {:.4f}, error {:.4f}, {:.0f} s); one-shot LHS {} "
        "(half-width {:.4f}, error {:.4f}, {:.0f} s); ratio {:.3f}\n",
        seed, r.evaluations, r.half_width, r.error, sr, o.evaluations, o.half_width, o.error, so,
        static_cast<double>(r.evaluations) / o.evaluations);
    std::fflush(stdout);
    refined.push_back(r.evaluations);
    shots.push_back(o.evaluations);
    ratios.push_back(static_cast<double>(r.evaluations) / o.evaluations);
    seconds_refine.push_back(sr);
    seconds_shot.push_back(so);
  }
  fmt::print(
      "median over seeds {}-{}: refine {} evaluations, one-shot maximin LHS {}, ratio {:.3f} (W = {}, batch "
      "{}, initial {}, noise sd {}); wall {:.0f} s / {:.0f} s\n",
      first, last, median(refined), median(shots), median(ratios), target, batch, initial, k_noise_sd,
      median(seconds_refine), median(seconds_shot));
}
