#include "orchestrator/report/plot.hpp"

#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/process.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace demsa::report {

using namespace demsa::util;

namespace fs = std::filesystem;

namespace {

constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();

/// Runs gnuplot (util/process.hpp: argv, no shell, stdin from /dev/null) in `cwd`, stdout and stderr together.
CaptureResult run_gnuplot(const std::vector<std::string>& argv, const fs::path& cwd) {
  CaptureOptions options;
  options.merge_stderr = true;
  options.cwd = cwd;
  return run_capture(argv, options);
}

/// A number for a gnuplot data block; NaN (and infinities) become the missing-value marker.
std::string num(double v) {
  if (!std::isfinite(v)) return "NaN";
  return fmt::format("{:.10g}", v);
}

std::string finite_or(double v, double fallback) { return std::isfinite(v) ? num(v) : num(fallback); }

/// min and max over the finite values of several lists; {0, 1} when there is none.
std::pair<double, double> finite_range(std::initializer_list<const std::vector<double>*> lists) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const std::vector<double>* list : lists) {
    for (double v : *list) {
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (!std::isfinite(lo)) return {0.0, 1.0};
  return {lo, hi};
}

/// [lo, hi] widened by `fraction` of its width on both sides (and made non-empty).
std::pair<double, double> padded(std::pair<double, double> range, double fraction) {
  double width = range.second - range.first;
  if (width <= 0) width = std::max(std::abs(range.first), 1.0) * 0.1;
  return {range.first - fraction * width, range.second + fraction * width};
}

/// 1, 2 or 5 times a power of ten, the smallest not below `raw` (axis tic spacing).
double nice_step(double raw) {
  if (!(raw > 0) || !std::isfinite(raw)) return 1.0;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * power >= raw * (1 - 1e-12)) return m * power;
  return 10 * power;
}

constexpr const char* k_purple = "#7b2f9e";
constexpr const char* k_red = "#d62728";
constexpr const char* k_blue = "#1f77b4";
constexpr const char* k_grey = "#9a9a9a";

}  // namespace

std::string gnuplot_quote(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  out += '"';
  return out;
}

void PlotOptions::validate() const {
  if (gnuplot.empty()) throw UserError("plot option gnuplot: empty; give an executable name or path");
  if (width < 200 || width > 8000)
    throw UserError(fmt::format("plot option width: {} px is outside [200, 8000]", width));
  if (height < 150 || height > 8000)
    throw UserError(fmt::format("plot option height: {} px is outside [150, 8000]", height));
  if (font_size < 6 || font_size > 48)
    throw UserError(fmt::format("plot option font_size: {} pt is outside [6, 48]", font_size));
}

GnuplotInfo query_gnuplot(const std::string& executable) {
  const CaptureResult r =
      run_gnuplot({executable, "-e", "print GPVAL_VERSION, GPVAL_PATCHLEVEL; print GPVAL_TERMINALS"}, fs::path());
  if (r.exit_code == 127)
    throw UserError(fmt::format("gnuplot: cannot run '{}' (not on PATH?); install gnuplot-nox", executable));
  if (r.exit_code != 0)
    throw UserError(fmt::format("gnuplot: '{}' failed with status {}: {}", executable, r.exit_code, r.out));
  std::istringstream lines(r.out);
  std::string version_line;
  std::string terminal_line;
  std::getline(lines, version_line);
  std::getline(lines, terminal_line);
  GnuplotInfo info;
  info.executable = executable;
  {
    std::istringstream v(version_line);
    std::string major;
    std::string patch;
    v >> major >> patch;
    info.version = fmt::format("gnuplot {} patchlevel {}", major, patch);
  }
  std::istringstream terms(terminal_line);
  std::string term;
  bool png = false;
  bool pngcairo = false;
  while (terms >> term) {
    png = png || term == "png";
    pngcairo = pngcairo || term == "pngcairo";
    info.svg = info.svg || term == "svg";
  }
  if (pngcairo) {
    info.png_terminal = "pngcairo";
  } else if (png) {
    info.png_terminal = "png";
  } else {
    throw UserError(
        fmt::format("gnuplot: '{}' has neither the pngcairo nor the png terminal; install gnuplot-nox", executable));
  }
  if (!info.svg) throw UserError(fmt::format("gnuplot: '{}' has no svg terminal; install gnuplot-nox", executable));
  return info;
}

Plotter::Plotter(PlotOptions options) : m_options(std::move(options)) {
  m_options.validate();
  m_info = query_gnuplot(m_options.gnuplot);
}

