#include "orchestrator/analysis/experiment_plan.hpp"

#include "orchestrator/analysis/calibration_posterior.hpp"
#include "orchestrator/analysis/joint_studies.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"
#include "sobol/design.hpp"
#include "sobol/ensemble_sampler.hpp"
#include "sobol/importance_sampler.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/posterior.hpp"
#include "sobol/random.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <fstream>
#include <limits>
#include <memory>
#include <numeric>
#include <thread>

#include <unistd.h>

namespace demsa::analysis {

using namespace demsa::util;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();

/// An observable's sd as given, and whether a measured observable took it.
struct SdOverride {
  ObservableSd given;
  bool used = false;
  std::string text() const { return fmt::format("{}={:.12g}", given.observable.label(), given.sd); }
};

/// Total indices of a fitted metamodel on its study's unit cube: the QMC Saltelli estimate of sobol::metamodel_sobol at
/// N = 2048 without intervals, enough to sort parameters at the k_plan_sensitive line.
std::vector<double> total_indices(const sobol::Metamodel& model, int dimension, std::uint64_t seed) {
  sobol::MetamodelSobolOptions options;
  options.base = 2048;
  options.bootstrap = 0;
  options.seed = seed;
  options.exact_for_rsm = false;
  try {
    std::vector<double> st;
    for (const sobol::IndexEstimate& e : sobol::metamodel_sobol(model, options).total)
      st.push_back(std::clamp(e.value, 0.0, 1.0));
    return st;
  } catch (const sobol::NumericalError&) {
    return std::vector<double>(static_cast<size_t>(dimension), 0.0);  // a constant response: no parameter matters
  }
}

/// Per parameter, max - min of its main effect z_j(t) = E[m(u) | u_j = t] over t in [0, 1] (Oakley & O'Hagan 2004,
/// "Probabilistic sensitivity analysis of complex models: a Bayesian approach", J. R. Stat. Soc. B 66: the main
/// effect, whose variance is S_j's numerator): the mean prediction over 512 scrambled Sobol' points with u_j set to t,
/// at 17 values of t.
std::vector<double> main_effect_ranges(const sobol::Metamodel& model, int dimension, std::uint64_t seed) {
  constexpr int k_points = 512;
  constexpr int k_grid = 17;
  const Eigen::MatrixXd base = sobol::scrambled_sobol(k_points, dimension, seed);
  std::vector<double> range(static_cast<size_t>(dimension), 0.0);
  for (int j = 0; j < dimension; ++j) {
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (int g = 0; g < k_grid; ++g) {
      Eigen::MatrixXd x = base;
      x.col(j).setConstant(static_cast<double>(g) / (k_grid - 1));
      const double mean = model.predict(x).mean();
      low = std::min(low, mean);
      high = std::max(high, mean);
    }
    range[static_cast<size_t>(j)] = std::isfinite(high - low) ? high - low : k_nan;
  }
  return range;
}

std::string subset_label(const PlanSubset& s) { return join(s.studies, " + "); }

/// One truth's posterior: by importance sampling over the shared prior sample, or by the ensemble sampler.
struct PlanChain {
  std::vector<std::pair<double, double>> interval;  ///< 90 % interval per parameter
  bool adapted = false;                             ///< by adaptive importance sampling
  bool sampled = false;                             ///< by the ensemble sampler
  bool converged = true;                            ///< false: the sampler's chain did not converge
  std::string advice;                               ///< the diagnostics' words when not converged
};

/// One truth's posterior where the prior sample carries too little of it: adaptive importance sampling
/// (sobol::adaptive_importance_sample) started from the prior sample's weights. Its draws are independent, so a
/// posterior narrow in two directions and flat in five, where the ensemble sampler's walkers took autocorrelation
/// times of up to 1147 steps, needs no chain. `adapted` is false when no round reached k_plan_min_ess.
PlanChain adapt_plan_posterior(const sobol::GaussianPosterior& posterior, const Eigen::MatrixXd& u,
                               const Eigen::VectorXd& log_w, std::uint64_t seed) {
  const int d = static_cast<int>(u.cols());
  const std::vector<double> lower(static_cast<size_t>(d), 0.0), upper(static_cast<size_t>(d), 1.0);
  sobol::ImportanceOptions options;
  options.draws = k_plan_importance_draws;
  options.rounds = k_plan_importance_rounds;
  options.min_ess = k_plan_min_ess;
  options.seed = seed;
  const sobol::ImportanceResult r =
      sobol::adaptive_importance_sample(sobol::posterior_function(posterior), lower, upper, u, log_w, options);
  PlanChain chain;
  chain.adapted = r.converged;
  if (r.converged)
    for (int j = 0; j < d; ++j) chain.interval.push_back(r.interval(j));
  return chain;
}

/// One truth's posterior where adaptive importance sampling falls short too: the ensemble sampler, started at the
/// k_plan_walkers_per_parameter d + 2 prior points of largest weight rather than uniformly in the box
/// (sobol::highest_density_start says why). A posterior narrower than the prior sample's spacing is then found at
/// once; started uniformly, a fixed chain did not reach it. The chain is then doubled, each run
/// continuing the last ensemble, until sobol::diagnose calls it converged (steps >= 50 τ, split R̂ < 1.05) or
/// k_plan_max_steps.
PlanChain sample_plan_posterior(const sobol::GaussianPosterior& posterior, const Eigen::MatrixXd& u,
                                const Eigen::VectorXd& log_w, std::uint64_t seed) {
  const int d = static_cast<int>(u.cols());
  const std::vector<double> lower(static_cast<size_t>(d), 0.0), upper(static_cast<size_t>(d), 1.0);
  sobol::EnsembleOptions sampler;
  sampler.walkers = k_plan_walkers_per_parameter * d + 2;
  sampler.start = sobol::highest_density_start(u, log_w, sampler.walkers);
  sampler.burn_in = k_plan_burn_in;
  sampler.steps = k_plan_steps;
  sampler.seed = seed;
  const sobol::BatchLogDensity density = sobol::posterior_function(posterior);
  sobol::EnsembleResult r = sobol::sample_ensemble(density, lower, upper, sampler);
  sobol::ChainDiagnostics diag = sobol::diagnose(r);
  while (!diag.converged && 2 * sampler.steps <= k_plan_max_steps) {
    sampler.start = r.last();
    sampler.burn_in = 0;
    sampler.steps *= 2;
    ++sampler.seed;
    r = sobol::sample_ensemble(density, lower, upper, sampler);
    diag = sobol::diagnose(r);
  }
  PlanChain chain;
  chain.sampled = true;
  const std::vector<sobol::MarginalSummary> m = sobol::summarise_marginals(r, lower, upper);
  for (int j = 0; j < d; ++j) chain.interval.emplace_back(m[static_cast<size_t>(j)].q05, m[static_cast<size_t>(j)].q95);
  chain.converged = diag.converged;
  chain.advice = fmt::format(
      "its chain of {} steps of {} walkers has τ up to {:.0f} steps (converged: >= 50 τ) and "
      "split R̂ {:.3f} (converged: < 1.05)",
      r.steps, r.walkers, diag.max_tau, diag.max_rhat);
  return chain;
}

/// f(0) .. f(n - 1) on up to `threads` threads (0: one per core), results in order. Each call must touch only its own
/// result and shared state it reads; the first exception thrown (by index) is rethrown once every thread has joined.
template <class F>
auto plan_in_parallel(int n, int threads, const F& f) -> std::vector<decltype(f(0))> {
  std::vector<decltype(f(0))> results(static_cast<size_t>(n));
  std::vector<std::exception_ptr> errors(static_cast<size_t>(n));
  std::atomic<int> next{0};
  const auto work = [&] {
    for (int i = next++; i < n; i = next++) {
      try {
        results[static_cast<size_t>(i)] = f(i);
      } catch (...) {
        errors[static_cast<size_t>(i)] = std::current_exception();
      }
    }
  };
  const int wanted = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (int t = 1; t < std::clamp(wanted, 1, std::max(n, 1)); ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  return results;
}

}  // namespace

void PlanOptions::validate() const {
  if (dirs.empty()) throw UserError("plan: a study folder is required");
  if (static_cast<int>(dirs.size()) > k_plan_max_studies)
    throw UserError(fmt::format("plan: {} studies given; at most {} ({} subsets)", dirs.size(), k_plan_max_studies,
                                (1 << k_plan_max_studies) - 1));
  if (truths < 2 || truths > 1000) throw UserError(fmt::format("PlanOptions.truths {}: must be in 2..1000", truths));
  if (threads < 0 || threads > 256)
    throw UserError(fmt::format("PlanOptions.threads {}: must be in 0..256 (0: one per core)", threads));
  if (!(goal > 0 && goal < 1)) throw UserError(fmt::format("PlanOptions.goal {:g}: must be in (0, 1)", goal));
  for (size_t k = 0; k < sds.size(); ++k) {
    const std::string text = fmt::format("{}={:.12g}", sds[k].observable.label(), sds[k].sd);
    if (sds[k].observable.name.empty()) throw UserError(fmt::format("PlanOptions.sds '{}': no observable named", text));
    if (!std::isfinite(sds[k].sd) || !(sds[k].sd > 0))
      throw UserError(
          fmt::format("PlanOptions.sds '{}': '{:g}' must be a number > 0 (the observable's standard "
                      "deviation, in the units demsa stores it: SI, angles in degrees)",
                      text, sds[k].sd));
    // The likelihood's variance is sd² (plus the metamodel's): beyond ~1.3e154 it overflows to infinity, and every
    // truth's posterior would be the prior without a word.
    if (!std::isfinite(sds[k].sd * sds[k].sd))
      throw UserError(
          fmt::format("PlanOptions.sds '{}': {:g} squared overflows a double (the likelihood's variance): "
                      "give an sd below 1e150",
                      text, sds[k].sd));
    for (size_t i = 0; i < k; ++i)
      if (sds[i].observable.study == sds[k].observable.study && sds[i].observable.name == sds[k].observable.name)
        throw UserError(fmt::format(
            "PlanOptions.sds '{}={:.12g}' and PlanOptions.sds '{}': the same observable's sd given twice; give it once",
            sds[i].observable.label(), sds[i].sd, text));
  }
  for (const QualifiedName& q : observe)
    if (q.name.empty()) throw UserError(fmt::format("PlanOptions.observe '{}': no observable named", q.label()));
  for (const MeasuredTarget& m : near)
    if (!(m.sd > 0) || !std::isfinite(m.sd) || !std::isfinite(m.value))
      throw UserError(
          fmt::format("PlanOptions.near '{}': give the value's spread, NAME=V±E with a finite sd > 0", m.text()));
  try {
    if (!model.empty()) sobol::metamodel_kind_from_string(model);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("PlanOptions.model: {}", e.what()));
  }
}

