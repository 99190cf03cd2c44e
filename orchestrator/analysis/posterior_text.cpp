// The printed tables of a posterior (calibration_posterior.hpp: posterior_text).
#include "orchestrator/analysis/calibration_posterior.hpp"

#include "orchestrator/util/text.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace demsa::analysis {

using namespace demsa::util;

std::string unconverged_problem(const std::string& advice) {
  return fmt::format(
      "{}: the sampler's chain has not converged (converged: steps >= 50 τ and every split R̂ < 1.05); its quantiles "
      "and widths are those of an unfinished chain, not of the measurements: {}",
      k_unconverged, advice);
}

std::string posterior_check_headline(const PosteriorOutcome& o) {
  const bool contradicted =
      std::any_of(o.targets.begin(), o.targets.end(), [](const PosteriorTarget& t) { return t.contradicted; });
  const std::string what = contradicted && !o.converged
                               ? "the measurements contradict what the studies can produce, and the chain has not "
                                 "converged"
                           : contradicted ? "the measurements contradict what the studies can produce"
                           : !o.converged ? "the chain has not converged"
                                          : "a check of the posterior failed";
  return what + "; this posterior is not an answer";
}

std::string posterior_text(const PosteriorOutcome& o) {
  std::string text = fmt::format("posterior of {} ({} walkers × {} steps after {} burn-in, seed {}, {:.1f} s)\n",
                                 join(o.studies), o.walkers, o.steps, o.burn_in, o.seed, o.seconds);
  if (o.auto_steps.size() > 1) {
    std::string runs;
    for (size_t i = 0; i < o.auto_steps.size(); ++i) runs += fmt::format("{}{}", i ? " → " : "", o.auto_steps[i]);
    text += fmt::format("  automatic steps: {} (each run 60 τ of the one before, until steps >= 50 τ)\n", runs);
  }
  text += fmt::format("  {:<10} {:>11} {:>11} {:>11} {:>11} {:>11} {:>7} {:>10} {:>7} {:>6} {:>8}\n", "parameter",
                      "mean", "MAP", "5 %", "50 %", "95 %", "width", "identified", "tau", "R-hat", "ESS");
  for (const PosteriorParameter& p : o.parameters)
    text += fmt::format(
        "  {:<10} {:>11.5g} {:>11.5g} {:>11.5g} {:>11.5g} {:>11.5g} {:>7.3f} {:>10} {:>7.1f} {:>6.3f} {:>8.0f}\n",
        p.name, p.mean, p.map, p.q05, p.q50, p.q95, p.width_ratio, p.identified, p.tau, p.rhat, p.ess);
  for (const PosteriorParameter& p : o.parameters)
    for (const std::string& t : p.tied) text += fmt::format("  {} = {} (tied, same_as)\n", t, p.name);
  text += "  (width: 90 % posterior width over the prior's width on the design scale; ~0.9 = not determined)\n";
  if (o.parameters.size() > 1) {
    // The pairs that matter: |r| >= k_print_correlation; the full matrix is in posterior.json.
    std::string pairs;
    int weak = 0;
    for (size_t i = 0; i < o.parameters.size(); ++i)
      for (size_t k = i + 1; k < o.parameters.size(); ++k) {
        if (std::abs(o.correlation[i][k]) >= k_print_correlation)
          pairs += fmt::format("  {} ~ {}: {:+.3f}\n", o.parameters[i].name, o.parameters[k].name, o.correlation[i][k]);
        else
          ++weak;
      }
    text += fmt::format(
        "correlations with |r| >= {:g}{}:\n{}", k_print_correlation,
        weak > 0 ? fmt::format(" ({} other pair{} below, all in posterior.json)", weak, weak == 1 ? "" : "s") : "",
        pairs.empty() ? "  none\n" : pairs);
  }
  text += fmt::format("  {:<14} {:<12} {:<10} {:>12} {:>10} {:>12} {:>12} {:>12} {:>12} {:>9}\n", "target", "study",
                      "model", "measured", "sd", "at MAP", "pred. 5 %", "pred. 95 %", "model sd", "tail p");
  for (const PosteriorTarget& t : o.targets)
    text +=
        fmt::format("  {:<14} {:<12} {:<10} {:>12.6g} {:>10.4g} {:>12.6g} {:>12.6g} {:>12.6g} {:>12.4g} {:>9.2g}{}\n",
                    t.name, t.study, t.model, t.value, t.sd, t.predicted_map, t.predictive_q05, t.predictive_q95,
                    t.model_sd, t.tail_probability, t.contradicted ? "  CONTRADICTED" : "");
  text += fmt::format("diagnostics: acceptance {:.2f}; {}\n", o.acceptance,
                      o.converged ? "converged (steps >= 50 τ, every R̂ < 1.05)" : k_unconverged + (": " + o.advice));
  for (const VerifyPoint& v : o.verification) {
    text += fmt::format("verification at {}:\n", v.label);
    for (const VerifyPoint::Measured& m : v.measured)
      text += fmt::format("  {:<14} {:<12} measured {:>12} predicted {:.6g} (90 % [{:.6g}, {:.6g}]){}\n", m.target,
                          m.study, m.value ? fmt::format("{:.6g}", *m.value) : "-", m.predicted, m.low, m.high,
                          m.value && (*m.value < m.low || *m.value > m.high) ? "  outside" : "");
    for (const std::string& e : v.errors) text += fmt::format("  failed: {}\n", e);
  }
  for (const std::string& w : o.warnings) text += fmt::format("warning: {}\n", w);
  if (!o.problems.empty()) {
    text += fmt::format("CHECK FAILED: {}:\n", posterior_check_headline(o));
    for (const std::string& p : o.problems) text += fmt::format("  {}\n", p);
  }
  text += fmt::format("written to {}\n", o.out.string());
  return text;
}

}  // namespace demsa::analysis
