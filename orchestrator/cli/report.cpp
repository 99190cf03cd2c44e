// `demsa report` (docs/reference/command-line.md): plots and report.md / report.html for a study.
#include "orchestrator/report/report.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <memory>
#include <string>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::report;

namespace {

struct ReportArgs {
  std::string dir;
  std::string out;
  int sample = -1;
  bool no_html = false;
  std::string photograph;
  int width = 960;
  int height = 640;
  int font_size = 13;
  bool json = false;
};

int do_report(const ReportArgs& args) {
  ReportOptions options;
  options.dir = args.dir;
  options.out = args.out;
  options.sample = args.sample;
  options.html = !args.no_html;
  options.lab_file = args.photograph;
  options.plot.width = args.width;
  options.plot.height = args.height;
  options.plot.font_size = args.font_size;
  // Not while a `demsa run` holds the study: the report would describe the samples done so far as the study.
  const auto lock = study::hold_study_for_results(options.dir);
  const ReportSummary summary = with_option_names({{"sample", "--sample"}, {"lab_file", "--photograph"}},
                                                  [&] { return write_study_report(options); });
  fmt::print("{}", args.json ? report_summary_json(summary).dump(2) + "\n" : report_summary_text(summary));
  return k_exit_ok;
}

}  // namespace

void register_report_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<ReportArgs>();
  CLI::App* sub = app.add_subcommand("report", "Plots and report.md / report.html for a study");
  sub->add_option("dir", args->dir, "Study folder")->required();
  sub->add_option("-o,--out", args->out, "Output folder (default: DIR/report)");
  sub->add_option("--sample", args->sample,
                  "Sample shown in the pile / oedometer figures (default: the one closest to the target)");
  sub->add_flag("--no-html", args->no_html, "Write report.md only");
  sub->add_option("--photograph", args->photograph,
                  "A laboratory file of the study's setup (a drum's photograph): the case shown superimposed on it, "
                  "with their mismatch area")
      ->check(CLI::ExistingFile);
  sub->add_option("--width", args->width, "Image width [px]");
  sub->add_option("--height", args->height, "Image height [px]");
  sub->add_option("--font-size", args->font_size, "Font size [pt]");
  sub->add_flag("--json", args->json, "Machine-readable output");
  sub->callback([args, &state] { state.exit_code = do_report(*args); });
}

}  // namespace demsa::cli