PlotFiles Plotter::render(const fs::path& stem, const std::string& title, const std::string& data_blocks,
                          const std::string& body, double size_scale, double width_scale) const {
  assert(size_scale > 0 && width_scale > 0);
  const fs::path folder = stem.parent_path().empty() ? fs::path(".") : stem.parent_path();
  const std::string name = stem.filename().string();
  fs::create_directories(folder);
  PlotFiles files{folder / (name + ".gp"), folder / (name + ".png"), folder / (name + ".svg")};

  const int height = static_cast<int>(std::lround(m_options.height * size_scale));
  const int width = static_cast<int>(std::lround(m_options.width * width_scale));
  const std::string font = gnuplot_quote(fmt::format("{},{}", m_options.font, m_options.font_size));
  const std::string png_terminal = fmt::format("set terminal {} size {},{} font {} enhanced background rgb 'white'",
                                               m_info.png_terminal, width, height, font);
  std::string script;
  script += fmt::format("# {}\n", title);
  script +=
      fmt::format("# Re-run in this folder with `gnuplot {}.gp` to remake {}.png and {}.svg.\n", name, name, name);
  script += data_blocks;
  script += "do for [format in \"png svg\"] {\n  reset\n";
  script += fmt::format("  if (format eq \"png\") {{\n    {}\n  }} else {{\n", png_terminal);
  script += fmt::format("    set terminal svg size {},{} font {} enhanced background rgb 'white'\n  }}\n", width,
                        height, font);
  script += fmt::format("  set output {}.format\n", gnuplot_quote(name + "."));
  script += "  set datafile missing \"NaN\"\n";
  script += body;
  script += "  unset multiplot\n  set output\n}\n";
  {
    std::ofstream out(files.script);
    if (!out) throw std::runtime_error(fmt::format("{}: cannot write", files.script.string()));
    out << script;
  }
  std::error_code ignored;
  fs::remove(files.png, ignored);
  fs::remove(files.svg, ignored);
  const CaptureResult r = run_gnuplot({m_options.gnuplot, name + ".gp"}, folder);
  const bool made =
      fs::exists(files.png) && fs::file_size(files.png) > 0 && fs::exists(files.svg) && fs::file_size(files.svg) > 0;
  if (r.exit_code != 0 || !made)
    throw std::runtime_error(
        fmt::format("gnuplot failed on {} (status {}): {}", files.script.string(), r.exit_code, r.out));
  return files;
}

// ------------------------------------------------------------------------------------------- Sobol' bars

PlotFiles plot_sobol_bars(const Plotter& plotter, const SobolBarChart& chart, const fs::path& stem) {
  const size_t d = chart.parameters.size();
  assert(chart.first_order.size() == d);
  assert(chart.total_effect.empty() || chart.total_effect.size() == d);
  const bool total = !chart.total_effect.empty();
  std::vector<double> all;
  std::string data = "$sobol << EOD\n";
  for (size_t i = 0; i < d; ++i) {
    const IntervalValue& s1 = chart.first_order[i];
    const IntervalValue st = total ? chart.total_effect[i] : IntervalValue{};
    // A missing interval is drawn as a whisker of zero length.
    data += fmt::format("{} {} {} {} {} {} {}\n", gnuplot_quote(chart.parameters[i]), finite_or(s1.value, 0.0),
                        finite_or(s1.low, s1.value), finite_or(s1.high, s1.value), finite_or(st.value, 0.0),
                        finite_or(st.low, st.value), finite_or(st.high, st.value));
    for (double v : {s1.value, s1.low, s1.high, st.value, st.low, st.high})
      if (std::isfinite(v)) all.push_back(v);
  }
  data += "EOD\n";
  const std::pair<double, double> range = finite_range({&all});
  const double ymin = std::min(0.0, range.first - 0.02);
  const double ymax = std::max(0.1, range.second) * 1.12;

  std::string body;
  body += fmt::format("  set title {} noenhanced\n", gnuplot_quote(chart.title));
  body += "  set style data histogram\n  set style histogram errorbars gap 1.5 lw 1.5\n";
  body += "  set style fill solid 0.85 border rgb 'black'\n  set boxwidth 0.9\n";
  body += fmt::format("  set yrange [{}:{}]\n", num(ymin), num(ymax));
  body += "  set ylabel \"Sobol' index [-]\"\n  set xlabel 'parameter'\n";
  body += "  set grid ytics lc rgb '#dddddd'\n  set key top right\n  set xtics nomirror\n";
  body += "  set errorbars 1.2\n";
  body += fmt::format("  plot $sobol using 2:3:4:xtic(1) title 'first order S_1' lc rgb '{}'", k_blue);
  if (total) body += fmt::format(", \\\n       '' using 5:6:7 title 'total effect S_T' lc rgb '{}'", k_red);
  body += "\n";
  return plotter.render(stem, chart.title, data, body);
}

