// `demsa refine` against a one-shot maximin LHS on a noisy 7-D simulator with known Sobol' indices
// (docs/explanation/benchmarks.md, section "Refinement against a one-shot maximin LHS"). A plain executable that drives
// the library directly, as `demsa refine` does through a study (a study would need LIGGGHTS): the refine loop of
// analysis/refinement.hpp and cli/refine.cpp — fit a GP with a nugget, Sobol' indices with the intervals of
// sobol/metamodel_sobol.hpp (GP-posterior draws, or the design bootstrap), stop once every S1 and ST half-width is at
// most W, otherwise add B points by sobol::select_by_variance — against the smallest one-shot maximin LHS (the
// study's `lhs-maximin`) whose indices, fitted and given intervals the same way, reach the same widths (bisection on
// N, step `resolution`).
//
// Simulators (both with Gaussian noise ε ~ N(0, σ²) of known σ):
//   sines:      f(x) = Σ_i a_i φ(x_i) + c φ(x_1) φ(x_2) + ε, φ(u) = √2 sin(2π u) (mean 0, variance 1 on [0,1]):
//               V = Σ a_i² + c², S1_i = a_i²/V, ST_1 = (a_1² + c²)/V, ST_2 = (a_2² + c²)/V, ST_i = S1_i otherwise.
//               Homogeneous: every region of the cube is as hard to model as any other.
//   saturating: f(x) = 3 (1 - exp(-x_1/0.08)) (0.7 + 0.6 x_2) + 0.8 x_3 + 0.4 tanh(6 (x_4 - 0.5)) + 0.3 x_5 + ε,
//               x_6, x_7 inert: a response that rises steeply over the first tenth of one input and then flattens,
//               as a pile's angle does with the rolling friction, with an interaction of that input with another.
//               Its indices are computed once by QMC on the noise-free function at N = 2^18 (Saltelli 2010 S1,
//               Jansen ST; the QMC error there is below 1e-3, a twentieth of the target widths).
//
// With `fixed`, every GP (refine's and the one-shot designs') takes the length scales and nugget fitted once on a
// 400-point maximin LHS of the same simulator, instead of its own likelihood search. With the hyperparameters
// known, the GP's posterior covariance depends on where the points are and not on the values observed (Rasmussen &
// Williams 2006, eq. 2.26), so a sequential design can do no better than the best one-shot design of its size
// (the posterior-variance criteria are then non-adaptive; Santner, Williams & Notz 2003 §6.2): this mode measures
// how much of refinement's advantage is placement, with an interval that is not overconfident from hyperparameters
// fitted on few points.
//
//   build/bench/refine_vs_lhs [FIRST_SEED] [LAST_SEED] [W] [BATCH] [INITIAL] [alc|variance] [posterior|bootstrap]
//                             [sines|saturating] [learned|fixed]
#include "sobol/augment.hpp"
#include "sobol/design.hpp"
#include "sobol/gp.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/random.hpp"
#include "sobol/saltelli.hpp"

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

enum class Simulator { sines, saturating };

double noise_sd(Simulator s) { return s == Simulator::sines ? 0.15 : 0.05; }

double phi(double u) { return std::numbers::sqrt2 * std::sin(2 * std::numbers::pi * u); }

double response(Simulator s, const Eigen::Ref<const Eigen::RowVectorXd>& x) {
  if (s == Simulator::saturating)
    return 3.0 * (1.0 - std::exp(-x(0) / 0.08)) * (0.7 + 0.6 * x(1)) + 0.8 * x(2) +
           0.4 * std::tanh(6.0 * (x(3) - 0.5)) + 0.3 * x(4);
  double v = k_c * phi(x(0)) * phi(x(1));
  for (int k = 0; k < k_d; ++k) v += k_a[static_cast<std::size_t>(k)] * phi(x(k));
  return v;
}

Eigen::VectorXd simulate(Simulator s, const Eigen::MatrixXd& x, Random& rng) {
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = response(s, x.row(i)) + noise_sd(s) * rng.normal();
  return y;
}

