#include "orchestrator/report/posterior_plots.hpp"

#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace demsa::report {

namespace fs = std::filesystem;
using analysis::PosteriorOutcome;
using analysis::PosteriorParameter;
using analysis::PosteriorTarget;

namespace {

constexpr int k_bins = 40;
constexpr const char* k_bar = "#4C72B0";
constexpr const char* k_map = "#C44E52";

std::string num(double v) { return std::isfinite(v) ? fmt::format("{:.10g}", v) : "NaN"; }

/// The coordinate of a draw on the prior's design scale (log10 for a log prior), so histograms have even bins.
double design(double v, const PosteriorParameter& p) { return p.log ? std::log10(v) : v; }
std::string axis(const PosteriorParameter& p) { return p.log ? fmt::format("log10({})", p.name) : p.name; }

/// Three labelled tics, at both ends and the middle of [lo, hi]: a corner plot's small panels have room for no more.
std::string three_tics(double lo, double hi) {
  return fmt::format("('{:.3g}' {}, '{:.3g}' {}, '{:.3g}' {})", lo, num(lo), 0.5 * (lo + hi), num(0.5 * (lo + hi)), hi,
                     num(hi));
}

/// Histogram of column j as a density on the prior's range: "centre density" rows.
std::string histogram(const Eigen::MatrixXd& draws, int j, const PosteriorParameter& p) {
  const double lo = design(p.low, p), hi = design(p.high, p);
  std::vector<double> counts(k_bins, 0.0);
  for (Eigen::Index i = 0; i < draws.rows(); ++i) {
    const int b = std::clamp(static_cast<int>((design(draws(i, j), p) - lo) / (hi - lo) * k_bins), 0, k_bins - 1);
    counts[static_cast<size_t>(b)] += 1.0;
  }
  const double width = (hi - lo) / k_bins;
  std::string out;
  for (int b = 0; b < k_bins; ++b)
    out += fmt::format("{} {}\n", num(lo + (b + 0.5) * width),
                       num(counts[static_cast<size_t>(b)] / (static_cast<double>(draws.rows()) * width)));
  return out;
}

/// Observable family of a target: "settlement_3" -> "settlement".
std::string family(const std::string& name) {
  const auto u = name.find_last_of('_');
  if (u != std::string::npos && u + 1 < name.size() &&
      std::all_of(name.begin() + static_cast<long>(u) + 1, name.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return name.substr(0, u);
  return name;
}

}  // namespace

PosteriorFigures plot_posterior(const Plotter& plotter, const PosteriorOutcome& o, const fs::path& samples,
                                const fs::path& folder) {
  const util::CsvTable table = util::read_csv(samples);
  const int d = static_cast<int>(o.parameters.size());
  Eigen::MatrixXd draws(table.rows(), d);
  for (int j = 0; j < d; ++j) draws.col(j) = table.values.col(table.column_index(o.parameters[j].name));
  PosteriorFigures figures;

  // Marginal histograms, one panel per parameter, the prior's density as a dashed line and the 5/95 % quantiles.
  {
    std::string data;
    for (int j = 0; j < d; ++j) data += fmt::format("$h{} << EOD\n{}EOD\n", j, histogram(draws, j, o.parameters[j]));
    const int cols = std::min(d, 3), rows = (d + cols - 1) / cols;
    std::string body =
        fmt::format("  set multiplot layout {},{} title 'posterior marginals (dashed: prior)'\n", rows, cols);
    body += "  unset key\n  set style fill solid 0.6 border rgb 'black'\n  set ylabel 'density'\n";
    for (int j = 0; j < d; ++j) {
      const PosteriorParameter& p = o.parameters[j];
      const double lo = design(p.low, p), hi = design(p.high, p);
      body += fmt::format("  set xrange [{}:{}]\n  set yrange [0:*]\n  set xlabel '{}' noenhanced\n", num(lo), num(hi),
                          axis(p));
      body += fmt::format("  set title '{}: width {:.2f}, identified: {}' noenhanced font ',10'\n", p.name,
                          p.width_ratio, p.identified);
      body += fmt::format("  unset arrow\n  set arrow from {0},graph 0 to {0},graph 1 nohead lc rgb '{1}' lw 2\n",
                          num(design(p.map, p)), k_map);
      body += fmt::format("  set arrow from {0},graph 0 to {0},graph 1 nohead dt 3 lc rgb 'black'\n",
                          num(design(p.q05, p)));
      body += fmt::format("  set arrow from {0},graph 0 to {0},graph 1 nohead dt 3 lc rgb 'black'\n",
                          num(design(p.q95, p)));
      body += fmt::format("  plot $h{} using 1:2 with boxes lc rgb '{}', {} with lines dt 2 lc rgb 'black'\n", j, k_bar,
                          num(1.0 / (hi - lo)));
    }
    body += "  unset arrow\n";
    figures.marginals = plotter.render(folder / "posterior_marginals", "posterior marginals", data, body,
                                       rows > 1 ? 1.0 + 0.5 * (rows - 1) : 1.0);
  }

  // Corner plot: histograms on the diagonal, up to 1500 draws per pair below it.
  {
    const Eigen::Index stride = std::max<Eigen::Index>(1, draws.rows() / 1500);
    std::string data = "$draws << EOD\n";
    for (Eigen::Index i = 0; i < draws.rows(); i += stride) {
      for (int j = 0; j < d; ++j) data += num(design(draws(i, j), o.parameters[j])) + (j + 1 < d ? " " : "\n");
    }
    data += "EOD\n";
    for (int j = 0; j < d; ++j) data += fmt::format("$h{} << EOD\n{}EOD\n", j, histogram(draws, j, o.parameters[j]));
    std::string body = fmt::format("  set multiplot layout {0},{0} title 'posterior: marginals and pairs'\n", d);
    body += "  unset key\n  set style fill solid 0.6 border rgb 'black'\n  set tics font ',8'\n";
    body += "  set lmargin 7\n  set rmargin 3\n  set tmargin 1\n  set bmargin 3\n";
    for (int r = 0; r < d; ++r)
      for (int c = 0; c < d; ++c) {
        const PosteriorParameter& pr = o.parameters[r];
        const PosteriorParameter& pc = o.parameters[c];
        const double x_lo = design(pc.low, pc), x_hi = design(pc.high, pc);
        const double y_lo = design(pr.low, pr), y_hi = design(pr.high, pr);
        body += fmt::format("  set xrange [{}:{}]\n  set xtics {}\n", num(x_lo), num(x_hi), three_tics(x_lo, x_hi));
        body +=
            r == c ? std::string("  set ytics autofreq\n") : fmt::format("  set ytics {}\n", three_tics(y_lo, y_hi));
        body += r == d - 1 ? fmt::format("  set xlabel '{}' noenhanced\n", axis(pc)) : "  unset xlabel\n";
        body += c == 0 && r > 0 ? fmt::format("  set ylabel '{}' noenhanced\n", axis(pr)) : "  unset ylabel\n";
        if (c > r) {
          body += "  set multiplot next\n";
        } else if (r == c) {
          body += fmt::format("  set yrange [0:*]\n  plot $h{} using 1:2 with boxes lc rgb '{}'\n", r, k_bar);
        } else {
          body += fmt::format("  set yrange [{}:{}]\n", num(y_lo), num(y_hi));
          body += fmt::format(
              "  plot $draws using {}:{} with dots lc rgb '{}', '+' using ({}):({}) every ::0::0 "
              "with points pt 7 ps 1 lc rgb '{}'\n",
              c + 1, r + 1, k_bar, num(design(pc.map, pc)), num(design(pr.map, pr)), k_map);
        }
      }
    // Square panels of about 180 px: a square canvas, whatever the default aspect.
    const double side = std::max(960.0, 180.0 * d);
    figures.corner = plotter.render(folder / "posterior_corner", "posterior corner plot", data, body,
                                    side / plotter.options().height, side / plotter.options().width);
  }

  // Posterior predictive against the measurements, one panel per observable family.
  {
    std::map<std::string, std::vector<const PosteriorTarget*>> groups;
    std::vector<std::string> order;
    for (const PosteriorTarget& t : o.targets) {
      const std::string key = t.study + ": " + family(t.name);
      if (!groups.count(key)) order.push_back(key);
      groups[key].push_back(&t);
    }
    std::string data;
    for (size_t g = 0; g < order.size(); ++g) {
      data += fmt::format("$p{} << EOD\n", g);
      int x = 1;
      for (const PosteriorTarget* t : groups[order[g]])
        data += fmt::format("{} {} {} {} {} {} {} \"{}\"\n", x++, num(t->value), num(t->sd), num(t->predictive_q05),
                            num(t->predictive_q50), num(t->predictive_q95), num(t->predicted_map), t->name);
      data += "EOD\n";
    }
    std::string body = fmt::format(
        "  set multiplot layout 1,{} title 'posterior predictive against the measurements'\n", order.size());
    body += "  set key below\n  set grid ytics\n  set xtics noenhanced\n  set offsets 0, 0, graph 0.05, graph 0.05\n";
    for (size_t g = 0; g < order.size(); ++g) {
      const size_t n = groups[order[g]].size();
      body += fmt::format("  set title '{}' noenhanced\n  set xrange [0.5:{}]\n  set yrange [*:*]\n", order[g],
                          num(n + 0.5));
      body += fmt::format(
          "  plot $p{0} using ($1-0.1):2:3:xtic(8) with yerrorbars pt 7 lw 2 lc rgb 'black' "
          "title 'measured ± sd', \\\n"
          "       $p{0} using ($1+0.1):5:4:6 with yerrorbars pt 6 lw 3 lc rgb '{1}' "
          "title 'predictive median, 90 %', \\\n"
          "       $p{0} using ($1+0.1):7 with points pt 9 ps 1.4 lc rgb '{2}' title 'MAP'\n",
          g, k_bar, k_map);
    }
    figures.predictive = plotter.render(folder / "posterior_predictive", "posterior predictive", data, body, 1.0);
  }
  return figures;
}

PlotFiles plot_plan(const Plotter& plotter, const analysis::PlanOutcome& plan, const std::filesystem::path& folder) {
  PlanWidthChart chart;
  chart.title = fmt::format("demsa plan: expected 90 % posterior width per parameter ({} truths)", plan.truths);
  chart.parameters = plan.parameters;
  for (const analysis::PlanSubset& s : plan.subsets) {
    chart.subsets.push_back(util::join(s.studies, " + "));
    chart.width.push_back(s.width);
  }
  chart.goal = plan.goal;
  chart.recommended = plan.recommended;
  if (plan.recommended >= 0)
    chart.recommended_label = analysis::plan_mark(plan, static_cast<std::size_t>(plan.recommended));
  return plot_plan_widths(plotter, chart, folder / "plan_widths");
}

std::string plot_posterior_note(const PosteriorOutcome& outcome) {
  try {
    plot_posterior(Plotter(), outcome, outcome.out / "posterior_samples.csv", outcome.out);
  } catch (const util::UserError& e) {
    return fmt::format("no plots: {}", e.what());
  }
  return "";
}

}  // namespace demsa::report