// ------------------------------------------------------------------------------------- plan widths

PlotFiles plot_plan_widths(const Plotter& plotter, const PlanWidthChart& chart, const fs::path& stem) {
  // Twenty colours (matplotlib's tab20), repeated beyond.
  static const char* const colours[] = {"#1f77b4", "#aec7e8", "#ff7f0e", "#ffbb78", "#2ca02c", "#98df8a", "#d62728",
                                        "#ff9896", "#9467bd", "#c5b0d5", "#8c564b", "#c49c94", "#e377c2", "#f7b6d2",
                                        "#7f7f7f", "#c7c7c7", "#bcbd22", "#dbdb8d", "#17becf", "#9edae5"};
  std::string data = "$widths << EOD\n";
  for (size_t j = 0; j < chart.parameters.size(); ++j) {
    data += gnuplot_quote(chart.parameters[j]);
    for (const std::vector<double>& w : chart.width) data += fmt::format(" {}", num(std::isfinite(w[j]) ? w[j] : 0.0));
    data += "\n";
  }
  data += "EOD\n";
  std::string body;
  body += fmt::format("  set title {} noenhanced\n", gnuplot_quote(chart.title));
  body += "  set style data histogram\n  set style histogram clustered gap 1\n";
  body += "  set style fill solid 0.85 border rgb 'black'\n  set boxwidth 0.9\n";
  body += "  set yrange [0:1.05]\n  set ylabel '90 % posterior width / prior width'\n  set xlabel 'parameter'\n";
  body +=
      "  set grid ytics lc rgb '#dddddd'\n  set key outside right top noenhanced\n  set xtics nomirror noenhanced\n";
  body += "  plot ";
  for (size_t i = 0; i < chart.subsets.size(); ++i) {
    const bool mark = static_cast<int>(i) == chart.recommended;
    body +=
        fmt::format("{}$widths using {}{} title {} lc rgb '{}'{}", i ? ", \\\n       " : "", i + 2, i ? "" : ":xtic(1)",
                    gnuplot_quote(chart.subsets[i] + (mark ? " (" + chart.recommended_label + ")" : "")),
                    colours[i % std::size(colours)], mark ? " lw 3" : "");
  }
  body += fmt::format(", \\\n       {} with lines dt 2 lw 2 lc rgb '{}' title {}\n", num(chart.goal), k_grey,
                      gnuplot_quote(fmt::format("goal {:g}", chart.goal)));
  return plotter.render(stem, chart.title, data, body, 1.0, chart.subsets.size() > 7 ? 1.6 : 1.2);
}

// ------------------------------------------------------------------------------------- predicted vs observed

PlotFiles plot_predicted_vs_observed(const Plotter& plotter, const PredictedVsObserved& p, const fs::path& stem) {
  assert(p.observed.size() == p.predicted.size());
  std::string data = "$points << EOD\n";
  for (size_t i = 0; i < p.observed.size(); ++i)
    data += fmt::format("{} {}\n", num(p.observed[i]), num(p.predicted[i]));
  data += "EOD\n";
  const std::pair<double, double> range = padded(finite_range({&p.observed, &p.predicted}), 0.05);
  std::string body;
  body += fmt::format("  set title {} noenhanced\n", gnuplot_quote(p.title));
  body += fmt::format("  set xlabel {}\n", gnuplot_quote("simulated " + p.response_label));
  body += fmt::format("  set ylabel {}\n", gnuplot_quote("leave-one-out prediction " + p.response_label));
  body += fmt::format("  set xrange [{0}:{1}]\n  set yrange [{0}:{1}]\n  set size ratio -1\n", num(range.first),
                      num(range.second));
  body += "  set grid lc rgb '#dddddd'\n  set key top left box opaque\n";
  body += fmt::format(
      "  set label 1 {} at graph 0.97, graph 0.06 right front\n",
      gnuplot_quote(fmt::format("R^2 = {}   Q^2 = {}", std::isfinite(p.r2) ? fmt::format("{:.4f}", p.r2) : "n/a",
                                std::isfinite(p.q2) ? fmt::format("{:.4f}", p.q2) : "n/a")));
  body += fmt::format(
      "  plot x title 'prediction = simulation' lc rgb '{}' dt 2 lw 1.5, \\\n"
      "       $points using 1:2 with points pt 7 ps 0.9 lc rgb '{}' title 'sample (left out of the fit)'\n",
      k_grey, k_blue);
  return plotter.render(stem, p.title, data, body);
}

