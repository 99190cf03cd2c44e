// Designs, metamodels and Sobol' analysis (docs/explanation/benchmarks.md, section "Designs, metamodels and Sobol'
// analysis").
//   build-*/bench/bench_sobol --benchmark_counters_tabular=true
// Counters: min_distance / centred_l2 of the optimised designs, Q2 of the fits.
#include "sobol/design.hpp"
#include "sobol/metamodel.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "tests/sobol/analytic.hpp"

#include <benchmark/benchmark.h>

#include <optional>

namespace {

using namespace demsa::sobol;

/// LHS of 160 points in 7-D optimised for `kind` with a budget of state.range(0) outer iterations.
void design_optimisation(benchmark::State& state, DesignKind kind) {
  DesignOptions o;
  o.kind = kind;
  o.samples = 160;
  o.dimension = 7;
  o.iterations = static_cast<int>(state.range(0));
  DesignResult r;
  for (auto _ : state) {
    r = make_design(o);
    benchmark::DoNotOptimize(r.points.data());
  }
  state.counters["min_distance"] = r.metrics.min_distance;
  if (const std::optional<double> c2 = r.metrics.centred_l2; c2.has_value()) state.counters["centred_l2"] = *c2;
  state.counters["iterations"] = r.iterations;
}
BENCHMARK_CAPTURE(design_optimisation, maximin, DesignKind::lhs_maximin)
    ->Arg(50)
    ->Arg(200)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(design_optimisation, cl2, DesignKind::lhs_cl2)->Arg(200)->Unit(benchmark::kSecond)->Iterations(1);

/// 160-point 7-D LHS of Ishigami with four inert inputs (the paper's sample size and dimension).
struct Training {
  Eigen::MatrixXd x = latin_hypercube(160, 7, 7);
  Eigen::VectorXd y = demsa::sobol::test::ishigami(x);
};

void fit(benchmark::State& state, const std::string& name) {
  const Training t;
  double q2 = 0.0;
  for (auto _ : state) {
    auto m = make_metamodel(name);
    m->fit(t.x, t.y);
    q2 = m->summary().q2;
  }
  state.counters["q2"] = q2;
}

void predict_1e6(benchmark::State& state, const std::string& name) {
  const Training t;
  auto m = make_metamodel(name);
  m->fit(t.x, t.y);
  const Eigen::MatrixXd q = scrambled_sobol(1000000, 7, 3);
  for (auto _ : state) {
    const Eigen::VectorXd y = m->predict(q);
    benchmark::DoNotOptimize(y.data());
  }
}

/// S1, ST, S2 at base 2^14 in 7-D (262144 predictions), no bootstrap; exact for RSM.
void full_analysis(benchmark::State& state, const std::string& name) {
  const Training t;
  auto m = make_metamodel(name);
  m->fit(t.x, t.y);
  MetamodelSobolOptions o;
  o.base = 1 << 14;
  o.second_order = true;
  o.bootstrap = 0;
  o.exact_for_rsm = state.range(0) != 0;
  SobolResult r;
  for (auto _ : state) r = metamodel_sobol(*m, o);
  state.counters["S1_x2"] = r.first[1].value;
}

BENCHMARK_CAPTURE(fit, rsm2, "rsm2")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(fit, rsm3, "rsm3")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(fit, rbf_cubic, "rbf-cubic")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(fit, rbf_tps, "rbf-tps")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(fit, gp, "gp")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(predict_1e6, rsm2, "rsm2")->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(predict_1e6, rsm3, "rsm3")->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(predict_1e6, rbf_cubic, "rbf-cubic")->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(predict_1e6, rbf_tps, "rbf-tps")->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(predict_1e6, gp, "gp")->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(full_analysis, rsm2, "rsm2")->Arg(0)->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(full_analysis, rsm3, "rsm3")->Arg(0)->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(full_analysis, rbf_cubic, "rbf-cubic")->Arg(0)->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(full_analysis, rbf_tps, "rbf-tps")->Arg(0)->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(full_analysis, gp, "gp")->Arg(0)->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(full_analysis, rsm3_exact, "rsm3")->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