PlanOutcome plan_experiments(const PlanOptions& options) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  const std::vector<JointStudy> studies = load_joint_studies(options.dirs, "plan");
  // The table and STUDY:NAME name studies by their [study] name: two folders of one name could not be told apart.
  for (size_t i = 0; i < studies.size(); ++i)
    for (size_t k = 0; k < i; ++k)
      if (studies[k].config.name == studies[i].config.name)
        throw UserError(fmt::format(
            "plan: the studies {} and {} share the name '{}', so the plan's rows and STUDY:NAME cannot tell them "
            "apart; give them different [study] names",
            studies[k].dir.string(), studies[i].dir.string(), studies[i].config.name));
  // The output folder is checked before any work: a --out that is a file or cannot be written fails now, not after.
  const fs::path out = options.out.empty() ? options.dirs.front() / "plan" : options.out;
  {
    std::error_code ec;
    if (fs::exists(out, ec) && !fs::is_directory(out, ec))
      throw UserError(fmt::format("PlanOptions.out {}: exists and is not a folder", out.string()));
    fs::create_directories(out, ec);
    if (ec)
      throw UserError(fmt::format("PlanOptions.out {}: cannot create the folder: {}", out.string(), ec.message()));
    if (::access(out.c_str(), W_OK) != 0)
      throw UserError(fmt::format("PlanOptions.out {}: cannot write into the folder", out.string()));
  }
  const JointPrior prior = joint_prior(studies);
  const int d = prior.dimension();
  PlanOutcome outcome;
  outcome.parameters = prior.names;
  outcome.truths = options.truths;
  outcome.goal = options.goal;
  outcome.seed = options.seed ? *options.seed : studies.front().config.seed;
  outcome.prior_points = k_plan_prior_points;

  std::vector<SdOverride> sds;
  for (const ObservableSd& given : options.sds) sds.push_back({given});
  const std::vector<QualifiedName>& observe = options.observe;
  for (const QualifiedName& q : observe)
    if (std::none_of(studies.begin(), studies.end(),
                     [&](const JointStudy& s) { return q.matches(s, q.name) && s.measures(q.name); }))
      throw UserError(fmt::format("PlanOptions.observe '{}': no study {}measures it", q.label(),
                                  q.study.empty() ? "" : "named '" + q.study + "' "));

  // The measured observables, their metamodels (in the prior's coordinates) and their sd.
  std::vector<std::unique_ptr<sobol::Metamodel>> models;
  std::vector<sobol::GaussianTarget> targets;
  std::vector<int> target_study;
  for (size_t si = 0; si < studies.size(); ++si) {
    const JointStudy& s = studies[si];
    PlanStudy ps;
    ps.name = s.config.name;
    ps.dir = s.dir;
    ps.experiment = s.config.experiment;
    ps.samples = static_cast<int>(s.samples.size());
    ps.cpu_per_case = s.cpu_per_case;
    outcome.studies.push_back(ps);
    std::vector<std::string> names;
    if (observe.empty()) {
      for (const std::string& name : experiments::of(s.config).lab_observables(s.config))
        if (s.measures(name)) names.push_back(name);
    } else {
      for (const QualifiedName& q : observe)
        if (q.matches(s, q.name) && s.measures(q.name) && std::find(names.begin(), names.end(), q.name) == names.end())
          names.push_back(q.name);
    }
    if (names.empty())
      throw UserError(
          fmt::format("plan: study {} ({}) measures none of the observables {} (it has: {}); name them "
                      "with PlanOptions.observe STUDY:NAME",
                      s.config.name, s.dir.string(),
                      observe.empty() ? "a laboratory measures in this experiment" : "given by PlanOptions.observe",
                      join(s.available)));
    for (const std::string& name : names) {
      FittedObservable fit = fit_observable(s, name, options.model);
      PlanObservable po;
      po.study = s.config.name;
      po.name = name;
      po.model = fit.model_name;
      po.q2 = fit.q2;
      po.median = fit.observed_median;
      po.low = fit.observed_low;
      po.high = fit.observed_high;
      po.samples = fit.samples;
      const std::vector<double> st =
          total_indices(*fit.model, static_cast<int>(s.config.parameters.size()), outcome.seed);
      const std::vector<double> effect =
          main_effect_ranges(*fit.model, static_cast<int>(s.config.parameters.size()), outcome.seed);
      po.total_index.assign(static_cast<size_t>(d), k_nan);
      po.main_effect_range.assign(static_cast<size_t>(d), k_nan);
      for (size_t j = 0; j < s.config.parameters.size(); ++j) {
        const auto column = static_cast<size_t>(prior.column_of(s.config.parameters[j].name));
        po.total_index[column] = st[j];
        po.main_effect_range[column] = effect[j];
      }
      const auto given = std::find_if(sds.begin(), sds.end(),
                                      [&](const SdOverride& o) { return o.given.observable.matches(s, name); });
      if (given != sds.end())
        for (auto other = given + 1; other != sds.end(); ++other)
          if (other->given.observable.matches(s, name))
            throw UserError(
                fmt::format("PlanOptions.sds '{}' and PlanOptions.sds '{}' both give the sd of {}:{}; give "
                            "it once",
                            given->text(), other->text(), s.config.name, name));
      if (given != sds.end()) {
        given->used = true;
        po.sd = given->given.sd;
        po.source = "given";
      } else {
        const double spread = fit.observed_high - fit.observed_low;
        po.measurement_sd = k_plan_measurement_share * (std::abs(po.median) > 0 ? std::abs(po.median) : spread);
        const std::optional<NoiseAnalysis> noise = measured_noise(s.replicates, s.observables, name, 0.95, 0.0);
        if (noise) po.noise_sd = std::sqrt(noise->estimate.variance);
        po.sd = std::sqrt(po.measurement_sd * po.measurement_sd + (noise ? noise->estimate.variance : 0.0));
        po.source = noise ? "replicates + default error" : "default error (no replicates)";
        if (!(po.sd > 0))
          throw UserError(fmt::format("plan: {}:{} is 0 on every sample: give its sd with PlanOptions.sds {}:{}=SD",
                                      s.config.name, name, s.config.name, name));
      }
      outcome.observables.push_back(po);
      models.push_back(std::move(fit.model));
      targets.push_back({name, models.back().get(), input_maps(s, prior), 0.0, po.sd, 1.0});
      target_study.push_back(static_cast<int>(si));
    }
  }
  for (const SdOverride& o : sds)
    if (!o.used)
      throw UserError(
          fmt::format("PlanOptions.sds '{}': no measured observable is named so (measured: {})", o.text(), [&] {
            std::vector<std::string> names;
            for (const PlanObservable& p : outcome.observables) names.push_back(p.study + ":" + p.name);
            return join(names);
          }()));
  for (int j = 0; j < d; ++j)
    for (const PlanObservable& po : outcome.observables)
      if (po.total_index[static_cast<size_t>(j)] >= k_plan_sensitive) {
        outcome.sensitive.push_back(prior.names[static_cast<size_t>(j)]);
        break;
      }

  // The shared prior sample and every observable's prediction on it; the truths and their measurements. The
  // measurements are drawn once per truth, so that every subset is judged on the same simulated lab results.
  const sobol::GaussianPosterior all(targets, d);
  const int n_targets = static_cast<int>(targets.size());
  const int p_points = k_plan_prior_points;
  sobol::Random random(outcome.seed);
  Eigen::MatrixXd u(p_points, d);
  for (int i = 0; i < p_points; ++i)
    for (int j = 0; j < d; ++j) u(i, j) = random.uniform();
  Eigen::MatrixXd mean, sd;
  all.predict(u, mean, sd);
  const Eigen::MatrixXd variance = sd.array().square().matrix();
  const Eigen::MatrixXd half_log_variance = (0.5 * variance.array().log()).matrix();
  std::vector<std::vector<Eigen::Index>> order;
  for (int j = 0; j < d; ++j) order.push_back(sobol::rows_by_column(u, j));
  // The truths: uniform on the box, or, with --near, uniform points accepted with probability exp(-z²/2), z the
  // distance of the predicted observable from the guessed value in units of its ±.
  struct Near {
    int target = 0;
    double value = 0.0, sd = 1.0;
  };
  std::vector<Near> near;
  for (const MeasuredTarget& m : options.near) {
    int found = -1;
    for (int k = 0; k < n_targets; ++k) {
      const PlanObservable& po = outcome.observables[static_cast<size_t>(k)];
      if (po.name == m.name && (m.study.empty() || m.study == po.study)) {
        if (found >= 0)
          throw UserError(fmt::format("PlanOptions.near '{}': several studies measure {}; say which with STUDY:{}",
                                      m.text(), m.name, m.name));
        found = k;
      }
    }
    if (found < 0)
      throw UserError(fmt::format("PlanOptions.near '{}': {} is not a measured observable", m.text(), m.label()));
    near.push_back({found, m.value, m.sd});
    outcome.near.push_back(m.text());
  }
  Eigen::MatrixXd truth(options.truths, d);
  {
    constexpr long k_max_candidates = 1000000;
    long candidates = 0;
    int accepted = 0;
    while (accepted < options.truths) {
      if (candidates >= k_max_candidates)
        throw UserError(
            fmt::format("PlanOptions.near {}: only {} of {} parameter points drawn from the prior predict values this "
                        "near; the studies "
                        "can hardly produce them (widen the ±, or check the value against the studies' ranges)",
                        join(outcome.near), accepted, k_max_candidates));
      Eigen::MatrixXd batch(near.empty() ? options.truths - accepted : 4096, d);
      for (Eigen::Index i = 0; i < batch.rows(); ++i)
        for (int j = 0; j < d; ++j) batch(i, j) = random.uniform();
      candidates += batch.rows();
      Eigen::MatrixXd batch_mean, batch_sd;
      if (!near.empty()) all.predict(batch, batch_mean, batch_sd);
      for (Eigen::Index i = 0; i < batch.rows() && accepted < options.truths; ++i) {
        double log_accept = 0.0;
        for (const Near& n : near) {
          const double z = (batch_mean(i, n.target) - n.value) / n.sd;
          log_accept -= 0.5 * z * z;
        }
        if (near.empty() || random.uniform() < std::exp(log_accept)) truth.row(accepted++) = batch.row(i);
      }
    }
  }
  Eigen::MatrixXd truth_mean, truth_sd;
  all.predict(truth, truth_mean, truth_sd);
  Eigen::MatrixXd measured(options.truths, n_targets);
  for (int t = 0; t < options.truths; ++t)
    for (int k = 0; k < n_targets; ++k) measured(t, k) = truth_mean(t, k) + truth_sd(t, k) * random.normal();

  const int n_studies = static_cast<int>(studies.size());
  // One subset's widths over every truth.
  const auto evaluate = [&](int mask) {
    PlanSubset subset;
    std::vector<int> ks;
    double cost = 0.0;
    for (int si = 0; si < n_studies; ++si)
      if (mask & (1 << si)) {
        subset.studies.push_back(studies[static_cast<size_t>(si)].config.name);
        cost += studies[static_cast<size_t>(si)].cpu_per_case *
                static_cast<double>(studies[static_cast<size_t>(si)].samples.size());
      }
    subset.cpu_seconds = cost;
    for (int k = 0; k < n_targets; ++k)
      if (mask & (1 << target_study[static_cast<size_t>(k)])) ks.push_back(k);
    std::vector<std::vector<double>> widths(static_cast<size_t>(d));
    std::vector<int> outside(static_cast<size_t>(d), 0);
    // Each truth's posterior reads only the shared state above, so the truths run side by side (plan_in_parallel);
    // each chain has its own seed, so the plan does not depend on the threads.
    const std::vector<PlanChain> posteriors = plan_in_parallel(options.truths, options.threads, [&](int t) {
      PlanChain p;
      Eigen::VectorXd log_w = Eigen::VectorXd::Zero(p_points);
      for (const int k : ks)
        log_w.array() -= (mean.col(k).array() - measured(t, k)).square() / (2.0 * variance.col(k).array()) +
                         half_log_variance.col(k).array();
      const Eigen::VectorXd w = (log_w.array() - log_w.maxCoeff()).exp().matrix();
      const double total = w.sum();
      const double ess = total * total / w.squaredNorm();
      p.interval.resize(static_cast<size_t>(d));
      if (ess >= k_plan_min_ess) {
        for (int j = 0; j < d; ++j)
          p.interval[static_cast<size_t>(j)] = sobol::weighted_interval(u, j, order[static_cast<size_t>(j)], w, total);
      } else {
        // Too few prior points carry the posterior (it is narrow in some direction): sample it.
        std::vector<sobol::GaussianTarget> chosen;
        for (const int k : ks) {
          sobol::GaussianTarget g = targets[static_cast<size_t>(k)];
          g.value = measured(t, k);
          chosen.push_back(g);
        }
        const sobol::GaussianPosterior posterior(chosen, d);
        const std::uint64_t seed =
            outcome.seed + 7919u * static_cast<std::uint64_t>(mask) + static_cast<std::uint64_t>(t);
        p = adapt_plan_posterior(posterior, u, log_w, seed);
        if (!p.adapted) p = sample_plan_posterior(posterior, u, log_w, seed);
      }
      return p;
    });
    for (int t = 0; t < options.truths; ++t) {
      const PlanChain& p = posteriors[static_cast<size_t>(t)];
      if (p.adapted) ++subset.adapted;
      if (p.sampled) ++subset.sampled;
      if (!p.converged) {
        ++subset.unconverged;
        subset.unconverged_advice = p.advice;
      }
      for (int j = 0; j < d; ++j) {
        const auto [q05, q95] = p.interval[static_cast<size_t>(j)];
        widths[static_cast<size_t>(j)].push_back(q95 - q05);
        if (truth(t, j) < q05 || truth(t, j) > q95) ++outside[static_cast<size_t>(j)];
      }
    }
    int outside_all = 0;
    for (int j = 0; j < d; ++j) {
      const std::vector<double>& w = widths[static_cast<size_t>(j)];
      subset.width.push_back(std::accumulate(w.begin(), w.end(), 0.0) / static_cast<double>(w.size()));
      subset.width_q10.push_back(sobol::quantile(w, 0.1));
      subset.width_q90.push_back(sobol::quantile(w, 0.9));
      subset.outside.push_back(static_cast<double>(outside[static_cast<size_t>(j)]) / options.truths);
      outside_all += outside[static_cast<size_t>(j)];
    }
    subset.outside_all = static_cast<double>(outside_all) / (static_cast<double>(options.truths) * d);
    subset.meets_goal = true;
    for (const std::string& name : outcome.sensitive) {
      const double w = subset.width[static_cast<size_t>(prior.column(name))];
      subset.worst_sensitive = std::max(subset.worst_sensitive, w);
      if (w > options.goal) subset.meets_goal = false;
    }
    return subset;
  };
  for (int mask = 1; mask < (1 << n_studies); ++mask) outcome.subsets.push_back(evaluate(mask));
  for (const PlanSubset& subset : outcome.subsets)
    if (subset.unconverged > 0)
      outcome.problems.push_back(fmt::format(
          "{}: the posterior of {} of {} truths did not converge ({}); its widths are those of an unfinished chain, "
          "not of the measurement",
          subset_label(subset), subset.unconverged, options.truths, subset.unconverged_advice));

  // The recommendation: the cheapest subset that meets the goal (unknown costs rank by the number of experiments),
  // ties broken by fewer experiments and then by the smaller largest width; else the smallest largest width.
  const auto cost_key = [](const PlanSubset& s) { return std::isnan(s.cpu_seconds) ? 0.0 : s.cpu_seconds; };
  for (size_t i = 0; i < outcome.subsets.size(); ++i) {
    const PlanSubset& s = outcome.subsets[i];
    if (!s.meets_goal) continue;
    if (outcome.recommended < 0) {
      outcome.recommended = static_cast<int>(i);
      continue;
    }
    const PlanSubset& best = outcome.subsets[static_cast<size_t>(outcome.recommended)];
    const auto key = [&](const PlanSubset& x) {
      return std::make_tuple(cost_key(x), x.studies.size(), x.worst_sensitive);
    };
    if (key(s) < key(best)) outcome.recommended = static_cast<int>(i);
  }
  const std::string sensitive = outcome.sensitive.empty() ? "none" : join(outcome.sensitive);
  if (outcome.recommended >= 0) {
    const PlanSubset& s = outcome.subsets[static_cast<size_t>(outcome.recommended)];
    outcome.recommendation = fmt::format(
        "measure {}: the cheapest set that brings every parameter with ST >= {:g} ({}) to <= {:g} of its prior width "
        "(largest {:.2f}){}",
        subset_label(s), k_plan_sensitive, sensitive, options.goal, s.worst_sensitive,
        std::isnan(s.cpu_seconds) ? ""
                                  : fmt::format("; one more study of it costs {:.2g} CPU-hours", s.cpu_seconds / 3600));
  } else {
    size_t best = 0;
    for (size_t i = 1; i < outcome.subsets.size(); ++i)
      if (outcome.subsets[i].worst_sensitive < outcome.subsets[best].worst_sensitive) best = i;
    outcome.recommended = static_cast<int>(best);
    const PlanSubset& s = outcome.subsets[best];
    // The sensitive parameters the best set leaves wider than the goal, and why each stays so (plan_wide_reason: its
    // largest main effect over an observable's sd).
    std::vector<std::string> wide, wide_names;
    for (const std::string& name : outcome.sensitive) {
      const auto j = static_cast<size_t>(prior.column(name));
      if (!(s.width[j] > options.goal)) continue;
      wide.push_back(fmt::format("{} {:.2f}", name, s.width[j]));
      wide_names.push_back(name);
      double effect = 0.0;
      std::string observable;
      for (const PlanObservable& po : outcome.observables)
        if (std::isfinite(po.main_effect_range[j]) && po.main_effect_range[j] / po.sd > effect) {
          effect = po.main_effect_range[j] / po.sd;
          observable = po.study + ":" + po.name;
        }
      outcome.wide_reasons.push_back(plan_wide_reason(name, s.width[j], observable, effect, options.goal));
    }
    outcome.recommendation = fmt::format(
        "no set of these experiments brings every parameter with ST >= {:g} ({}) to <= {:g} of its prior width; the "
        "best is {} (still wide: {}): an experiment that follows {} is missing",
        k_plan_sensitive, sensitive, options.goal, subset_label(s), join(wide), join(wide_names, " and "));
  }
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  outcome.out = out;
  write_file_atomically(outcome.out / "plan.json", plan_to_json(outcome));
  return outcome;
}