// ----------------------------------------------------------------------------------------- refine history

PlotFiles plot_refine_history(const Plotter& plotter, const RefineHistoryPlot& h, const fs::path& stem) {
  static constexpr std::array<const char*, 6> colours{k_blue, k_red, k_purple, "#2ca02c", "#ff7f0e", "#8c564b"};
  std::string data;
  for (std::size_t o = 0; o < h.observables.size(); ++o) {
    data += fmt::format("$w{} << EOD\n", o);
    for (std::size_t i = 0; i < h.samples.size(); ++i) {
      const double w = h.half_width[o][i];
      if (std::isfinite(w) && w > 0) data += fmt::format("{} {}\n", num(h.samples[i]), num(w));
    }
    data += "EOD\n";
  }
  std::string body;
  body += fmt::format("  set title {} noenhanced\n", gnuplot_quote(h.title));
  body += "  set xlabel 'done samples'\n  set ylabel 'largest S1/ST interval half-width'\n";
  body += "  set logscale y\n  set format y '%g'\n  set grid lc rgb '#dddddd'\n  set key top right box opaque\n";
  // The target and every width inside the y range, with room around them on the log scale.
  double low = h.target, high = h.target;
  for (const std::vector<double>& line : h.half_width)
    for (const double w : line)
      if (std::isfinite(w) && w > 0) {
        low = std::min(low, w);
        high = std::max(high, w);
      }
  if (low > 0) body += fmt::format("  set yrange [{}:{}]\n", num(low / 1.6), num(high * 1.6));
  std::vector<double> xs = h.samples;
  const std::pair<double, double> xr = padded(finite_range({&xs}), 0.05);
  body += fmt::format("  set xrange [{}:{}]\n", num(xr.first), num(xr.second == xr.first ? xr.first + 1 : xr.second));
  body += fmt::format("  plot {} with lines dt 2 lw 2 lc rgb '{}' title {}", num(h.target), k_grey,
                      gnuplot_quote(fmt::format("target W = {}", num(h.target))));
  for (std::size_t o = 0; o < h.observables.size(); ++o)
    body += fmt::format(", \\\n       $w{} using 1:2 with linespoints pt 7 lw 2 lc rgb '{}' title {} noenhanced", o,
                        colours[o % colours.size()], gnuplot_quote(h.observables[o]));
  body += "\n";
  return plotter.render(stem, h.title, data, body);
}

// ----------------------------------------------------------------------------------------- response scatter

PlotFiles plot_response_scatter(const Plotter& plotter, const ResponseScatter& s, const fs::path& stem) {
  const Eigen::Index d = s.physical.cols();
  assert(static_cast<size_t>(d) == s.parameter_labels.size());
  assert(static_cast<size_t>(s.physical.rows()) == s.response.size());
  assert(s.log_scale.empty() || s.log_scale.size() == static_cast<size_t>(d));
  std::string data = "$samples << EOD\n";
  for (Eigen::Index r = 0; r < s.physical.rows(); ++r) {
    for (Eigen::Index c = 0; c < d; ++c) data += num(s.physical(r, c)) + " ";
    data += num(s.response[static_cast<size_t>(r)]) + "\n";
  }
  data += "EOD\n";
  const int columns = d <= 1 ? 1 : (d <= 4 ? 2 : 3);
  const int rows = static_cast<int>((d + columns - 1) / columns);
  const std::pair<double, double> yrange = padded(finite_range({&s.response}), 0.06);
  std::string body;
  body += fmt::format("  set multiplot layout {},{} title {} noenhanced\n", rows, columns, gnuplot_quote(s.title));
  body += fmt::format("  set ylabel {}\n  set yrange [{}:{}]\n", gnuplot_quote(s.response_label), num(yrange.first),
                      num(yrange.second));
  body += "  set grid lc rgb '#dddddd'\n  unset key\n";
  for (Eigen::Index c = 0; c < d; ++c) {
    const bool log = !s.log_scale.empty() && s.log_scale[static_cast<size_t>(c)];
    body += log ? "  set logscale x\n  set autoscale x\n" : "  unset logscale x\n";
    body += fmt::format("  set xlabel {}\n", gnuplot_quote(s.parameter_labels[static_cast<size_t>(c)]));
    if (log) {
      body += "  set xtics autofreq\n  set format x '10^{%T}'\n";
    } else {
      // About four tics per panel: gnuplot's automatic ones overlap in a grid of small panels.
      std::vector<double> column(s.physical.col(c).data(), s.physical.col(c).data() + s.physical.rows());
      const std::pair<double, double> xr = finite_range({&column});
      const double step = nice_step((xr.second - xr.first) / 3.5);
      body += fmt::format("  set xtics {}\n  set format x '%g'\n  set xrange [{}:{}]\n", num(step),
                          num(std::floor(xr.first / step) * step), num(std::ceil(xr.second / step) * step));
    }
    body += fmt::format("  plot $samples using {}:{} with points pt 7 ps 0.7 lc rgb '{}'\n", c + 1, d + 1, k_blue);
  }
  return plotter.render(stem, s.title, data, body, std::max(1.0, rows / 2.0 * 1.1));
}

