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

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
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

/// `name=value` items (comma separated, possibly over several --set options).
std::vector<std::pair<std::string, double>> parse_sets(const std::vector<std::string>& sets) {
  std::vector<std::pair<std::string, double>> out;
  for (const std::string& arg : sets) {
    std::size_t start = 0;
    while (start <= arg.size()) {
      const std::size_t comma = arg.find(',', start);
      const std::string item = arg.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      start = comma == std::string::npos ? arg.size() + 1 : comma + 1;
      if (item.empty()) continue;
      const std::size_t eq = item.find('=');
      if (eq == std::string::npos || eq == 0) throw UserError(fmt::format("--set: '{}' is not name=value", item));
      const std::string name = item.substr(0, eq), text = item.substr(eq + 1);
      char* end = nullptr;
      const double value = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !std::isfinite(value))
        throw UserError(fmt::format("--set: {}: '{}' is not a number", name, text));
      // A name given twice would silently take its last value.
      for (const auto& [given, first] : out)
        if (given == name)
          throw UserError(fmt::format("--set: {} is given twice ({}={} and {}={}); give each parameter once", name,
                                      name, first, name, text));
      out.emplace_back(name, value);
    }
  }
  return out;
}

void run_case(const CaseOptions& o, CliState& state) {
  exec::HandCaseOptions options;
  options.study = o.study;
  if (o.sample >= 0) options.sample = o.sample;
  options.dir = o.dir;
  if (o.sample < 0) options.values = parse_sets(o.sets);
  options.output = o.output;
  options.overwrite = o.overwrite;
  const exec::HandCase written =
      with_option_names({{"sample", "--sample"}}, [&] { return exec::write_hand_case(options); });
  const cases::CaseSummary& summary = written.summary;
  if (o.json)
    fmt::print("{}\n", exec::hand_case_json(written).dump(2));
  else
    fmt::print("wrote {} ({} particles, dt = {:.4g} s = {:.3f} T_R); run it with: cd {} && ./run.sh\n",
               summary.dir.string(), summary.particles, summary.dt, summary.dt / summary.rayleigh_time,
               summary.dir.string());
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
