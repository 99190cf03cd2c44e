// `demsa report` and `demsa calibrate` (README "Usage").
#include "orchestrator/report/report.hpp"
#include "orchestrator/analysis/calibration.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/exec/point_run.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <memory>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::exec;
using namespace demsa::analysis;
using namespace demsa::report;

namespace {

struct ReportArgs {
  std::string dir;
  std::string out;
  int sample = -1;
  bool no_html = false;
  int width = 960;
  int height = 640;
  int font_size = 13;
  bool json = false;
};

struct CalibrateArgs {
  CalibrateOptions options;
  std::string dir;
  bool json = false;
};

int do_report(const ReportArgs& args) {
  ReportOptions options;
  options.dir = args.dir;
  options.out = args.out;
  options.sample = args.sample;
  options.html = !args.no_html;
  options.plot.width = args.width;
  options.plot.height = args.height;
  options.plot.font_size = args.font_size;
  const ReportSummary summary = write_study_report(options);
  if (args.json) {
    nlohmann::json j{{"dir", summary.out_dir.string()},
                     {"markdown", summary.markdown.string()},
                     {"html", summary.html.string()},
                     {"sample_shown", summary.sample_shown},
                     {"notes", summary.notes}};
    nlohmann::json images = nlohmann::json::array();
    for (const auto& p : summary.images) images.push_back(p.string());
    j["images"] = images;
    fmt::print("{}\n", j.dump(2));
    return k_exit_ok;
  }
  fmt::print("report: {}\n", summary.markdown.string());
  if (!summary.html.empty()) fmt::print("report: {}\n", summary.html.string());
  fmt::print("{} plots (PNG and SVG, each with its gnuplot script) in {}\n", summary.images.size(),
             summary.out_dir.string());
  for (const std::string& note : summary.notes) fmt::print("note: {}\n", note);
  return k_exit_ok;
}

int do_calibrate(CalibrateArgs& args) {
  args.options.dir = args.dir;
  args.options.run_point = exec::run_point;
  const CalibrationOutcome outcome = calibrate_study(args.options);
  if (args.json)
    fmt::print("{}", calibration_to_json(outcome));
  else
    fmt::print("{}", calibration_text(outcome));
  // A verification that was asked for and did not give measurements is a failed check.
  return args.options.verify && !outcome.verified ? k_exit_check_failed : k_exit_ok;
}

}  // namespace

void register_report_commands(CLI::App& app, CliState& state) {
  {
    auto args = std::make_shared<ReportArgs>();
    CLI::App* sub = app.add_subcommand("report", "Plots and report.md / report.html for a study");
    sub->add_option("dir", args->dir, "Study folder")->required();
    sub->add_option("-o,--out", args->out, "Output folder (default: DIR/report)");
    sub->add_option("--sample", args->sample,
                    "Sample shown in the pile / oedometer figures (default: the one closest to the target)");
    sub->add_flag("--no-html", args->no_html, "Write report.md only");
    sub->add_option("--width", args->width, "Image width [px]");
    sub->add_option("--height", args->height, "Image height [px]");
    sub->add_option("--font-size", args->font_size, "Font size [pt]");
    sub->add_flag("--json", args->json, "Machine-readable output");
    sub->callback([args, &state] { state.exit_code = do_report(*args); });
  }
  {
    auto args = std::make_shared<CalibrateArgs>();
    CLI::App* sub = app.add_subcommand("calibrate",
                                       "Parameters that best match measured values, optionally verified by a real run");
    sub->add_option("dir", args->dir, "Study folder")->required();
    sub->add_option("--target", args->options.targets,
                    "NAME=VALUE to match, e.g. angle=33.5 or settlement=0.5e-3,1.2e-3,1.9e-3 (default: the study's "
                    "target angle or measured settlements)");
    sub->add_option("--weight", args->options.weights, "NAME=W weight of a target (default 1)");
    sub->add_option("--model", args->options.model, "Metamodel for every target (default: the best Q² per target)");
    sub->add_flag("--verify", args->options.verify, "Run the real case at the optimum and compare");
    sub->add_option("--global", args->options.global, "NLopt global pass: direct-l, crs2, isres, mlsl-lds, none");
    sub->add_option("--local", args->options.local, "NLopt local pass: bobyqa, nelder-mead, sbplx, cobyla, none");
    sub->add_option("--global-evaluations", args->options.global_evaluations, "Budget of the global pass");
    sub->add_option("--local-evaluations", args->options.local_evaluations, "Budget of the local pass");
    sub->add_flag("--json", args->json, "Machine-readable output (the calibration.json document)");
    sub->callback([args, &state] { state.exit_code = do_calibrate(*args); });
  }
}

}  // namespace demsa::cli
