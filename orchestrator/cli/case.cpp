// `demsa case`: one LIGGGHTS case folder, runnable by hand; and the hidden commands of the experiments' in-process
// drivers (`demsa drive-oedometer`, which run.sh of a trial-step oedometer case starts under mpirun).
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/exec/hand_case.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/signals.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace demsa::cli {

using namespace demsa::util;

namespace {

struct CaseOptions {
  std::string study;              ///< the study file
  int sample = -1;                ///< --sample ID: a case id of the study (design, extension, refinement, replicate)
  std::string dir;                ///< --dir: the study folder (default: the study file's name without .toml)
  std::vector<std::string> sets;  ///< --set name=value,...
  std::string output;             ///< -o DIR
  bool overwrite = false;         ///< --overwrite: empty a non-empty DIR first
  bool json = false;
};

void run_case(const CaseOptions& o, CliState& state) {
  exec::HandCaseOptions options;
  options.study = o.study;
  if (o.sample >= 0) options.sample = o.sample;
  options.dir = o.dir;
  options.output = o.output;
  options.overwrite = o.overwrite;
  const OptionNames names{{"sample", "--sample"}, {"values", "--set"}};
  const exec::HandCase written = with_option_names(names, [&] {
    if (o.sample < 0) options.values = exec::parse_parameter_values(o.sets);
    return exec::write_hand_case(options);
  });
  fmt::print("{}", o.json ? exec::hand_case_json(written).dump(2) + "\n" : exec::hand_case_text(written));
  state.exit_code = k_exit_ok;
}

}  // namespace

void register_case_commands(CLI::App& app, CliState& state) {
  auto options = std::make_shared<CaseOptions>();
  CLI::App* sub = app.add_subcommand(
      "case", "Write one LIGGGHTS case folder of a study, runnable by hand with `cd DIR && ./run.sh`");
  sub->add_option("study", options->study, "Study file (TOML)")->required()->check(CLI::ExistingFile);
  CLI::Option* sample =
      sub->add_option("--sample", options->sample,
                      "Case ID of the study: a design sample (0-based), one added by `demsa extend` or `demsa "
                      "refine`, or a replicate case (ids as `demsa status` prints them)")
          ->check(non_negative_number());
  CLI::Option* dir = sub->add_option("--dir", options->dir,
                                     "Study folder whose samples --sample reads (default: the study file's name "
                                     "without .toml; without a folder, the design drawn from the study file)");
  dir->needs(sample);
  CLI::Option* set = sub->add_option("--set", options->sets,
                                     "Parameter values name=value[,name=value...]; varied parameters not named take "
                                     "the middle of their range");
  sample->excludes(set);
  sub->add_option("-o,--out", options->output, "Case folder (default case-<K>); it must be empty or new");
  add_deprecated_option(sub, "--output", "-o/--out", options->output);
  sub->add_flag("--overwrite", options->overwrite,
                "Empty the case folder first when it holds files (e.g. the outputs of an earlier ./run.sh); only a "
                "folder that holds a case.json is emptied");
  sub->add_flag("--json", options->json, "Print what was written as JSON");
  sub->callback([options, sample, set, &state] {
    if (sample->count() == 0 && set->count() == 0) throw UserError("demsa case: give --sample K or --set name=value");
    // Drawing and writing a large case takes seconds: a signal stops it between particles and removes the folder.
    util::StopFlag::install();
    run_case(*options, state);
  });

  for (const experiments::Experiment* e : experiments::all())
    for (const experiments::Driver& d : e->drivers()) {
      auto driver_dir = std::make_shared<std::string>();
      CLI::App* driver = app.add_subcommand(std::string(d.command), std::string(d.description));
      driver->group("");  // internal: run.sh calls it under mpirun
      driver->add_option("case_dir", *driver_dir, "Case folder")->required()->check(CLI::ExistingDirectory);
      driver->callback([driver_dir, run = d.run, &state] { state.exit_code = run(*driver_dir); });
    }
}

}  // namespace demsa::cli