// ------------------------------------------------------------------------------------------- pile side view

PlotFiles plot_pile_side(const Plotter& plotter, const PileSideView& v, const fs::path& stem) {
  assert(v.directions > 0);
  double r_max = 0;
  for (const PileParticle& p : v.particles) r_max = std::max(r_max, p.radius);
  const double slab = v.slab > 0 ? v.slab : 2 * r_max;
  constexpr double mm = 1e3;
  // Cross section: particles with |y| <= slab, drawn as circles of their radius in the x-z plane.
  std::string data = "$section << EOD\n";
  for (const PileParticle& p : v.particles) {
    if (std::abs(p.y) > slab) continue;
    data += fmt::format("{} {} {} {}\n", num(p.x * mm), num(p.z * mm), num(p.radius * mm), p.direction);
  }
  data += "EOD\n";
  // Unrolled: every boundary particle at (radial distance along its direction, z).
  data += "$boundary << EOD\n";
  for (const PileParticle& p : v.particles) {
    if (p.direction < 0) continue;
    const double phi = 2 * M_PI * p.direction / v.directions;
    const double rho = p.x * std::cos(phi) - p.y * std::sin(phi);  // e = (cos φ, −sin φ), paper eq. 9
    data += fmt::format("{} {} {} {}\n", num(rho * mm), num(p.z * mm), num(p.radius * mm), p.direction);
  }
  data += "EOD\n";
  // Fitted lines: all of them unrolled; in the cross section the two whose half-planes are closest to x-z.
  data += "$lines << EOD\n";
  for (const PileLine& l : v.lines)
    data += fmt::format("{} {} {} {} {}\n", num(l.rho0 * mm), num(l.z0 * mm), num((l.rho1 - l.rho0) * mm),
                        num((l.z1 - l.z0) * mm), l.direction);
  data += "EOD\n";
  data += "$section_lines << EOD\n";
  const PileLine* best_plus = nullptr;
  const PileLine* best_minus = nullptr;
  for (const PileLine& l : v.lines) {
    const double c = std::cos(l.phi_deg * M_PI / 180);
    if (c > 0 && (best_plus == nullptr || c > std::cos(best_plus->phi_deg * M_PI / 180))) best_plus = &l;
    if (c < 0 && (best_minus == nullptr || c < std::cos(best_minus->phi_deg * M_PI / 180))) best_minus = &l;
  }
  for (const PileLine* l : {best_plus, best_minus}) {
    if (l == nullptr) continue;
    const double c = std::cos(l->phi_deg * M_PI / 180);
    data += fmt::format("{} {} {} {} {}\n", num(l->rho0 * c * mm), num(l->z0 * mm), num((l->rho1 - l->rho0) * c * mm),
                        num((l->z1 - l->z0) * mm), l->direction);
  }
  data += "EOD\n";

  const double half_width = v.pedestal_radius * mm * 1.1;
  const double top = std::max((v.pedestal_height + v.height * 1.1) * mm, v.pedestal_height * mm * 4);
  std::string body;
  body += fmt::format("  set multiplot layout 2,1 title {} noenhanced\n",
                      gnuplot_quote(fmt::format("{}: angle of repose {:.2f}°, pile height {:.1f} mm, {} directions",
                                                v.title, v.angle_deg, v.height * mm, v.directions)));
  body += "  set palette defined (0 '#e41a1c', 0.5 '#4daf4a', 1 '#0000cc')\n";
  body += fmt::format("  set cbrange [0:{}]\n  set cblabel 'direction i_φ'\n", std::max(1, v.directions - 1));
  body += "  set style fill solid 0.9 noborder\n  set grid lc rgb '#e5e5e5'\n  set key below horizontal\n";
  body += fmt::format("  set xrange [{}:{}]\n  set yrange [{}:{}]\n  set size ratio -1\n", num(-half_width),
                      num(half_width), num(-0.5), num(top));
  body += fmt::format("  set object 1 rect from {},0 to {},{} fc rgb '#c8b27a' fs solid 0.6 border rgb 'black' back\n",
                      num(-v.pedestal_radius * mm), num(v.pedestal_radius * mm), num(v.pedestal_height * mm));
  body += fmt::format("  set title {} noenhanced\n",
                      gnuplot_quote(fmt::format("side view: cross section |y| ≤ {:.1f} mm", slab * mm)));
  body += "  set xlabel 'x [mm]'\n  set ylabel 'z [mm]'\n";
  body += fmt::format(
      "  plot $section using 1:($4 < 0 ? $2 : NaN):3 with circles lc rgb '{}' title 'particle', \\\n"
      "       $section using 1:($4 >= 0 ? $2 : NaN):3:4 with circles lc palette title 'boundary particle', \\\n"
      "       $section_lines using 1:2:3:4 with vectors nohead lw 2.5 lc rgb 'black' title 'fitted line'\n",
      "#b4b4b4");
  body += "  unset object 1\n  set size noratio\n";
  body += fmt::format("  set xrange [0:{}]\n", num(half_width));
  body += fmt::format("  set title {} noenhanced\n",
                      gnuplot_quote("all directions unrolled: boundary particles and fitted lines"));
  body += "  set xlabel 'radial distance along the direction [mm]'\n  set ylabel 'z [mm]'\n";
  // The levels are measured from the pedestal top (paper §3.3).
  body += fmt::format("  set arrow 1 from 0,{0} to {1},{0} nohead dt 2 lc rgb '{2}'\n",
                      num((v.pedestal_height + 0.2 * v.height) * mm), num(half_width), k_purple);
  body += fmt::format("  set arrow 2 from 0,{0} to {1},{0} nohead dt 2 lc rgb '{2}'\n",
                      num((v.pedestal_height + 0.75 * v.height) * mm), num(half_width), k_purple);
  body +=
      "  plot $boundary using 1:2:3:4 with circles lc palette fs transparent solid 0.5 noborder "
      "title 'boundary particle', \\\n"
      "       $lines using 1:2:3:4:5 with vectors nohead lw 1 lc palette title 'fitted line', \\\n"
      "       NaN with lines dt 2 lc rgb '" +
      std::string(k_purple) + "' title 'levels 0.2 h_P and 0.75 h_P'\n";
  return plotter.render(stem, v.title, data, body, 1.5);
}

