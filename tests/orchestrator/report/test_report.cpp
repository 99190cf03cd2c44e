// The report (orchestrator/report.hpp): rendering of the document model, and the report of synthetic pile and
// oedometer studies (store, analysis, case files) with every table, every plot and a self-contained HTML page.
#include "orchestrator/analysis/calibration.hpp"
#include "orchestrator/report/report.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <sstream>

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::analysis;
using namespace demsa::report;

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

size_t count_of(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

/// Width, height, distinct colours and non-background fraction of a PNG (tests/data/report/png_stats.py).
std::vector<double> png_stats(const fs::path& png) {
  const CommandResult r = run_command({"python3", data_path("report/png_stats.py").string(), png.string()});
  EXPECT_EQ(r.exit_code, 0) << png << ": " << r.err;
  std::istringstream in(r.out);
  std::vector<double> v(4, 0.0);
  in >> v[0] >> v[1] >> v[2] >> v[3];
  return v;
}

TEST(Report, Base64KnownVectors) {  // RFC 4648 §10
  EXPECT_EQ(base64_encode(""), "");
  EXPECT_EQ(base64_encode("f"), "Zg==");
  EXPECT_EQ(base64_encode("fo"), "Zm8=");
  EXPECT_EQ(base64_encode("foo"), "Zm9v");
  EXPECT_EQ(base64_encode("foob"), "Zm9vYg==");
  EXPECT_EQ(base64_encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64_encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64_encode(std::string("\xff\x00\x80", 3)), "/wCA");
}

TEST(Report, IntervalFormatting) {
  // One number format per column: three decimals for the value and both bounds.
  EXPECT_EQ(format_interval(0.5302, 0.512, 0.551), "0.530 [0.512, 0.551]");
  EXPECT_EQ(format_interval(3.7e-5, 3.7e-5, 3.7e-5), "0.000");  // collapsed interval (exact RSM indices)
  EXPECT_EQ(format_interval(0.0213, 0.02130001, 0.0213), "0.021");
  EXPECT_EQ(format_interval(1e-31, -2e-33, 3e-30), "0.000");  // round-off of a zero, no "-0.000"
  EXPECT_EQ(format_interval(0.25, std::nan(""), std::nan("")), "0.250");
  EXPECT_EQ(format_interval(std::nan(""), 0, 1), "n/a [0.000, 1.000]");
  // A lower bound below 0 is clipped at 0 and marked.
  EXPECT_EQ(format_interval(0.012, -0.031, 0.054), "0.012 [0.000*, 0.054]");
}

TEST(Report, MarkdownAndHtmlOfADocument) {
  TempDir dir;
  const Plotter plotter;
  SobolBarChart chart{"bars", {"E", "ν"}, {{0.7, 0.6, 0.8}, {0.2, 0.1, 0.3}}, {}};
  ReportDocument doc;
  doc.title = "a <study>";
  ReportSection s;
  s.heading = "Tables & plots";
  s.paragraphs = {"Study `x` with *two* parameters."};
  s.tables.push_back({"caption", {"model", "E | ν"}, {{"rsm2", "0.7"}}});
  s.figures.push_back({"the bars", plot_sobol_bars(plotter, chart, dir / "img" / "bars")});
  doc.sections.push_back(s);
  const std::string md = render_markdown(doc, dir.path());
  EXPECT_NE(md.find("# a \\<study\\>\n"), std::string::npos) << md;
  EXPECT_NE(md.find("## Tables & plots"), std::string::npos) << md;
  EXPECT_NE(md.find("| model | E \\| ν |"), std::string::npos) << md;
  EXPECT_NE(md.find("![the bars](img/bars.png)"), std::string::npos) << md;
  EXPECT_NE(md.find("[SVG](img/bars.svg)"), std::string::npos) << md;
  const std::string html = render_html(doc);
  EXPECT_NE(html.find("<title>a &lt;study&gt;</title>"), std::string::npos);
  EXPECT_NE(html.find("<code>x</code>"), std::string::npos);
  EXPECT_NE(html.find("<em>two</em>"), std::string::npos);
  EXPECT_EQ(count_of(html, "src=\"data:image/png;base64,"), 1u);
  EXPECT_NE(html.find(base64_encode(read_file(dir / "img" / "bars.png"))), std::string::npos);
  EXPECT_EQ(count_of(html, "<td>"), 2u);
  // A heading's code span is code, not backticks printed as text.
  ReportSection observable;
  observable.heading = "Observable `angle` & more";
  doc.sections = {observable};
  EXPECT_NE(render_html(doc).find("<h2>Observable <code>angle</code> &amp; more</h2>"), std::string::npos)
      << render_html(doc);
}

TEST(Report, MarkdownShowsTheStudyNameAsTextNotMarkup) {
  // The title carries the user's study name: HTML escapes it, and so does the Markdown (CommonMark backslash
  // escapes), so that neither raw HTML, a link nor emphasis reaches report.md, nor a line break its heading.
  ReportDocument doc;
  doc.title = "demsa report: <img src=x onerror=alert(1)> *b* [l](u) `c` &amp;\n# h";
  const std::string md = render_markdown(doc, ".");
  EXPECT_EQ(md.substr(0, md.find('\n') + 1),
            "# demsa report: \\<img src=x onerror=alert\\(1\\)\\> \\*b\\* \\[l\\]\\(u\\) \\`c\\` \\&amp; \\# h\n")
      << md;
}

TEST(Report, AStudyNameIsOneCodeSpanWhateverItHolds) {
  // A name with a backtick ended the "Study `NAME`" code span, and its line breaks started headings and raw HTML.
  const std::string name = "a`b\n\n# heading\n<script>x</script> [l](u) ``` `";
  const std::string span = code_span(name);
  EXPECT_EQ(span, "```` a`b  # heading <script>x</script> [l](u) ``` ` ````");
  EXPECT_EQ(span.find('\n'), std::string::npos);
  EXPECT_EQ(code_span("plain"), "`plain`");
  EXPECT_EQ(code_span("`x"), "`` `x ``");
  // The HTML page reads the span back as one <code> element, escaped.
  ReportDocument doc;
  ReportSection section;
  section.paragraphs.push_back("Study " + span + ": pile, design `lhs`.");
  doc.sections.push_back(section);
  const std::string html = render_html(doc);
  EXPECT_NE(html.find("<p>Study <code>a`b  # heading &lt;script&gt;x&lt;/script&gt; [l](u) ``` `</code>: pile, design "
                      "<code>lhs</code>.</p>"),
            std::string::npos)
      << html;
  EXPECT_EQ(html.find("<script>"), std::string::npos);
}

TEST(Report, HtmlOfAMissingImageFails) {
  ReportDocument doc;
  ReportSection s;
  s.figures.push_back({"gone", {"/nonexistent/a.gp", "/nonexistent/a.png", "/nonexistent/a.svg"}});
  doc.sections.push_back(s);
  EXPECT_THROW(render_html(doc), std::runtime_error);
}

TEST(Report, OptionsValidation) {
  ReportOptions o;
  EXPECT_THROW(o.validate(), UserError);
  o.dir = "x";
  o.sample = -2;
  EXPECT_THROW(o.validate(), UserError);
  o.sample = 3;
  o.plot.width = 10;
  EXPECT_THROW(o.validate(), UserError);
}

TEST(Report, NotAStudyFolder) {
  TempDir dir;
  ReportOptions o;
  o.dir = dir.path();
  try {
    write_study_report(o);
    FAIL() << "accepted";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("not a study folder"), std::string::npos) << e.what();
  }
}

