#include "orchestrator/analysis/calibration_posterior.hpp"

#include "orchestrator/analysis/calibration.hpp"
#include "orchestrator/analysis/fit.hpp"
#include "orchestrator/analysis/joint_studies.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/parameters.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"
#include "sobol/ensemble_sampler.hpp"
#include "sobol/posterior.hpp"
#include "sobol/random.hpp"
#include "sobol/scaling.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <set>

namespace demsa::analysis {

using namespace demsa::util;
using namespace demsa::study;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string identified_label(double ratio) { return ratio < 0.5 ? "yes" : ratio < 0.8 ? "partly" : "no"; }

}  // namespace

void PosteriorOptions::validate() const {
  if (dirs.empty()) throw UserError("calibrate: a study folder is required");
  if (targets.empty()) throw UserError("PosteriorOptions.targets: no measured value given");
  std::set<std::string> seen;
  for (const MeasuredTarget& t : targets) {
    if (t.name.empty()) throw UserError(fmt::format("PosteriorOptions.targets '{}': no observable named", t.text()));
    if (!std::isfinite(t.value))
      throw UserError(fmt::format("PosteriorOptions.targets '{}': the value must be a finite number", t.text()));
    // sd 0 (none given): the likelihood's variance is the metamodel's alone.
    if (!(t.sd >= 0) || !std::isfinite(t.sd))
      throw UserError(
          fmt::format("PosteriorOptions.targets '{}': uncertainty {:g} must be a finite number >= 0", t.label(), t.sd));
    if (!seen.insert(t.label()).second)
      throw UserError(fmt::format("PosteriorOptions.targets: {} is given twice", t.label()));
  }
  for (const auto& [label, weight] : weights) {
    if (!(weight >= 0) || !std::isfinite(weight))
      throw UserError(fmt::format("PosteriorOptions.weights '{}={}': one value >= 0 expected", label, weight));
    if (!seen.count(label)) throw UserError(fmt::format("PosteriorOptions.weights: {} is not a target", label));
  }
  if (walkers != 0 && (walkers < 4 || walkers % 2 != 0))
    throw UserError(fmt::format("PosteriorOptions.walkers {}: must be even and >= 2 × parameters + 2", walkers));
  if (steps != 0 && steps < 10)
    throw UserError(fmt::format("PosteriorOptions.steps {}: must be >= 10 (or 0: automatic)", steps));
  if (burn_in < 0) throw UserError(fmt::format("PosteriorOptions.burn_in {}: must be >= 0", burn_in));
  if (verify < -1 || verify > 1000)
    throw UserError(fmt::format("PosteriorOptions.verify {}: must be in 0..1000", verify));
  try {
    if (!model.empty()) sobol::metamodel_kind_from_string(model);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("PosteriorOptions.model: {}", e.what()));
  }
}

namespace {

/// The studies a target is matched to: the one named by its STUDY: prefix, else the only study that measures its
/// name. A bare name that several studies measure (two piles both have `angle`) is refused: the measured value of
/// one lab test belongs to one experiment.
std::vector<const JointStudy*> studies_measuring(const std::vector<JointStudy>& studies, const MeasuredTarget& target) {
  const std::string text = target.label();
  std::vector<const JointStudy*> named, measuring;
  for (const JointStudy& s : studies) {
    if (!target.study.empty() && s.config.name != target.study) continue;
    named.push_back(&s);
    if (s.measures(target.name)) measuring.push_back(&s);
  }
  if (!target.study.empty() && named.empty()) {
    std::vector<std::string> names;
    for (const JointStudy& s : studies) names.push_back(s.config.name);
    throw UserError(fmt::format("PosteriorOptions.targets {}: no study is named '{}' (the studies: {})", text,
                                target.study, join(names)));
  }
  if (!target.study.empty() && named.size() > 1) {
    std::vector<std::string> dirs;
    for (const JointStudy* s : named) dirs.push_back(s->dir.string());
    throw UserError(
        fmt::format("PosteriorOptions.targets {}: the studies {} share the name '{}', so STUDY:NAME cannot tell them "
                    "apart; give them different [study] names",
                    text, join(dirs), target.study));
  }
  if (measuring.empty()) {
    std::string all;
    for (const JointStudy* s : named)
      all += fmt::format("\n  {} ({}): {}", s->config.name, s->dir.string(), join(s->available));
    throw UserError(fmt::format("PosteriorOptions.targets {}: no study {}has this observable (observables:{})", text,
                                target.study.empty() ? "" : "named '" + target.study + "' ", all));
  }
  if (measuring.size() > 1) {
    std::vector<std::string> names;
    for (const JointStudy* s : measuring) names.push_back(s->config.name);
    throw UserError(
        fmt::format("PosteriorOptions.targets {}: ambiguous: the studies {} all measure '{}'; say which with "
                    "PosteriorOptions.targets STUDY:{}=... (one per study)",
                    text, join(names), target.name, target.name));
  }
  return measuring;
}

}  // namespace