std::string plan_wide_reason(const std::string& parameter, double width, const std::string& observable, double effect,
                             double goal) {
  if (observable.empty() || !(effect > 0))
    return fmt::format("{} ({:.2f}): no observable's main effect follows it", parameter, width);
  // The width a straight response of that size would leave alone; a flat posterior's 90 % interval is 0.9 of the box.
  const double straight = std::min(plan_needed_effect(1.0) / effect, k_plan_flat_width);
  const bool shared = width > k_plan_shared_excess * straight || straight <= goal;
  const bool weak = straight > goal && (straight > k_plan_weak_excess * goal || !shared);
  std::string text = fmt::format(
      "{} ({:.2f}): its largest main effect, on {}, spans {:.2g} of that observable's sd over its range; a straight "
      "response of that size alone would leave {:.2f} of its width",
      parameter, width, observable, effect, straight);
  if (weak) {
    const double smaller = plan_needed_effect(goal) / effect;
    text += fmt::format(
        "; {:g} of its width needs an sd at least {:.2g} times smaller (about {:.2g} times the packings, if the sd "
        "were all DEM noise)",
        goal, smaller, smaller * smaller);
  }
  if (shared)
    text +=
        "; the rest is where the effect lies in its range (a step, a curve) or other parameters that make the same "
        "change";
  return text;
}

