// Plots (orchestrator/plot.hpp): every plot writes a re-runnable gnuplot script, a PNG that decodes and is not
// blank, and an SVG; bad options and a failing gnuplot are reported, not ignored.
#include "orchestrator/report/plot.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

using namespace demsa::util;
using namespace demsa::report;

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

struct PngStats {
  int width = 0;
  int height = 0;
  long colours = 0;          ///< distinct pixel values
  double nonbackground = 0;  ///< fraction of pixels that differ from the most common value
};

/// Decodes a PNG with tests/data/report/png_stats.py (standard-library zlib) and fails the test when it does not.
PngStats png_stats(const fs::path& png) {
  const CommandResult r = run_command({"python3", data_path("report/png_stats.py").string(), png.string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  PngStats s;
  std::istringstream in(r.out);
  in >> s.width >> s.height >> s.colours >> s.nonbackground;
  return s;
}

void expect_drawn(const PlotFiles& files, int width, int height) {
  ASSERT_TRUE(fs::exists(files.script)) << files.script;
  ASSERT_TRUE(fs::exists(files.png)) << files.png;
  ASSERT_TRUE(fs::exists(files.svg)) << files.svg;
  const PngStats s = png_stats(files.png);
  EXPECT_EQ(s.width, width);
  EXPECT_EQ(s.height, height);
  EXPECT_GT(s.colours, 8) << files.png;           // text, axes and data in several colours
  EXPECT_GT(s.nonbackground, 0.01) << files.png;  // not a blank canvas
  const std::string svg = read_file(files.svg);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
}

TEST(Plot, OptionsValidateNamesFieldAndValue) {
  PlotOptions o;
  o.width = 50;
  try {
    o.validate();
    FAIL() << "width 50 accepted";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("width: 50"), std::string::npos) << e.what();
  }
  o = PlotOptions{};
  o.font_size = 0;
  EXPECT_THROW(o.validate(), UserError);
  o = PlotOptions{};
  o.height = 9000;
  EXPECT_THROW(o.validate(), UserError);
}

TEST(Plot, QueryFindsPngAndSvgTerminals) {
  const GnuplotInfo info = query_gnuplot("gnuplot");
  EXPECT_TRUE(info.png_terminal == "pngcairo" || info.png_terminal == "png") << info.png_terminal;
  EXPECT_TRUE(info.svg);
  EXPECT_EQ(info.version.rfind("gnuplot 5", 0), 0u) << info.version;
}

TEST(Plot, MissingGnuplotIsAUserError) {
  PlotOptions o;
  o.gnuplot = "/nonexistent/gnuplot";
  try {
    Plotter p(o);
    FAIL() << "a missing gnuplot was accepted";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/gnuplot"), std::string::npos) << e.what();
  }
}

TEST(Plot, GnuplotErrorIsReportedWithItsMessage) {
  TempDir dir;
  const Plotter plotter;
  try {
    plotter.render(dir / "broken", "broken", "", "  plot $nosuchblock using 1:2\n");
    FAIL() << "a failing script was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("broken.gp"), std::string::npos) << e.what();
  }
}

TEST(Plot, QuoteEscapesQuotesAndBackslashes) {
  EXPECT_EQ(gnuplot_quote("a\"b\\c"), "\"a\\\"b\\\\c\"");
  EXPECT_EQ(gnuplot_quote("two\nlines"), "\"two\\nlines\"");
}

TEST(Plot, SobolBarsWithWhiskers) {
  TempDir dir;
  const Plotter plotter;
  SobolBarChart chart;
  chart.title = "angle of repose, RSM cubic";
  chart.parameters = {"E", "ν", "μ_{PP}", "μ_{PW}", "e_r", "μ_{R,PP}", "μ_{R,PW}"};
  const double s1[] = {0.030, 9.4e-4, 0.0165, 0.0132, 7.8e-6, 0.5302, 0.0066};  // paper Table 4, RSM cub.
  for (double v : s1) {
    chart.first_order.push_back({v, v - 0.01, v + 0.02});
    chart.total_effect.push_back({v * 1.3, v * 1.2, v * 1.5});
  }
  chart.first_order[1] = {9.4e-4, std::nan(""), std::nan("")};  // no interval: drawn without whisker
  const PlotFiles files = plot_sobol_bars(plotter, chart, dir / "sobol_rsm3");
  expect_drawn(files, 960, 640);
  const std::string script = read_file(files.script);
  EXPECT_NE(script.find("0.5302"), std::string::npos);
  EXPECT_NE(script.find("errorbars"), std::string::npos);
}

TEST(Plot, ScriptIsRerunnableFromItsFolder) {
  TempDir dir;
  const Plotter plotter;
  PredictedVsObserved p;
  p.title = "angle of repose, RBF cubic";
  p.response_label = "angle [°]";
  for (int i = 0; i < 30; ++i) {
    p.observed.push_back(25 + 0.4 * i);
    p.predicted.push_back(25 + 0.4 * i + std::sin(i) * 0.8);
  }
  p.r2 = 0.981;
  p.q2 = 0.912;
  const PlotFiles files = plot_predicted_vs_observed(plotter, p, dir / "loo_rbf");
  expect_drawn(files, 960, 640);
  EXPECT_NE(read_file(files.script).find("Q^2 = 0.9120"), std::string::npos);
  fs::remove(files.png);
  fs::remove(files.svg);
  const CommandResult r = run_command({"gnuplot", "loo_rbf.gp"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  expect_drawn(files, 960, 640);
}

TEST(Plot, ResponseAgainstEachParameter) {
  TempDir dir;
  const Plotter plotter;
  ResponseScatter s;
  s.title = "angle of repose against each parameter";
  s.response_label = "angle [°]";
  s.parameter_labels = {"E [Pa]", "ν [-]", "μ_{PP} [-]", "μ_{R,PP} [-]", "e_r [-]"};
  s.log_scale = {true, false, false, false, false};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  s.physical.resize(40, 5);
  for (int r = 0; r < 40; ++r) {
    s.physical(r, 0) = 1e8 * std::pow(10, u(rng));
    s.physical(r, 1) = 0.2 + 0.2 * u(rng);
    s.physical(r, 2) = 0.7 + 1.2 * u(rng);
    s.physical(r, 3) = 0.05 + 0.3 * u(rng);
    s.physical(r, 4) = 0.2 + 0.4 * u(rng);
    s.response.push_back(20 + 40 * s.physical(r, 3) + 2 * s.physical(r, 2));
  }
  const PlotFiles files = plot_response_scatter(plotter, s, dir / "response");
  expect_drawn(files, 960, static_cast<int>(std::lround(640 * 1.1)));
  EXPECT_NE(read_file(files.script).find("set logscale x"), std::string::npos);
}

/// A cone of slope 30° on the pedestal, its boundary particles per direction and the exact lines.
PileSideView synthetic_pile() {
  PileSideView v;
  v.title = "sample 000017";
  v.directions = 36;
  v.angle_deg = 30;
  const double radius = 0.05;
  const double slope = std::tan(30 * M_PI / 180);
  v.height = 0.005 + radius * slope;
  const double r = 0.002;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 3000; ++k) {
    const double rho = radius * std::sqrt(u(rng));
    const double phi = 2 * M_PI * u(rng);
    const double top = 0.005 + (radius - rho) * slope;
    v.particles.push_back({rho * std::cos(phi), rho * std::sin(phi), 0.005 + r + (top - 0.005 - r) * u(rng), r, -1});
  }
  for (int i = 0; i < v.directions; ++i) {
    const double phi = 2 * M_PI * i / v.directions;
    PileLine line{i, 360.0 * i / v.directions, 30, 0, 0, 0, 0};
    for (int level = 0; level < 6; ++level) {
      const double z = 0.2 * v.height + (0.55 * v.height) * level / 5;
      const double rho = radius - (z - 0.005) / slope;
      v.particles.push_back({rho * std::cos(phi), -rho * std::sin(phi), z, r, i});
    }
    line.z0 = 0.2 * v.height;
    line.rho0 = radius - (line.z0 - 0.005) / slope;
    line.z1 = 0.75 * v.height;
    line.rho1 = radius - (line.z1 - 0.005) / slope;
    v.lines.push_back(line);
  }
  return v;
}

TEST(Plot, PileSideViewWithBoundaryParticlesAndLines) {
  TempDir dir;
  const Plotter plotter;
  const PlotFiles files = plot_pile_side(plotter, synthetic_pile(), dir / "pile");
  expect_drawn(files, 960, 960);
  const std::string script = read_file(files.script);
  EXPECT_NE(script.find("angle of repose 30.00°, pile height"), std::string::npos);
  EXPECT_NE(script.find("$section_lines"), std::string::npos);
}

TEST(Plot, SettlementCurveAgainstMeasured) {
  TempDir dir;
  const Plotter plotter;
  SettlementCurve c;
  c.title = "oedometer, sample 120";
  c.loads = {100, 400, 1100, 2700};
  c.area = 0.01;
  c.simulated = {0, 0.4e-3, 1.1e-3, 2.0e-3};
  c.measured = {0, 0.5e-3, 1.2e-3, 1.9e-3};
  c.measured_low = {0, 0.45e-3, 1.05e-3, 1.7e-3};
  c.measured_high = {0, 0.55e-3, 1.35e-3, 2.1e-3};
  const PlotFiles files = plot_settlement_curve(plotter, c, dir / "settlement");
  expect_drawn(files, 960, 640);
  EXPECT_NE(read_file(files.script).find("270 "), std::string::npos);  // 2700 N on 0.01 m² = 270 kPa
}

TEST(Plot, PlateHistoryWithLoadSteps) {
  TempDir dir;
  const Plotter plotter;
  PlateHistoryPlot h;
  h.title = "plate iteration, sample 120";
  const double loads[] = {100, 400, 1100, 2700};
  for (int i = 0; i < 400; ++i) {
    const double load = loads[i / 100];
    h.step.push_back(1000.0 * i);
    h.load.push_back(load);
    h.force.push_back(load * (1 - std::exp(-(i % 100) / 12.0)) + 5 * std::sin(i));
    h.plate_z.push_back(0.06 - 1e-5 * i);
  }
  const PlotFiles files = plot_plate_history(plotter, h, dir / "plate");
  expect_drawn(files, 960, 640);
  EXPECT_NE(read_file(files.script).find("y2label"), std::string::npos);
}

TEST(Plot, CalibrationOptimumAndTargets) {
  TempDir dir;
  const Plotter plotter;
  CalibrationPlot c;
  c.title = "calibration on RSM cubic";
  c.parameter_labels = {"E [Pa]", "μ_{PP} [-]", "μ_{R,PP} [-]"};
  c.optimum_unit = {0.2, 0.55, 0.9};
  c.optimum_physical = {2.8e8, 1.36, 0.32};
  c.observable_labels = {"angle of repose [°]"};
  c.target = {33.5};
  c.predicted = {33.49};
  c.measured = {32.8};
  const PlotFiles files = plot_calibration(plotter, c, dir / "calibration");
  expect_drawn(files, 960, 640);
  EXPECT_NE(read_file(files.script).find("33.49"), std::string::npos);
}

}  // namespace
}  // namespace demsa::test