struct Truth {
  std::array<double, k_d> s1{}, st{};
  double variance = 0.0;
};
Truth truth(Simulator s) {
  Truth t;
  if (s == Simulator::sines) {
    double v = k_c * k_c;
    for (double a : k_a) v += a * a;
    t.variance = v;
    for (int k = 0; k < k_d; ++k) {
      const double a2 = k_a[static_cast<std::size_t>(k)] * k_a[static_cast<std::size_t>(k)];
      t.s1[static_cast<std::size_t>(k)] = a2 / v;
      t.st[static_cast<std::size_t>(k)] = (a2 + (k < 2 ? k_c * k_c : 0.0)) / v;
    }
    return t;
  }
  SaltelliOptions so;
  so.base = 1 << 18;
  so.dimension = k_d;
  so.seed = 20261201;
  SobolOptions o;
  o.interval = SaltelliInterval::none;
  const SobolResult r = sobol_indices(
      [s](const Eigen::MatrixXd& x) {
        Eigen::VectorXd y(x.rows());
        for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = response(s, x.row(i));
        return y;
      },
      saltelli_design(so), o);
  t.variance = r.variance;
  for (int k = 0; k < k_d; ++k) {
    t.s1[static_cast<std::size_t>(k)] = r.first[static_cast<std::size_t>(k)].value;
    t.st[static_cast<std::size_t>(k)] = r.total[static_cast<std::size_t>(k)].value;
  }
  return t;
}

struct Setup {
  Simulator simulator = Simulator::sines;
  Truth truth;
  MetamodelInterval interval = MetamodelInterval::gp_posterior;
  bool fixed = false;  ///< every GP takes `lengths` and `nugget` instead of its own likelihood search
  Eigen::VectorXd lengths;
  double nugget = 0.0;
};

struct Evaluation {
  double max_half_width = 0.0;
  double max_error = 0.0;  ///< largest |estimate - truth| over S1 and ST
  int covered = 0;         ///< S1 and ST intervals (of 2d) that hold the true index
  std::unique_ptr<GaussianProcess> gp;
};