namespace {

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
json numbers(const std::vector<double>& v) {
  json a = json::array();
  for (const double x : v) a.push_back(number(x));
  return a;
}
double number_of(const json& j) { return j.is_number() ? j.get<double>() : k_nan; }
std::vector<double> numbers_of(const json& j) {
  std::vector<double> v;
  for (const json& x : j) v.push_back(number_of(x));
  return v;
}

}  // namespace

std::string plan_mark(const PlanOutcome& o, std::size_t i) {
  const bool goal = o.subsets[i].meets_goal;
  if (static_cast<int>(i) == o.recommended) return goal ? "recommended" : "best there is";
  return goal ? "meets goal" : "";
}

std::string plan_to_json(const PlanOutcome& o) {
  json j;
  j["parameters"] = o.parameters;
  json studies = json::array();
  for (const PlanStudy& s : o.studies)
    studies.push_back(json{{"name", s.name},
                           {"dir", s.dir.string()},
                           {"experiment", s.experiment},
                           {"samples", s.samples},
                           {"cpu_per_case", number(s.cpu_per_case)}});
  j["studies"] = studies;
  json observables = json::array();
  for (const PlanObservable& p : o.observables)
    observables.push_back(json{{"study", p.study},
                               {"name", p.name},
                               {"model", p.model},
                               {"q2", number(p.q2)},
                               {"sd", p.sd},
                               {"noise_sd", p.noise_sd >= 0 ? json(p.noise_sd) : json(nullptr)},
                               {"measurement_sd", p.measurement_sd},
                               {"source", p.source},
                               {"median", p.median},
                               {"low", p.low},
                               {"high", p.high},
                               {"samples", p.samples},
                               {"total_index", numbers(p.total_index)},
                               {"main_effect_range", numbers(p.main_effect_range)}});
  j["observables"] = observables;
  j["sensitive"] = o.sensitive;
  json subsets = json::array();
  for (const PlanSubset& s : o.subsets)
    subsets.push_back(json{{"studies", s.studies},
                           {"width", numbers(s.width)},
                           {"width_q10", numbers(s.width_q10)},
                           {"width_q90", numbers(s.width_q90)},
                           {"outside", numbers(s.outside)},
                           {"outside_all", s.outside_all},
                           {"cpu_seconds", number(s.cpu_seconds)},
                           {"adapted", s.adapted},
                           {"sampled", s.sampled},
                           {"unconverged", s.unconverged},
                           {"meets_goal", s.meets_goal},
                           {"worst_sensitive", s.worst_sensitive}});
  j["subsets"] = subsets;
  j["recommended"] = o.recommended;
  j["recommendation"] = o.recommendation;
  j["wide_reasons"] = o.wide_reasons;
  j["truths"] = o.truths;
  j["near"] = o.near;
  j["goal"] = o.goal;
  j["seed"] = o.seed;
  j["prior_points"] = o.prior_points;
  j["seconds"] = o.seconds;
  j["defaults"] = json{{"measurement_share", k_plan_measurement_share},
                       {"sensitive_total_index", k_plan_sensitive},
                       {"min_ess", k_plan_min_ess},
                       {"importance_draws", k_plan_importance_draws},
                       {"importance_rounds", k_plan_importance_rounds},
                       {"burn_in", k_plan_burn_in},
                       {"steps", k_plan_steps},
                       {"max_steps", k_plan_max_steps}};
  j["checks"] = json{{"passed", o.problems.empty()}, {"problems", o.problems}};
  return j.dump(2) + "\n";
}