// --------------------------------------------------------------------------------------- settlement curve

PlotFiles plot_settlement_curve(const Plotter& plotter, const SettlementCurve& c, const fs::path& stem) {
  assert(c.area > 0);
  const size_t n = c.loads.size();
  assert(c.simulated.empty() || c.simulated.size() == n);
  assert(c.measured.empty() || c.measured.size() == n);
  assert(c.measured_low.size() == c.measured_high.size());
  assert(c.measured_low.empty() || c.measured_low.size() == n);
  constexpr double mm = 1e3;
  constexpr double kpa = 1e-3;
  std::string data = "$curve << EOD\n";
  for (size_t i = 0; i < n; ++i) {
    const double sim = c.simulated.empty() ? k_nan : c.simulated[i];
    const double meas = c.measured.empty() ? k_nan : c.measured[i];
    const double low = c.measured_low.empty() ? meas : c.measured_low[i];
    const double high = c.measured_high.empty() ? meas : c.measured_high[i];
    data += fmt::format("{} {} {} {} {}\n", num(c.loads[i] / c.area * kpa), num(sim * mm), num(meas * mm),
                        num(low * mm), num(high * mm));
  }
  data += "EOD\n";
  std::string body;
  body += fmt::format("  set title {} noenhanced\n", gnuplot_quote(c.title));
  body +=
      "  set xlabel 'vertical stress σ = L / A [kPa]'\n  set ylabel 'settlement s relative to the first load [mm]'\n";
  body +=
      "  set grid lc rgb '#dddddd'\n  set key bottom left box opaque\n  set xrange [0:*]\n  set yrange [*:*] reverse\n";
  for (size_t i = 0; i < n; ++i)
    body += fmt::format("  set arrow {} from first {},graph 0 to first {},graph 1 nohead dt 2 lc rgb '{}'\n", i + 1,
                        num(c.loads[i] / c.area * kpa), num(c.loads[i] / c.area * kpa), k_purple);
  body += fmt::format("  plot NaN with lines dt 2 lc rgb '{}' title 'load steps L_n'", k_purple);
  if (!c.measured.empty()) {
    body += fmt::format(", \\\n       $curve using 1:3 with lines lw 2 lc rgb '{}' title 'measured (mean)'", k_blue);
    if (!c.measured_low.empty())
      body += fmt::format(
          ", \\\n       $curve using 1:3:4:5 with yerrorbars pt 7 lc rgb '{}' title 'measured (lowest, highest)'",
          k_blue);
  }
  if (!c.simulated.empty())
    body +=
        fmt::format(", \\\n       $curve using 1:2 with linespoints lw 2 pt 5 lc rgb '{}' title 'simulated'", k_red);
  body += "\n";
  return plotter.render(stem, c.title, data, body);
}

