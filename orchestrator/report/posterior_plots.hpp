#pragma once
// The figures of a Bayesian calibration (analysis/calibration_posterior.hpp), drawn by gnuplot (report/plot.hpp):
// marginal histograms, a corner plot (histograms on the diagonal, pairwise draws below it), and the posterior
// predictive against every measured target (one panel per observable family: the angle; the settlement curve with
// its error bars).
#include "orchestrator/analysis/calibration_posterior.hpp"
#include "orchestrator/analysis/experiment_plan.hpp"
#include "orchestrator/report/plot.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace demsa::report {

struct PosteriorFigures {
  PlotFiles marginals;
  PlotFiles corner;
  PlotFiles predictive;
};

/// Writes posterior_marginals, posterior_corner and posterior_predictive (.gp, .png, .svg) into `folder`, from the
/// draws in `samples` (posterior_samples.csv).
PosteriorFigures plot_posterior(const Plotter& plotter, const analysis::PosteriorOutcome& outcome,
                                const std::filesystem::path& samples, const std::filesystem::path& folder);

/// plot_posterior with gnuplot into the posterior's own folder (outcome.out, from its posterior_samples.csv), for a
/// front end that says what it did: "" when the figures were written, else "no plots: " and why (no gnuplot, ...).
std::string plot_posterior_note(const analysis::PosteriorOutcome& outcome);

/// `demsa plan`'s figure, plan_widths (.gp, .png, .svg) in `folder`: grouped bars of the expected widths.
PlotFiles plot_plan(const Plotter& plotter, const analysis::PlanOutcome& plan, const std::filesystem::path& folder);

}  // namespace demsa::report