Evaluation evaluate(const Setup& setup, const Eigen::MatrixXd& x, const Eigen::VectorXd& y, std::uint64_t seed) {
  GpOptions gp;
  gp.nugget = true;
  gp.seed = seed;
  Evaluation e;
  e.gp = std::make_unique<GaussianProcess>(gp);
  if (setup.fixed)
    e.gp->fit_with(x, y, setup.lengths, setup.nugget);
  else
    e.gp->fit(x, y);
  MetamodelSobolOptions o;
  o.base = 1024;
  o.interval = setup.interval;
  // 60 design-bootstrap refits (each a refit and a QMC pass); 200 posterior draws (cheap: one matrix product).
  o.bootstrap = setup.interval == MetamodelInterval::design_bootstrap ? 60 : 200;
  o.seed = seed;
  const SobolResult r = metamodel_sobol(*e.gp, o);
  const Truth& t = setup.truth;
  for (int k = 0; k < k_d; ++k) {
    const auto& s1 = r.first[static_cast<std::size_t>(k)];
    const auto& st = r.total[static_cast<std::size_t>(k)];
    e.max_half_width = std::max({e.max_half_width, 0.5 * (s1.upper - s1.lower), 0.5 * (st.upper - st.lower)});
    e.max_error = std::max({e.max_error, std::abs(s1.value - t.s1[static_cast<std::size_t>(k)]),
                            std::abs(st.value - t.st[static_cast<std::size_t>(k)])});
    e.covered += s1.lower <= t.s1[static_cast<std::size_t>(k)] && t.s1[static_cast<std::size_t>(k)] <= s1.upper;
    e.covered += st.lower <= t.st[static_cast<std::size_t>(k)] && t.st[static_cast<std::size_t>(k)] <= st.upper;
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
  int covered = 0;
};

Outcome refine(const Setup& setup, std::uint64_t seed, double target, int batch, int initial, int max_samples,
               SelectionCriterion criterion) {
  Random rng(seed * 7919 + 1);
  Eigen::MatrixXd x = maximin_lhs(initial, seed);
  Eigen::VectorXd y = simulate(setup.simulator, x, rng);
  for (int step = 1;; ++step) {
    const Evaluation e = evaluate(setup, x, y, seed);
    fmt::print("  refine seed {} step {:2d}: n = {:3d}  max half-width {:.4f}  max error {:.4f}  covered {}/{}\n", seed,
               step, x.rows(), e.max_half_width, e.max_error, e.covered, 2 * k_d);
    std::fflush(stdout);
    if (e.max_half_width <= target || x.rows() >= max_samples)
      return {static_cast<int>(x.rows()), e.max_half_width, e.max_error, e.covered};
    VarianceSelectionOptions o;
    o.criterion = criterion;
    o.candidates = 1000;
    o.batch = batch;
    o.seed = seed * 1000 + static_cast<std::uint64_t>(step);
    const Eigen::MatrixXd add = select_by_variance({e.gp.get()}, x, o);
    Eigen::MatrixXd nx(x.rows() + add.rows(), k_d);
    nx << x, add;
    Eigen::VectorXd ny(nx.rows());
    ny << y, simulate(setup.simulator, add, rng);
    x = std::move(nx);
    y = std::move(ny);
  }
}

/// The smallest one-shot maximin LHS (to `resolution` points) whose max half-width is at most `target`: doubling
/// from `start`, then bisection (assumes the width falls with N, as it does on the median).
Outcome one_shot(const Setup& setup, std::uint64_t seed, double target, int start, int resolution, int max_samples) {
  const auto at = [&](int n) {
    Random rng(seed * 7919 + 2);
    const Eigen::MatrixXd x = maximin_lhs(n, seed + 1000);
    const Evaluation e = evaluate(setup, x, simulate(setup.simulator, x, rng), seed);
    fmt::print("  lhs    seed {} n = {:3d}: max half-width {:.4f}  max error {:.4f}  covered {}/{}\n", seed, n,
               e.max_half_width, e.max_error, e.covered, 2 * k_d);
    std::fflush(stdout);
    return Outcome{n, e.max_half_width, e.max_error, e.covered};
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
  Setup setup;
  setup.interval = argc > 7 && std::string(argv[7]) == "bootstrap" ? MetamodelInterval::design_bootstrap
                                                                   : MetamodelInterval::gp_posterior;
  setup.simulator = argc > 8 && std::string(argv[8]) == "saturating" ? Simulator::saturating : Simulator::sines;
  setup.truth = truth(setup.simulator);
  if (argc > 9 && std::string(argv[9]) == "fixed") {
    if (setup.interval != MetamodelInterval::gp_posterior) {
      fmt::print(stderr, "refine_vs_lhs: `fixed` needs the GP-posterior interval (a bootstrap refit would fit)\n");
      return 2;
    }
    Random rng(424242);
    const Eigen::MatrixXd x = maximin_lhs(400, 424242);
    GpOptions gp;
    gp.nugget = true;
    gp.seed = 424242;
    GaussianProcess reference(gp);
    reference.fit(x, simulate(setup.simulator, x, rng));
    setup.fixed = true;
    setup.lengths = reference.lengths();
    setup.nugget = reference.nugget();
    fmt::print("fixed hyperparameters (400-point maximin LHS): nugget {:.4g}, lengths", setup.nugget);
    for (double v : setup.lengths) fmt::print(" {:.4g}", v);
    fmt::print("\n");
  }
  fmt::print("simulator {} (variance {:.5f}, noise sd {}), interval {}\n  S1 =", argc > 8 ? argv[8] : "sines",
             setup.truth.variance, noise_sd(setup.simulator), to_string(setup.interval));
  for (double v : setup.truth.s1) fmt::print(" {:.4f}", v);
  fmt::print("\n  ST =");
  for (double v : setup.truth.st) fmt::print(" {:.4f}", v);
  fmt::print("\n");
  const int max_samples = 1200;
  std::vector<double> refined, shots, ratios, seconds_refine, seconds_shot;
  for (int seed = first; seed <= last; ++seed) {
    const auto s = static_cast<std::uint64_t>(seed);
    auto t0 = std::chrono::steady_clock::now();
    const Outcome r = refine(setup, s, target, batch, initial, max_samples, criterion);
    auto t1 = std::chrono::steady_clock::now();
    const Outcome o = one_shot(setup, s, target, initial, 5, max_samples);
    auto t2 = std::chrono::steady_clock::now();
    const double sr = std::chrono::duration<double>(t1 - t0).count();
    const double so = std::chrono::duration<double>(t2 - t1).count();
    fmt::print(
        "seed {}: refine {} evaluations (half-width {:.4f}, error {:.4f}, covered {}/{}, {:.0f} s); one-shot LHS {} "
        "(half-width {:.4f}, error {:.4f}, covered {}/{}, {:.0f} s); ratio {:.3f}\n",
        seed, r.evaluations, r.half_width, r.error, r.covered, 2 * k_d, sr, o.evaluations, o.half_width, o.error,
        o.covered, 2 * k_d, so, static_cast<double>(r.evaluations) / o.evaluations);
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
      first, last, median(refined), median(shots), median(ratios), target, batch, initial, noise_sd(setup.simulator),
      median(seconds_refine), median(seconds_shot));
}