PlanOutcome read_plan(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw UserError(fmt::format("{}: cannot read", file.string()));
  PlanOutcome o;
  try {
    const json j = json::parse(in);
    o.parameters = j.at("parameters").get<std::vector<std::string>>();
    for (const json& e : j.at("studies"))
      o.studies.push_back({e.at("name"), fs::path(e.at("dir").get<std::string>()), e.at("experiment"), e.at("samples"),
                           number_of(e.at("cpu_per_case"))});
    for (const json& e : j.at("observables")) {
      PlanObservable p;
      p.study = e.at("study");
      p.name = e.at("name");
      p.model = e.at("model");
      p.q2 = number_of(e.at("q2"));
      p.sd = e.at("sd");
      p.noise_sd = e.at("noise_sd").is_number() ? e.at("noise_sd").get<double>() : -1.0;
      p.measurement_sd = e.at("measurement_sd");
      p.source = e.at("source");
      p.median = e.at("median");
      p.low = e.at("low");
      p.high = e.at("high");
      p.samples = e.at("samples");
      p.total_index = numbers_of(e.at("total_index"));
      if (e.contains("main_effect_range"))  // written since the wide parameters' reasons
        p.main_effect_range = numbers_of(e.at("main_effect_range"));
      o.observables.push_back(p);
    }
    o.sensitive = j.at("sensitive").get<std::vector<std::string>>();
    for (const json& e : j.at("subsets")) {
      PlanSubset s;
      s.studies = e.at("studies").get<std::vector<std::string>>();
      s.width = numbers_of(e.at("width"));
      s.width_q10 = numbers_of(e.at("width_q10"));
      s.width_q90 = numbers_of(e.at("width_q90"));
      s.outside = numbers_of(e.at("outside"));
      s.outside_all = e.at("outside_all");
      s.cpu_seconds = number_of(e.at("cpu_seconds"));
      s.adapted = e.value("adapted", 0);  // written since adaptive importance sampling
      s.sampled = e.at("sampled");
      s.unconverged = e.value("unconverged", 0);  // written since the convergence check
      s.meets_goal = e.at("meets_goal");
      s.worst_sensitive = e.at("worst_sensitive");
      if (s.width.size() != o.parameters.size())
        throw UserError(
            fmt::format("{}: a subset's widths do not match its "
                        "parameters",
                        file.string()));
      o.subsets.push_back(s);
    }
    o.recommended = j.at("recommended");
    if (o.recommended >= static_cast<int>(o.subsets.size()))
      throw UserError(fmt::format("{}: recommended subset {} does not exist", file.string(), o.recommended));
    o.recommendation = j.at("recommendation");
    o.wide_reasons = j.value("wide_reasons", std::vector<std::string>{});
    o.truths = j.at("truths");
    o.near = j.value("near", std::vector<std::string>{});
    o.goal = j.at("goal");
    o.seed = j.at("seed");
    o.prior_points = j.at("prior_points");
    o.seconds = j.at("seconds");
    if (j.contains("checks")) o.problems = j.at("checks").at("problems").get<std::vector<std::string>>();
  } catch (const json::exception& e) {
    throw UserError(fmt::format("{}: not a plan file: {}", file.string(), e.what()));
  }
  o.out = file.parent_path();
  return o;
}