PosteriorOutcome calibrate_posterior(const PosteriorOptions& options) {
  options.validate();
  const std::vector<JointStudy> studies = load_joint_studies(options.dirs, "calibrate");
  PosteriorOutcome outcome;
  const JointPrior joint = joint_prior(studies);
  const std::vector<sobol::Bounds>& prior = joint.bounds;
  for (const JointStudy& s : studies) outcome.studies.push_back(s.config.name);
  for (const std::string& name : joint.names) {
    PosteriorParameter q;
    q.name = name;
    for (const study::ParameterTie& t : joint.ties)
      if (t.partner == name) q.tied.push_back(t.name);
    outcome.parameters.push_back(q);
  }
  const int d = static_cast<int>(prior.size());

  // Targets: the measured values, each matched to the study that has the observable.
  std::vector<std::unique_ptr<sobol::Metamodel>> models;
  std::vector<sobol::GaussianTarget> gaussian;
  std::set<std::pair<std::string, std::string>> matched;  // (study folder, observable): one target each
  for (const MeasuredTarget& t : options.targets) {
    for (const JointStudy* study : studies_measuring(studies, t)) {
      const JointStudy& s = *study;
      if (!matched.insert({s.dir.string(), t.name}).second)
        throw UserError(fmt::format("PosteriorOptions.targets {}: {} of {} is given a value twice", t.label(), t.name,
                                    s.dir.string()));
      FittedObservable fit = fit_observable(s, t.name, options.model);
      PosteriorTarget pt;
      pt.name = t.name;
      pt.study = s.config.name;
      pt.model = fit.model_name;
      pt.q2 = fit.q2;
      pt.value = t.value;
      pt.sd = t.sd;
      const auto weight = options.weights.find(t.label());
      pt.weight = weight == options.weights.end() ? 1.0 : weight->second;
      pt.observed_low = fit.observed_low;
      pt.observed_high = fit.observed_high;
      pt.samples = fit.samples;
      outcome.targets.push_back(pt);
      models.push_back(std::move(fit.model));
      gaussian.push_back({pt.name, models.back().get(), input_maps(s, joint), pt.value, pt.sd, pt.weight});
    }
  }
  std::optional<sobol::GaussianPosterior> posterior;
  try {
    posterior.emplace(gaussian, d);
  } catch (const sobol::InputError& e) {
    throw UserError(fmt::format("PosteriorOptions.targets: {}", e.what()));
  }

  sobol::EnsembleOptions sampler;
  sampler.walkers = options.walkers;
  sampler.steps = options.steps == 0 ? k_auto_first_steps : options.steps;
  sampler.burn_in = options.burn_in;
  const std::uint64_t seed = options.seed ? *options.seed : studies.front().config.seed;
  sampler.seed = seed;
  try {
    sampler.validate(d);
  } catch (const sobol::InputError& e) {
    // The sampler names its own fields ("burn-in 2147483548: ..."): the same fields of PosteriorOptions.
    std::string message = e.what();
    for (const auto& [sampler_field, field] :
         {std::pair<std::string, std::string>{"walkers ", "walkers "}, {"steps ", "steps "}, {"burn-in ", "burn_in "}})
      if (message.rfind(sampler_field, 0) == 0)
        message = "PosteriorOptions." + field + message.substr(sampler_field.size());
    throw UserError(message);
  }
  const std::vector<double> lower(static_cast<size_t>(d), 0.0), upper(static_cast<size_t>(d), 1.0);
  const auto start = std::chrono::steady_clock::now();
  const sobol::BatchLogDensity density = sobol::posterior_function(*posterior);
  {
    // The walkers start at the points of highest density among k_start_points uniform draws from the prior box
    // (sobol::highest_density_start). Started uniformly, a chain could not shrink onto a narrow posterior: at sd
    // 0.0002° on two incline angles it ended with its walkers apart (split R̂ 1.5e4) and widths of 0.44 and 0.13 for a
    // posterior of width 3e-5.
    sobol::Random draw(seed + 3);
    Eigen::MatrixXd points(k_start_points, d);
    for (Eigen::Index i = 0; i < points.rows(); ++i)
      for (int j = 0; j < d; ++j) points(i, j) = draw.uniform();
    sampler.start = sobol::highest_density_start(points, density(points), sampler.walkers_for(d));
  }
  sobol::EnsembleResult r = sobol::sample_ensemble(density, lower, upper, sampler);
  sobol::ChainDiagnostics diag = sobol::diagnose(r);
  if (options.steps == 0) {
    // Automatic length, emcee's practice (Foreman-Mackey et al. 2013, §3; the emcee documentation's
    // "Autocorrelation analysis" tutorial): a chain of at least 50 integrated autocorrelation times, the burn-in a
    // few τ. τ is estimated from the run before, so the next run asks for 60 τ; while the walkers still disagree
    // (split R̂ >= 1.05) each run is at least twice as long as the last. Each run continues the last one's
    // ensemble; the sampler is seeded, so the result is the same for the same inputs. The runs stop at the memory
    // cap, where the advice says so.
    outcome.auto_steps.push_back(r.steps);
    const int walkers = sampler.walkers_for(d);
    const auto cap = static_cast<int>(k_max_auto_draws / (static_cast<double>(walkers) * (d + 1)));
    for (int run = 1; run < k_auto_max_runs && !diag.converged && r.steps < cap; ++run) {
      sampler.steps = std::min(cap, std::max(2 * r.steps, static_cast<int>(std::ceil(60.0 * diag.max_tau))));
      sampler.burn_in = std::max(options.burn_in, static_cast<int>(std::ceil(5.0 * diag.max_tau)));
      sampler.start = r.last();
      // A stream of its own for each run (splitmix64's increment), the reported seed staying the first.
      sampler.seed = seed + static_cast<std::uint64_t>(run) * 0x9E3779B97F4A7C15ULL;
      r = sobol::sample_ensemble(density, lower, upper, sampler);
      diag = sobol::diagnose(r);
      outcome.auto_steps.push_back(r.steps);
    }
    if (!diag.converged && r.steps >= cap)
      diag.advice += fmt::format(
          " (automatic steps stopped at {}, the most {} walkers × {} parameters keep in "
          "memory: give the steps per walker to go further)",
          cap, walkers, d);
  }
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::vector<sobol::MarginalSummary> marginals = sobol::summarise_marginals(r, lower, upper);
  const Eigen::MatrixXd corr = sobol::posterior_correlation(r.draws);
  outcome.walkers = r.walkers;
  outcome.steps = r.steps;
  outcome.burn_in = sampler.burn_in;
  outcome.draws = static_cast<int>(r.draws.rows());
  outcome.evaluations = r.evaluations;
  outcome.seed = seed;
  outcome.acceptance = diag.acceptance;
  outcome.converged = diag.converged;
  outcome.advice = diag.advice;
  // An unfinished chain fails the check, as an unconverged truth fails the plan's: its quantiles and widths are its
  // starting spread or a part of the posterior, not what the measurements say. Everything is still written.
  if (!diag.converged) outcome.problems.push_back(unconverged_problem(diag.advice));
  for (int j = 0; j < d; ++j) {
    PosteriorParameter& p = outcome.parameters[static_cast<size_t>(j)];
    const sobol::Bounds& b = prior[static_cast<size_t>(j)];
    const sobol::MarginalSummary& m = marginals[static_cast<size_t>(j)];
    p.low = b.low;
    p.high = b.high;
    p.log = b.scale == sobol::Scale::log_uniform;
    p.mean = sobol::to_physical(m.mean, b);  // the mean on the design scale, mapped
    p.map = sobol::to_physical(m.map, b);
    p.q05 = sobol::to_physical(m.q05, b);
    p.q50 = sobol::to_physical(m.q50, b);
    p.q95 = sobol::to_physical(m.q95, b);
    p.width_ratio = m.width_ratio;
    p.identified = identified_label(m.width_ratio);
    // Draws piled on an end of the prior range: the measurements ask for values beyond the study's range, and a
    // narrow marginal there says nothing about the parameter inside it.
    const Eigen::Index n_draws = r.draws.rows();
    const double at_low = static_cast<double>((r.draws.col(j).array() < k_bound_band).count()) /
                          static_cast<double>(std::max<Eigen::Index>(1, n_draws));
    const double at_high = static_cast<double>((r.draws.col(j).array() > 1.0 - k_bound_band).count()) /
                           static_cast<double>(std::max<Eigen::Index>(1, n_draws));
    p.bound_share = std::max(at_low, at_high);
    if (p.bound_share > k_bound_share) {
      p.at_bound = at_low >= at_high ? "low" : "high";
      p.identified = "at bound";
      outcome.warnings.push_back(
          fmt::format("{}: {:.0f} % of the posterior draws lie in the {} {:.0f} % of its range [{:g}, {:g}]: the "
                      "measurements ask for values {} the study's range",
                      p.name, 100.0 * p.bound_share, p.at_bound == "low" ? "lowest" : "highest", 100.0 * k_bound_band,
                      b.low, b.high, p.at_bound == "low" ? "below" : "above"));
    }
    p.tau = diag.tau[static_cast<size_t>(j)];
    p.rhat = diag.rhat[static_cast<size_t>(j)];
    p.ess = diag.ess[static_cast<size_t>(j)];
    outcome.correlation.emplace_back();
    for (int k = 0; k < d; ++k) outcome.correlation.back().push_back(corr(j, k));
  }

  // Posterior predictive: metamodel mean plus Gaussian noise of the total variance, at up to 4000 draws spread
  // evenly over the kept draws.
  const Eigen::Index stride = std::max<Eigen::Index>(1, r.draws.rows() / 4000);
  Eigen::MatrixXd subset(r.draws.rows() / stride, d);
  for (Eigen::Index i = 0; i < subset.rows(); ++i) subset.row(i) = r.draws.row(i * stride);
  Eigen::MatrixXd mean, sd;
  posterior->predict(subset, mean, sd);
  sobol::Random noise(seed + 1);
  Eigen::MatrixXd map_mean, map_sd;
  posterior->predict(r.best.transpose(), map_mean, map_sd);
  for (size_t k = 0; k < outcome.targets.size(); ++k) {
    const Eigen::Index c = static_cast<Eigen::Index>(k);
    std::vector<double> y;
    for (Eigen::Index i = 0; i < subset.rows(); ++i) y.push_back(mean(i, c) + sd(i, c) * noise.normal());
    PosteriorTarget& t = outcome.targets[k];
    t.predictive_q05 = sobol::quantile(y, 0.05);
    t.predictive_q50 = sobol::quantile(y, 0.50);
    t.predictive_q95 = sobol::quantile(y, 0.95);
    t.predicted_map = map_mean(0, c);
    t.model_sd = std::sqrt(std::max(0.0, map_sd(0, c) * map_sd(0, c) - t.sd * t.sd));
    // The measured value against the posterior predictive (a Gaussian mixture over the draws): its two-sided tail
    // probability, each tail summed on its own so that a far value keeps its small probability instead of 1 - 1.
    double below = 0.0, above = 0.0;
    for (Eigen::Index i = 0; i < subset.rows(); ++i) {
      const double s_i = sd(i, c), m_i = mean(i, c);
      if (s_i > 0) {
        const double z = (t.value - m_i) / s_i;
        below += 0.5 * std::erfc(-z / std::sqrt(2.0));
        above += 0.5 * std::erfc(z / std::sqrt(2.0));
      } else {
        below += t.value >= m_i ? 1.0 : 0.0;
        above += t.value <= m_i ? 1.0 : 0.0;
      }
    }
    const double n_sub = static_cast<double>(std::max<Eigen::Index>(1, subset.rows()));
    t.tail_probability = std::min(1.0, 2.0 * std::min(below, above) / n_sub);
    // A target of weight 0 does not enter the likelihood: it is not held against the posterior.
    t.contradicted = t.weight > 0 && t.tail_probability < k_predictive_tail;
    if (t.contradicted) {
      const study::Observable l = experiments::describe_observable(t.name);
      outcome.problems.push_back(fmt::format(
          "{} = {:.5g}{} ± {:.3g}: the posterior predicts 5–95 % [{:.5g}, {:.5g}]{}; the measured value's tail "
          "probability is {:.2g} (< {:g}); {}",
          t.name, t.value * l.factor, l.unit.empty() ? "" : " " + l.unit, t.sd * l.factor, t.predictive_q05 * l.factor,
          t.predictive_q95 * l.factor, l.unit.empty() ? "" : " " + l.unit, t.tail_probability, k_predictive_tail,
          t.value < t.observed_low || t.value > t.observed_high
              ? observed_span_text(t.study, t.name, t.observed_low, t.observed_high, t.samples, t.value) +
                    ": the measurement contradicts the study (no parameters in its ranges produce it)"
              : "the targets contradict one another or the metamodels"));
    }
  }

  outcome.out = options.out.empty() ? options.dirs.front() / k_posterior_folder : options.out;
  fs::create_directories(outcome.out);
  // The samples in physical units, thinned to at most 20000 rows (every k-th kept draw).
  {
    const Eigen::Index thin = std::max<Eigen::Index>(1, r.draws.rows() / 20000);
    Eigen::MatrixXd table(r.draws.rows() / thin, d + 1);
    for (Eigen::Index i = 0; i < table.rows(); ++i) {
      for (int j = 0; j < d; ++j) table(i, j) = sobol::to_physical(r.draws(i * thin, j), prior[static_cast<size_t>(j)]);
      table(i, d) = r.log_density(i * thin);
    }
    std::vector<std::string> header;
    for (const PosteriorParameter& p : outcome.parameters) header.push_back(p.name);
    header.push_back("log_posterior");
    write_csv(outcome.out / "posterior_samples.csv", header, table);
  }

  if (options.verify >= 0) {
    if (!options.run_point) throw util::InternalError("calibrate: verification asked for, but no way to run a case");
    std::vector<std::pair<std::string, Eigen::VectorXd>> points{{"map", r.best}};
    sobol::Random pick(seed + 2);
    for (int k = 0; k < options.verify; ++k)
      points.emplace_back(
          fmt::format("draw-{}", k + 1),
          r.draws.row(static_cast<Eigen::Index>(pick.below(static_cast<std::uint64_t>(r.draws.rows())))).transpose());
    for (const auto& [label, u] : points) {
      VerifyPoint vp;
      vp.label = label;
      for (int j = 0; j < d; ++j) vp.physical.push_back(sobol::to_physical(u(j), prior[static_cast<size_t>(j)]));
      Eigen::MatrixXd pm, ps;
      posterior->predict(u.transpose(), pm, ps);
      for (const JointStudy& s : studies) {
        std::vector<double> unit;
        for (const ParameterRange& p : s.config.parameters) {
          const size_t column = static_cast<size_t>(joint.column_of(p.name));  // a tied one: its partner's
          unit.push_back(std::clamp(sobol::to_unit(vp.physical[column], p.bounds), 0.0, 1.0));
        }
        // Resumable: a point measured by an earlier run (same coordinates) is read back, not run again.
        const fs::path folder = outcome.out / "verify" / label / s.config.name;
        const fs::path record = outcome.out / "verify" / label / (s.config.name + ".json");
        std::map<std::string, double> values;
        std::string error;
        bool reused = false;
        if (fs::exists(record)) {
          std::ifstream in(record);
          const json j = json::parse(in, nullptr, false);
          if (!j.is_discarded() && j.contains("unit") && j.at("unit").get<std::vector<double>>() == unit) {
            values = j.at("observables").get<std::map<std::string, double>>();
            error = j.at("error").get<std::string>();
            reused = true;
          }
        }
        if (!reused) {
          const PointRun run = options.run_point(s.config, folder, unit);
          values = run.observables;
          error = run.error;
          write_file_atomically(record, json{{"unit", unit}, {"observables", values}, {"error", error}}.dump(2));
        }
        if (!error.empty()) vp.errors.push_back(fmt::format("{}: {}", s.config.name, error));
        for (size_t k = 0; k < outcome.targets.size(); ++k) {
          const PosteriorTarget& t = outcome.targets[k];
          if (t.study != s.config.name) continue;
          VerifyPoint::Measured m;
          m.target = t.name;
          m.study = t.study;
          const Eigen::Index c = static_cast<Eigen::Index>(k);
          m.predicted = pm(0, c);
          m.low = pm(0, c) - 1.645 * ps(0, c);
          m.high = pm(0, c) + 1.645 * ps(0, c);
          if (const auto it = values.find(t.name); it != values.end() && error.empty()) m.value = it->second;
          vp.measured.push_back(m);
        }
      }
      outcome.verification.push_back(vp);
    }
  }
  write_file_atomically(outcome.out / k_posterior_json, posterior_to_json(outcome));
  return outcome;
}

}  // namespace demsa::analysis
