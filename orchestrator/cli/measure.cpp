// `demsa measure CASE [--json]`: the observables of a finished case folder of any experiment, measured exactly as
// `demsa run` measures its cases (exec/measure.hpp: from the case's files and its case.json), under the names and
// units the study stores. `demsa measure FILE`: the same observables of a laboratory file (a photograph), measured
// by the experiment whose laboratory files have its extension (Experiment::measure_lab_file).
#include "orchestrator/exec/measure.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"

#include <fmt/core.h>

#include <memory>
#include <string>

namespace demsa::cli {

namespace {

struct MeasureArgs {
  std::string folder;
  bool json = false;
  std::string photograph;  ///< --photograph: a laboratory file to compare the case with
  std::string overlay;     ///< --overlay: where the two superimposed go
};

}  // namespace

void register_measure_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<MeasureArgs>();
  CLI::App* sub =
      app.add_subcommand("measure",
                         "The observables of a finished case folder, measured as its study measures them, or of a "
                         "laboratory file (a drum's photograph) measured the same way");
  sub->add_option("CASE", args->folder,
                  "A case folder (written by demsa run or demsa case, and run), or a laboratory file (.bmp, .png)")
      ->required()
      ->check(CLI::ExistingPath);
  sub->add_flag("--json", args->json, "Print them as JSON (observables and their units, by name)");
  sub->add_option("--photograph", args->photograph,
                  "A laboratory file of the same setup (a drum's photograph): print the area where it and the case "
                  "disagree about material and write the two superimposed")
      ->check(CLI::ExistingFile);
  sub->add_option("--overlay", args->overlay,
                  "With --photograph: the PNG of the two superimposed (default CASE/lab_overlay.png)")
      ->needs("--photograph");
  sub->callback([args, &state] {
    const exec::MeasureReport report = with_option_names({{"overlay", "--overlay"}}, [&] {
      return exec::measure_report({args->folder, args->photograph, args->overlay});
    });
    fmt::print("{}", args->json ? report.json : report.text);
    state.exit_code = 0;
  });
}

}  // namespace demsa::cli