// ------------------------------------------------------------------------------------------ plate history

PlotFiles plot_plate_history(const Plotter& plotter, const PlateHistoryPlot& h, const fs::path& stem) {
  const size_t n = h.step.size();
  assert(h.load.size() == n && h.force.size() == n);
  assert(h.plate_z.empty() || h.plate_z.size() == n);
  constexpr double mm = 1e3;
  std::string data = "$history << EOD\n";
  for (size_t i = 0; i < n; ++i)
    data += fmt::format("{} {} {} {}\n", num(h.step[i]), num(h.load[i]), num(h.force[i]),
                        num(h.plate_z.empty() ? k_nan : h.plate_z[i] * mm));
  data += "EOD\n";
  std::string body;
  body += fmt::format("  set title {} noenhanced\n", gnuplot_quote(h.title));
  body += "  set xlabel 'time step'\n  set ylabel 'force on the plate [N]'\n";
  body += "  set grid lc rgb '#dddddd'\n  set key outside top center horizontal\n  set yrange [0:*]\n";
  if (!h.plate_z.empty()) body += "  set y2label 'plate height z [mm]'\n  set y2tics\n  set ytics nomirror\n";
  body += fmt::format(
      "  plot $history using 1:3 with lines lw 1.5 lc rgb '{}' title 'particle force F_R', \\\n"
      "       $history using 1:2 with steps dt 2 lw 2 lc rgb '{}' title 'load step L_n'",
      k_red, k_purple);
  if (!h.plate_z.empty())
    body += fmt::format(", \\\n       $history using 1:4 axes x1y2 with lines lw 1.5 lc rgb '{}' title 'plate height'",
                        k_blue);
  body += "\n";
  return plotter.render(stem, h.title, data, body);
}

PlotFiles plot_image(const ImageFigure& image, const fs::path& stem) {
  PlotFiles files;
  files.png = fs::path(stem.string() + ".png");
  std::error_code ec;
  fs::copy_file(image.png, files.png, fs::copy_options::overwrite_existing, ec);
  if (ec) throw UserError(fmt::format("{}: cannot copy the picture into the report: {}", image.png, ec.message()));
  return files;
}

PlotFiles plot_lines(const Plotter& plotter, const LinePlot& p, const fs::path& stem) {
  // Twenty colours (matplotlib's tab20), repeated beyond.
  static const char* const colours[] = {"#1f77b4", "#aec7e8", "#ff7f0e", "#ffbb78", "#2ca02c", "#98df8a", "#d62728",
                                        "#ff9896", "#9467bd", "#c5b0d5", "#8c564b", "#c49c94", "#e377c2", "#f7b6d2",
                                        "#7f7f7f", "#c7c7c7", "#bcbd22", "#dbdb8d", "#17becf", "#9edae5"};
  std::string data;
  for (size_t k = 0; k < p.series.size(); ++k) {
    const LinePlot::Series& s = p.series[k];
    assert(s.x.size() == s.y.size());
    data += fmt::format("$series{} << EOD\n", k);
    for (size_t i = 0; i < s.x.size(); ++i) data += fmt::format("{} {}\n", num(s.x[i]), num(s.y[i]));
    data += "EOD\n";
  }
  std::string body;
  body += fmt::format("  set title {} noenhanced\n", gnuplot_quote(p.title));
  body += fmt::format("  set xlabel {} noenhanced\n  set ylabel {} noenhanced\n", gnuplot_quote(p.x_label),
                      gnuplot_quote(p.y_label));
  body += "  set grid lc rgb '#dddddd'\n  set key outside top center horizontal noenhanced\n";
  std::string plots;
  for (size_t k = 0; k < p.series.size(); ++k) {
    const LinePlot::Series& s = p.series[k];
    const std::string colour = s.colour.empty() ? colours[k % std::size(colours)] : s.colour;
    plots += fmt::format("{}$series{} using 1:2 with {} lc rgb '{}' {}", plots.empty() ? "" : ", \\\n       ", k,
                         s.points ? "points pt 7 ps 0.5" : "lines lw 1.5", colour,
                         s.name.empty() ? "notitle" : "title " + gnuplot_quote(s.name));
  }
  if (!p.y_reference_label.empty())
    plots += fmt::format("{}{} with lines dt 2 lw 1.5 lc rgb 'black' title {}", plots.empty() ? "" : ", \\\n       ",
                         num(p.y_reference), gnuplot_quote(p.y_reference_label));
  if (plots.empty()) plots = "NaN notitle";
  body += "  plot " + plots + "\n";
  return plotter.render(stem, p.title, data, body);
}