std::string plan_text(const PlanOutcome& o) {
  std::string text = fmt::format(
      "plan over {} studies: {} truths drawn from the prior{}, each measured with the sd below and calibrated ({:.1f} "
      "s)\n",
      o.studies.size(), o.truths, o.near.empty() ? "" : " where the metamodels predict " + join(o.near), o.seconds);
  text += "measured observables:\n";
  for (const PlanObservable& p : o.observables) {
    const study::Observable l = experiments::describe_observable(p.name);
    const std::string unit = l.unit.empty() ? "" : " " + l.unit;
    std::string st;
    for (size_t j = 0; j < o.parameters.size(); ++j)
      if (std::isfinite(p.total_index[j]) && p.total_index[j] >= 0.05)
        st += fmt::format("{}{} {:.2f}", st.empty() ? "" : ", ", o.parameters[j], p.total_index[j]);
    text += fmt::format(
        "  {}:{:<14} sd {:.3g}{} ({}{}), {} Q² {:.3f}; ST: {}\n", p.study, p.name, p.sd * l.factor, unit, p.source,
        p.source == "given" ? ""
        : p.noise_sd >= 0
            ? fmt::format(": DEM noise {:.3g}{}, measurement {:.3g}{} = {:.0f} % of the median", p.noise_sd * l.factor,
                          unit, p.measurement_sd * l.factor, unit, 100 * k_plan_measurement_share)
            : fmt::format(": measurement {:.3g}{} = {:.0f} % of the median", p.measurement_sd * l.factor, unit,
                          100 * k_plan_measurement_share),
        p.model, p.q2, st.empty() ? "none >= 0.05" : st);
  }
  size_t label = 6;
  for (const PlanSubset& s : o.subsets) label = std::max(label, subset_label(s).size());
  text += fmt::format("expected 90 % posterior width / prior width (mean over the truths):\n  {:<{}}", "subset", label);
  for (const std::string& p : o.parameters) text += fmt::format(" {:>8}", p.substr(0, 8));
  text += fmt::format(" {:>8} {:>10}\n", "outside", "CPU-h");
  for (size_t i = 0; i < o.subsets.size(); ++i) {
    const PlanSubset& s = o.subsets[i];
    text += fmt::format("  {:<{}}", subset_label(s), label);
    for (size_t j = 0; j < s.width.size(); ++j) text += fmt::format(" {:>8.2f}", s.width[j]);
    text += fmt::format(" {:>7.0f}% {:>10}{}\n", 100 * s.outside_all,
                        std::isfinite(s.cpu_seconds) ? fmt::format("{:.3f}", s.cpu_seconds / 3600) : "-",
                        plan_mark(o, i).empty() ? "" : "  <- " + plan_mark(o, i));
  }
  text += fmt::format(
      "  (outside: how often the truth fell outside its 90 % interval, about 10 % for a well-calibrated plan; CPU-h: "
      "one "
      "more study of each experiment, median CPU per done case × design samples)\n");
  text += fmt::format("parameters with ST >= {:g} in some measured observable: {}\n", k_plan_sensitive,
                      o.sensitive.empty() ? "none" : join(o.sensitive));
  text += fmt::format("recommendation: {}\n", o.recommendation);
  if (!o.wide_reasons.empty()) {
    text += "why they stay wide:\n";
    for (const std::string& r : o.wide_reasons) text += fmt::format("  {}\n", r);
  }
  if (!o.problems.empty()) {
    text += "Check failed: the widths above are not all those of the measurements\n";
    for (const std::string& p : o.problems) text += fmt::format("  {}\n", p);
  }
  text += fmt::format("written to {}\n", o.out.string());
  return text;
}

}  // namespace demsa::analysis
