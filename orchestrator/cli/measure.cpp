// `demsa measure CASE [--json]`: the observables of a finished case folder of any experiment, measured exactly as
// `demsa run` measures its cases (exec/measure.hpp: from the case's files and its case.json), under the names and
// units the study stores.
#include "orchestrator/exec/measure.hpp"
#include "orchestrator/cli/commands.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>

namespace demsa::cli {

namespace {

struct MeasureArgs {
  std::string folder;
  bool json = false;
};

void run_measure(const MeasureArgs& a) {
  const exec::CaseMeasurement m = exec::measure_case_described(a.folder);
  if (a.json) {
    nlohmann::ordered_json j;
    j["case"] = a.folder;
    j["experiment"] = m.experiment;
    nlohmann::ordered_json values = nlohmann::ordered_json::object();
    nlohmann::ordered_json units = nlohmann::ordered_json::object();
    for (const exec::MeasuredValue& v : m.values) {
      values[v.observable.name] = v.value;
      units[v.observable.name] = v.observable.stored_unit;
    }
    j["observables"] = values;
    j["units"] = units;
    fmt::print("{}\n", j.dump(2));
    return;
  }
  fmt::print("case {} ({})\n", a.folder, m.experiment);
  std::size_t width = 0;
  for (const exec::MeasuredValue& v : m.values) width = std::max(width, v.observable.name.size());
  for (const exec::MeasuredValue& v : m.values)
    fmt::print("  {:<{}}  {:>14.8g} {:<3}  {}\n", v.observable.name, width, v.value, v.observable.stored_unit,
               v.observable.label);
}

}  // namespace

void register_measure_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<MeasureArgs>();
  CLI::App* sub =
      app.add_subcommand("measure", "The observables of a finished case folder, measured as its study measures them");
  sub->add_option("CASE", args->folder, "A case folder (written by demsa run or demsa case, and run)")
      ->required()
      ->check(CLI::ExistingDirectory);
  sub->add_flag("--json", args->json, "Print them as JSON (observables and their units, by name)");
  sub->callback([args, &state] {
    run_measure(*args);
    state.exit_code = 0;
  });
}

}  // namespace demsa::cli