// ------------------------------------------------------------------------------- synthetic studies

const std::string k_pile_study =
    StudyToml{.name = "pile-synthetic",
              .seed = 7,
              .samples = 24,
              .parameters =
                  "mu_pp = { low = 0.7, high = 1.9 }\nmu_r_pp = { low = 0.05, high = 0.5 }\n"
                  "e_r = { low = 0.2, high = 0.6 }\n",
              .analysis = "metamodels = [\"rsm2\", \"rbf-cubic\"]\nbootstrap = 10\nbase_samples = 512\n"}
        .text();

const std::string k_oedometer_study =
    StudyToml{.name = "oedometer-synthetic",
              .experiment = "oedometer",
              .seed = 9,
              .samples = 16,
              .parameters = "E = { low = 1e8, high = 1e9, scale = \"log\" }\nnu = { low = 0.2, high = 0.4 }\n",
              .tables = "[oedometer]\nmeasured_settlements = [0.4e-3, 1.0e-3, 1.8e-3]\n",
              .analysis = "metamodels = [\"rsm2\"]\nbootstrap = 10\nbase_samples = 512\n"}
        .text();

/// A study folder with `n` done samples at random points whose observables come from `measure(unit)`; two failed
/// attempts (one sample failed for good, of class "timeout"; one retried and done).
void write_study(const fs::path& dir, const std::string& toml,
                 const std::function<std::map<std::string, double>(const std::vector<double>&)>& measure) {
  SyntheticStudy study = start_synthetic_study(dir, toml, 5);
  Store& store = study.store;
  RunOutcome failed;
  failed.failure = study::FailureClass::timeout;
  failed.cpu_seconds = 100;
  failed.wall_seconds = 100;
  store.record_failed(store.add_run(0, 1), failed);
  store.record_failed(store.add_run(1, 1), failed);
  for (const SampleRow& row : study.samples) {
    if (row.sample == 0) continue;  // failed for good
    const long run = store.add_run(row.sample, row.sample == 1 ? 2 : 1);
    RunOutcome done;
    done.exit_code = 0;
    done.cpu_seconds = 360;
    done.wall_seconds = 400;
    store.record_done(run, done, measure(row.unit));
  }
}