// -------------------------------------------------------------------------------------------- calibration

PlotFiles plot_calibration(const Plotter& plotter, const CalibrationPlot& c, const fs::path& stem) {
  const size_t d = c.parameter_labels.size();
  const size_t m = c.observable_labels.size();
  assert(c.optimum_unit.size() == d && c.optimum_physical.size() == d);
  assert(c.target.size() == m && c.predicted.size() == m);
  assert(c.measured.empty() || c.measured.size() == m);
  std::string data = "$optimum << EOD\n";
  for (size_t i = 0; i < d; ++i)
    data += fmt::format("{} {} {} {}\n", i, num(c.optimum_unit[i]), gnuplot_quote(c.parameter_labels[i]),
                        gnuplot_quote(fmt::format("{:.4g}", c.optimum_physical[i])));
  data += "EOD\n";
  for (size_t k = 0; k < m; ++k) {
    const double measured = c.measured.empty() ? k_nan : c.measured[k];
    data += fmt::format("$observable{} << EOD\n0 {} \"target\"\n1 {} \"predicted\"\n2 {} \"measured\"\nEOD\n", k,
                        num(c.target[k]), num(c.predicted[k]), num(measured));
  }
  const int panels = static_cast<int>(1 + m);
  std::string body;
  body += fmt::format("  set multiplot layout 1,{} title {} noenhanced\n", panels, gnuplot_quote(c.title));
  body += "  set grid xtics lc rgb '#dddddd'\n  unset key\n";
  body += fmt::format("  set yrange [-0.7:{}]\n  set xrange [-0.02:1.25]\n", num(d - 0.3));
  body += "  set xlabel 'position in the study range (0 = low, 1 = high)'\n  set xtics 0,0.25,1\n";
  body += "  set title 'optimum'\n";
  body += fmt::format(
      "  plot $optimum using (0):1:(1):(0):ytic(3) with vectors nohead lw 6 lc rgb '#dddddd', \\\n"
      "       $optimum using 2:1 with points pt 7 ps 1.6 lc rgb '{}', \\\n"
      "       $optimum using 2:1:4 with labels offset 0,0.9 font ',{}'\n",
      k_red, std::max(8, plotter.options().font_size - 2));
  // Without a verification run there is no measured bar.
  body += c.measured.empty() ? "  set xtics ('target' 0, 'predicted' 1)\n  set xrange [-0.6:1.6]\n"
                             : "  set xtics ('target' 0, 'predicted' 1, 'measured' 2)\n  set xrange [-0.6:2.6]\n";
  body +=
      "  unset yrange\n  set grid ytics\n  unset xlabel\n  set style fill solid 0.85 border rgb 'black'\n"
      "  set boxwidth 0.7\n";
  for (size_t k = 0; k < m; ++k) {
    double panel_top = 0;
    for (double v : {c.target[k], c.predicted[k], c.measured.empty() ? 0.0 : c.measured[k]})
      if (std::isfinite(v)) panel_top = std::max(panel_top, v);
    body += fmt::format("  set yrange [0:{}]\n", num(panel_top > 0 ? panel_top * 1.15 : 1.0));
    body += fmt::format("  set title {}\n  set ylabel {}\n", gnuplot_quote(c.observable_labels[k]),
                        gnuplot_quote(c.observable_labels[k]));
    body += fmt::format(
        "  plot $observable{0} using 1:2:($1 == 0 ? 1 : ($1 == 1 ? 2 : 3)) with boxes lc variable, \\\n"
        "       $observable{0} using 1:2:(sprintf('%.4g', $2)) with labels offset 0,0.8\n",
        k);
  }
  return plotter.render(stem, c.title, data, body, 1.0);
}

}  // namespace demsa::report
