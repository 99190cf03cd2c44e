#pragma once
// Plots of a study, drawn by gnuplot. Every plot is one gnuplot script `<stem>.gp` that holds its own data (as
// inline data blocks) and writes `<stem>.png` and `<stem>.svg` next to it; the script stays in the folder so a
// user can edit it and re-run it with `gnuplot <stem>.gp` from that folder.
//
// The functions take plain structs (numbers and labels), not study files, so that the report and the tests can
// feed them from anywhere. Labels use gnuplot's enhanced text: `μ_{PP}` is μ with subscript PP.
#include "orchestrator/experiments/case_report.hpp"

#include <Eigen/Core>

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace demsa::report {

// The figure data of a case, as the experiments hand it to the report.
using experiments::ImageFigure;
using experiments::LinePlot;
using experiments::PileLine;
using experiments::PileParticle;
using experiments::PileSideView;
using experiments::PlateHistoryPlot;
using experiments::SettlementCurve;

/// How gnuplot is run and how large the images are.
struct PlotOptions {
  std::string gnuplot = "gnuplot";   ///< executable, a name on PATH or a path
  int width = 960;                   ///< PNG and SVG width [px], 200..8000
  int height = 640;                  ///< PNG and SVG height [px], 150..8000
  int font_size = 13;                ///< font size [pt], 6..48
  std::string font = "DejaVu Sans";  ///< font family; gnuplot falls back to its default when it is missing

  /// Throws util::UserError naming the field, its value and the rule.
  void validate() const;
};

/// What the installed gnuplot can draw.
struct GnuplotInfo {
  std::string executable;    ///< as given
  std::string version;       ///< "gnuplot 5.4 patchlevel 4"
  std::string png_terminal;  ///< "pngcairo" when available, otherwise "png" (libgd)
  bool svg = false;          ///< the svg terminal exists
};

/// Asks gnuplot for its version and terminals. Throws util::UserError when gnuplot cannot be run or has no PNG
/// terminal (install gnuplot-nox).
GnuplotInfo query_gnuplot(const std::string& executable);

/// The files of one plot, all in one folder.
struct PlotFiles {
  std::filesystem::path script;  ///< <stem>.gp: data and commands; re-runnable
  std::filesystem::path png;     ///< <stem>.png
  std::filesystem::path svg;     ///< <stem>.svg
};

/// A plotter bound to one gnuplot (queried once).
class Plotter {
 public:
  explicit Plotter(PlotOptions options = {});
  const GnuplotInfo& gnuplot() const { return m_info; }
  const PlotOptions& options() const { return m_options; }

  /// Writes `<stem>.gp` from `body` (data blocks and commands that draw one picture, terminal-free) and runs it
  /// in the stem's folder to make `<stem>.png` and `<stem>.svg`. `size_scale` multiplies the default height (tall
  /// multi-panel figures), `width_scale` the default width (wide ones). Throws std::runtime_error with gnuplot's own
  /// message when gnuplot fails.
  PlotFiles render(const std::filesystem::path& stem, const std::string& title, const std::string& data_blocks,
                   const std::string& body, double size_scale = 1.0, double width_scale = 1.0) const;

 private:
  PlotOptions m_options;
  GnuplotInfo m_info;
};

/// One index estimate with its confidence interval (NaN bounds: no interval).
struct IntervalValue {
  double value = std::numeric_limits<double>::quiet_NaN();
  double low = std::numeric_limits<double>::quiet_NaN();
  double high = std::numeric_limits<double>::quiet_NaN();
};

/// Sobol' indices of one metamodel (paper Tables 4–7 as bars).
struct SobolBarChart {
  std::string title;                        ///< e.g. "angle of repose, RSM cubic"
  std::vector<std::string> parameters;      ///< one label per parameter (enhanced text)
  std::vector<IntervalValue> first_order;   ///< S1 per parameter
  std::vector<IntervalValue> total_effect;  ///< ST per parameter; empty when not computed
};
/// Grouped bars S1 and ST per parameter with the confidence interval as whiskers.
PlotFiles plot_sobol_bars(const Plotter& plotter, const SobolBarChart& chart, const std::filesystem::path& stem);

/// Leave-one-out predictions of one metamodel against the simulated values.
struct PredictedVsObserved {
  std::string title;
  std::string response_label;     ///< with unit, e.g. "angle of repose [°]"
  std::vector<double> observed;   ///< simulated responses
  std::vector<double> predicted;  ///< leave-one-out predictions, same order
  double r2 = std::numeric_limits<double>::quiet_NaN();
  double q2 = std::numeric_limits<double>::quiet_NaN();
};
PlotFiles plot_predicted_vs_observed(const Plotter& plotter, const PredictedVsObserved& data,
                                     const std::filesystem::path& stem);

/// The response of every sample against each varied parameter (one panel per parameter).
struct ResponseScatter {
  std::string title;
  std::string response_label;                 ///< with unit
  std::vector<std::string> parameter_labels;  ///< with unit, one per column of `physical`
  std::vector<bool> log_scale;                ///< per parameter: log x axis; empty = all linear
  Eigen::MatrixXd physical;                   ///< samples x parameters, physical values
  std::vector<double> response;               ///< one per row of `physical`
};
PlotFiles plot_response_scatter(const Plotter& plotter, const ResponseScatter& data, const std::filesystem::path& stem);

/// `demsa refine`'s history: the largest S1/ST interval half-width of each observable against the done samples,
/// with the target W as a horizontal line (log y axis).
struct RefineHistoryPlot {
  std::string title;
  double target = 0.0;                          ///< W
  std::vector<std::string> observables;         ///< one line each
  std::vector<double> samples;                  ///< x of each step
  std::vector<std::vector<double>> half_width;  ///< [observable][step]; NaN: no interval at that step
};
PlotFiles plot_refine_history(const Plotter& plotter, const RefineHistoryPlot& data, const std::filesystem::path& stem);

PlotFiles plot_pile_side(const Plotter& plotter, const PileSideView& view, const std::filesystem::path& stem);

PlotFiles plot_settlement_curve(const Plotter& plotter, const SettlementCurve& curve,
                                const std::filesystem::path& stem);

PlotFiles plot_lines(const Plotter& plotter, const LinePlot& plot, const std::filesystem::path& stem);
/// An experiment's own picture copied to `<stem>.png` (no script, no SVG: those paths stay empty). Throws
/// util::UserError naming the PNG when it cannot be copied.
PlotFiles plot_image(const experiments::ImageFigure& image, const std::filesystem::path& stem);
PlotFiles plot_plate_history(const Plotter& plotter, const PlateHistoryPlot& history,
                             const std::filesystem::path& stem);

/// `demsa plan`: the expected 90 % posterior width over the prior width of each parameter (groups along x) for each
/// set of experiments (one bar per set in every group), with the goal as a dashed line.
struct PlanWidthChart {
  std::string title;
  std::vector<std::string> parameters;     ///< one group each
  std::vector<std::string> subsets;        ///< one bar per group each ("pile + incline")
  std::vector<std::vector<double>> width;  ///< [subset][parameter]
  double goal = 0.5;
  int recommended = -1;                           ///< subset drawn with a thick border (-1: none)
  std::string recommended_label = "recommended";  ///< appended to its key entry in parentheses
};
PlotFiles plot_plan_widths(const Plotter& plotter, const PlanWidthChart& chart, const std::filesystem::path& stem);

/// A calibration: where the optimum lies in each parameter's range, and target against predicted (and
/// measured, after a verification run) per observable.
struct CalibrationPlot {
  std::string title;
  std::vector<std::string> parameter_labels;   ///< one per parameter
  std::vector<double> optimum_unit;            ///< optimum on the unit cube, in [0,1]
  std::vector<double> optimum_physical;        ///< the same in physical units (printed as labels)
  std::vector<std::string> observable_labels;  ///< with unit, one per target
  std::vector<double> target;
  std::vector<double> predicted;
  std::vector<double> measured;  ///< from a verification run; empty or NaN where not measured
};
PlotFiles plot_calibration(const Plotter& plotter, const CalibrationPlot& data, const std::filesystem::path& stem);

/// Gnuplot string literal of `text` (double-quoted, with `"` and `\` escaped).
std::string gnuplot_quote(const std::string& text);

}  // namespace demsa::report