/// A cone of particles (slope 30°) on the pedestal, as a LIGGGHTS text dump.
void write_cone_dump(const fs::path& file) {
  const double r = 0.0015;
  const double slope = std::tan(30.0 * M_PI / 180);
  std::string atoms;
  int n = 0;
  for (double z = 0.005 + r; z < 0.005 + 0.05 * slope; z += 2 * r) {
    const double outer = 0.05 - (z - 0.005) / slope;
    for (double x = -outer; x <= outer; x += 2 * r)
      for (double y = -outer; y <= outer; y += 2 * r)
        if (x * x + y * y <= outer * outer)
          atoms += fmt::format("{} 1 {:.6f} {:.6f} {:.6f} {} 0 0 0\n", ++n, x, y, z, r);
  }
  write_file(file, fmt::format("ITEM: TIMESTEP\n1000\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS ff ff ff\n"
                               "-0.1 0.1\n-0.1 0.1\n0 0.2\nITEM: ATOMS id type x y z radius vx vy vz\n{}",
                               n, atoms));
}

void expect_images_drawn(const ReportSummary& summary) {
  for (const fs::path& png : summary.images) {
    ASSERT_TRUE(fs::exists(png)) << png;
    EXPECT_TRUE(fs::exists(fs::path(png).replace_extension(".svg"))) << png;
    EXPECT_TRUE(fs::exists(fs::path(png).replace_extension(".gp"))) << png;
    const std::vector<double> s = png_stats(png);
    EXPECT_GE(s[0], 200) << png;
    EXPECT_GT(s[2], 8) << png;     // colours
    EXPECT_GT(s[3], 0.01) << png;  // not blank
  }
}

