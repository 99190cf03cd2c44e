// Bayesian calibration on metamodels (docs/explanation/benchmarks.md, section "Posterior sampling on metamodels"):
//   build-*/bench/bench_posterior --benchmark_counters_tabular=true
// 7 parameters, 4 targets each on its own metamodel kind (GP, cubic RBF, quadratic and cubic RSM) fitted to a
// 160-point LHS, 20,000 posterior draws (32 walkers × 625 steps) with the diagnostics.
#include "sobol/design.hpp"
#include "sobol/ensemble_sampler.hpp"
#include "sobol/metamodel.hpp"
#include "sobol/posterior.hpp"

#include <benchmark/benchmark.h>

#include <cmath>

namespace {

using namespace demsa::sobol;

double response(const Eigen::RowVectorXd& u, int k) {
  // Smooth responses of different shapes, each depending on several of the 7 inputs.
  switch (k) {
    case 0:
      return 30.0 + 8.0 * u(0) + 4.0 * u(1) * u(1) + 1.0 * u(2) * u(3);
    case 1:
      return std::sin(2.0 * u(0)) + 0.5 * u(4) + 0.2 * u(5) * u(6);
    case 2:
      return 1.0 + u(1) + 0.5 * u(2) * u(2) - 0.3 * u(5);
    default:
      return std::exp(0.5 * u(3)) + 0.4 * u(0) * u(6);
  }
}

void posterior_sampling(benchmark::State& state, bool with_diagnostics) {
  const Eigen::MatrixXd x = latin_hypercube(160, 7, 11);
  const std::vector<std::string> kinds{"gp", "rbf-cubic", "rsm2", "rsm3"};
  std::vector<std::unique_ptr<Metamodel>> models;
  std::vector<GaussianTarget> targets;
  Eigen::RowVectorXd truth = Eigen::RowVectorXd::Constant(7, 0.4);
  for (int k = 0; k < 4; ++k) {
    Eigen::VectorXd y(x.rows());
    for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = response(x.row(i), k);
    models.push_back(make_metamodel(kinds[static_cast<size_t>(k)]));
    models.back()->fit(x, y);
    const double t = response(truth, k);
    targets.push_back({kinds[static_cast<size_t>(k)], models.back().get(), {}, t, 0.03 * std::abs(t), 1.0});
  }
  const GaussianPosterior posterior(targets, 7);
  EnsembleOptions o;
  o.walkers = 32;
  o.steps = 625;
  o.burn_in = 0;
  const std::vector<double> lower(7, 0.0), upper(7, 1.0);
  EnsembleResult r;
  ChainDiagnostics d;
  for (auto _ : state) {
    r = sample_ensemble(posterior_function(posterior), lower, upper, o);
    if (with_diagnostics) d = diagnose(r);
    benchmark::DoNotOptimize(r.draws.data());
  }
  state.counters["draws"] = static_cast<double>(r.draws.rows());
  state.counters["evaluations"] = r.evaluations;
  state.counters["acceptance"] = r.acceptance;
  if (with_diagnostics) state.counters["max_tau"] = d.max_tau;
}
BENCHMARK_CAPTURE(posterior_sampling, sampler, false)->Unit(benchmark::kSecond)->Iterations(3);
BENCHMARK_CAPTURE(posterior_sampling, with_diagnostics, true)->Unit(benchmark::kSecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