TEST(Report, PileStudyWithFigureFourAndCalibration) {
  TempDir dir;
  write_study(dir.path(), k_pile_study, [](const std::vector<double>& u) {
    return std::map<std::string, double>{{"angle", 24 + 14 * u[1] + 2 * u[0] * u[0] + 0.5 * u[2]},
                                         {"pile_height", 0.02 + 0.01 * u[1]}};
  });
  write_cone_dump(dir / "cases" / "000003" / "pile_final.dump");
  CalibrateOptions calibrate;
  calibrate.dir = dir.path();
  calibrate.targets = {{.name = "angle", .value = 33.5}};
  calibrate_study(calibrate);

  ReportOptions options;
  options.dir = dir.path();
  options.sample = 3;
  const ReportSummary summary = write_study_report(options);
  EXPECT_TRUE(summary.notes.empty()) << summary.notes.front();
  EXPECT_EQ(summary.sample_shown, 3);
  // per observable (2): 2 Sobol' bars, 2 LOO, 1 response; the pile; the calibration
  EXPECT_EQ(summary.images.size(), 2u * 5u + 2u);
  expect_images_drawn(summary);
  const std::string md = read_file(summary.markdown);
  EXPECT_NE(md.find("24 in the design, 23 done, 1 failed"), std::string::npos) << md;
  EXPECT_NE(md.find("| timeout | 1 | 2 |"), std::string::npos) << md;
  EXPECT_NE(md.find("CPU time of all attempts: 2.356 h"), std::string::npos) << md;  // (23·360 + 2·100) s
  EXPECT_NE(md.find("| metamodel | μ_PP | e_r | μ_R,PP | Res |"), std::string::npos) << md;
  EXPECT_NE(md.find("Second-order indices S2 (RSM quad.)"), std::string::npos) << md;
  EXPECT_NE(md.find("| RSM quad. | 10 | 1.0000 | 1.0000 | 1.0000 |"), std::string::npos) << md;  // exact fit
  EXPECT_NE(md.find("the pile (paper Fig. 4)"), std::string::npos) << md;
  EXPECT_NE(md.find("## Calibration"), std::string::npos) << md;
  EXPECT_NE(md.find("![The pile of sample 3"), std::string::npos) << md;
  EXPECT_NE(md.find("the paper's estimator, §3.3"), std::string::npos) << md;
  const std::string html = read_file(summary.html);
  EXPECT_EQ(count_of(html, "src=\"data:image/png;base64,"), summary.images.size());
  EXPECT_EQ(count_of(html, "src=\""), summary.images.size());  // nothing outside the page
  // The cone's slope is 30°: the measured angle in the report is close to it.
  const auto at = md.find("angle of repose φ = ");
  ASSERT_NE(at, std::string::npos) << md;
  EXPECT_NEAR(std::stod(md.substr(at + std::string("angle of repose φ = ").size())), 30.0, 3.0);
}

TEST(Report, PileFigureUsesTheStudysAngleEstimator) {
  TempDir dir;
  StudyToml toml{.name = "pile-robust",
                 .seed = 7,
                 .samples = 24,
                 .parameters = "mu_pp = { low = 0.7, high = 1.9 }\nmu_r_pp = { low = 0.05, high = 0.5 }\n",
                 .tables = "[pile]\nangle_estimator = \"robust\"\n",
                 .analysis = "metamodels = [\"rsm2\"]\nbootstrap = 0\nbase_samples = 256\n"};
  write_study(dir.path(), toml.text(), [](const std::vector<double>& u) {
    return std::map<std::string, double>{{"angle", 24 + 14 * u[1] + 2 * u[0] * u[0]},
                                         {"pile_height", 0.02 + 0.01 * u[1]}};
  });
  write_cone_dump(dir / "cases" / "000003" / "pile_final.dump");
  ReportOptions options;
  options.dir = dir.path();
  options.sample = 3;
  const std::string md = read_file(write_study_report(options).markdown);
  EXPECT_NE(md.find("robust estimator: Theil–Sen lines through the surface points"), std::string::npos) << md;
  const auto at = md.find("angle of repose φ = ");
  ASSERT_NE(at, std::string::npos) << md;
  EXPECT_NEAR(std::stod(md.substr(at + std::string("angle of repose φ = ").size())), 30.0, 3.0);
}

TEST(Report, OedometerStudyWithFiguresFiveAndSixB) {
  TempDir dir;
  write_study(dir.path(), k_oedometer_study, [](const std::vector<double>& u) {
    const double soft = 1.0 - 0.6 * u[0] + 0.05 * u[1];
    const double s1 = 0.5e-3 * soft, s2 = 1.2e-3 * soft, s3 = 2.0e-3 * soft;
    return std::map<std::string, double>{
        {"settlement_1", s1},
        {"settlement_2", s2},
        {"settlement_3", s3},
        {"settlement_error",
         std::sqrt(std::pow(s1 - 0.4e-3, 2) + std::pow(s2 - 1.0e-3, 2) + std::pow(s3 - 1.8e-3, 2))}};
  });
  // Sample 5's plate files: four load states and a history with trial steps.
  const fs::path cases = dir / "cases" / "000005";
  write_file(cases / "plate_states.txt",
             "# load_N plate_z_m force_N converged\n100 0.0600 100.01 1\n400 0.0595 400.02 1\n"
             "1100 0.0588 1099.98 1\n2700 0.0580 2700.01 1\n");
  std::string history = "# plate history\n# step load_N plate_z_m force_N\n";
  const double loads[] = {100, 400, 1100, 2700};
  const double z_end[] = {0.0600, 0.0595, 0.0588, 0.0580};
  for (int i = 0; i < 200; ++i) {
    const int k = i / 50;
    const double frac = (i % 50) / 49.0;
    const double z0 = k == 0 ? 0.0610 : z_end[k - 1];
    history += fmt::format("{} {} {:.6f} {:.3f}\n", i * 1000, loads[k], z0 + (z_end[k] - z0) * frac,
                           loads[k] * (1 - std::exp(-5 * frac)));
  }
  write_file(cases / "plate_history.txt", history);
  ReportOptions options;
  options.dir = dir.path();
  options.sample = 5;
  const ReportSummary summary = write_study_report(options);
  EXPECT_TRUE(summary.notes.empty()) << summary.notes.front();
  // 4 observables (settlements 1-3, E_0) × (1 bars + 1 LOO + 1 response) + settlement curve + plate history
  EXPECT_EQ(summary.images.size(), 4u * 3u + 2u);
  expect_images_drawn(summary);
  const std::string md = read_file(summary.markdown);
  EXPECT_NE(md.find("the oedometer (paper Figs. 5 and 6b)"), std::string::npos) << md;
  EXPECT_NE(md.find("| 2700 | 270.0 | 2700.010 | yes | 2.0000 | 1.8000 |"), std::string::npos) << md;
  EXPECT_NE(md.find("Settlement error E_0 = "), std::string::npos) << md;
  EXPECT_TRUE(fs::exists(dir / "report" / "plate_history.png"));
  EXPECT_TRUE(fs::exists(dir / "report" / "settlement_curve.svg"));
}

TEST(Report, MissingCaseFilesBecomeANoteNotAFailure) {
  TempDir dir;
  write_study(dir.path(), k_pile_study, [](const std::vector<double>& u) {
    return std::map<std::string, double>{{"angle", 24 + 14 * u[1]}, {"pile_height", 0.02 + 0.01 * u[0]}};
  });
  ReportOptions options;
  options.dir = dir.path();
  options.html = false;
  const ReportSummary summary = write_study_report(options);
  ASSERT_EQ(summary.notes.size(), 1u);
  EXPECT_NE(summary.notes[0].find("pile_final.dump"), std::string::npos) << summary.notes[0];
  EXPECT_TRUE(summary.html.empty());
  EXPECT_NE(read_file(summary.markdown).find("## Notes"), std::string::npos);
}

TEST(Report, UnknownSampleIsAUserError) {
  TempDir dir;
  write_study(dir.path(), k_pile_study, [](const std::vector<double>& u) {
    return std::map<std::string, double>{{"angle", 24 + 14 * u[1]}, {"pile_height", 0.02 + 0.01 * u[0]}};
  });
  ReportOptions options;
  options.dir = dir.path();
  options.sample = 0;  // failed for good
  EXPECT_THROW(write_study_report(options), UserError);
}

}  // namespace
}  // namespace demsa::test
