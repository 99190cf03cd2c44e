// `demsa measure CASE [--json]`: the observables of a finished case folder of any experiment, measured exactly as
// `demsa run` measures its cases (exec/measure.hpp: from the case's files and its case.json), under the names and
// units the study stores. `demsa measure FILE`: the same observables of a laboratory file (a photograph), measured
// by the experiment whose laboratory files have its extension (Experiment::measure_lab_file).
#include "orchestrator/exec/measure.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/util/errors.hpp"

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
  std::string photograph;  ///< --photograph: a laboratory file to compare the case with
  std::string overlay;     ///< --overlay: where the two superimposed go
};

void run_compare_lab(const MeasureArgs& a) {
  const experiments::LabComparison c = exec::compare_case_with_lab_file(a.folder, a.photograph, a.overlay);
  if (a.json) {
    nlohmann::ordered_json j;
    j["case"] = a.folder;
    j["photograph"] = a.photograph;
    j["mismatch_m2"] = c.mismatch_m2;
    j["region"] = c.region;
    j["overlay"] = c.picture.string();
    fmt::print("{}\n", j.dump(2));
    return;
  }
  fmt::print("case {} against {}\n", a.folder, a.photograph);
  fmt::print("  mismatch area  {:.1f} mm² {} (where the case and the photograph disagree about material)\n",
             c.mismatch_m2 * 1e6, c.region);
  fmt::print("  superimposed   {}\n", c.picture.string());
}

void run_measure_lab(const MeasureArgs& a, const experiments::Experiment& e) {
  const experiments::LabMeasurement m = e.measure_lab_file(a.folder);
  if (a.json) {
    nlohmann::ordered_json j;
    j["file"] = a.folder;
    j["experiment"] = std::string(e.name);
    nlohmann::ordered_json values = nlohmann::ordered_json::object();
    nlohmann::ordered_json units = nlohmann::ordered_json::object();
    nlohmann::ordered_json uncertainty = nlohmann::ordered_json::object();
    for (const experiments::LabValue& v : m.values) {
      values[v.name] = v.value;
      units[v.name] = experiments::describe_observable(v.name).stored_unit;
      if (v.uncertainty) uncertainty[v.name] = *v.uncertainty;
    }
    j["observables"] = values;
    j["units"] = units;
    j["uncertainty"] = uncertainty;
    j["notes"] = m.notes;
    fmt::print("{}\n", j.dump(2));
    return;
  }
  fmt::print("file {} ({})\n", a.folder, e.name);
  std::size_t width = 0;
  for (const experiments::LabValue& v : m.values) width = std::max(width, v.name.size());
  for (const experiments::LabValue& v : m.values) {
    const study::Observable o = experiments::describe_observable(v.name);
    const std::string band = v.uncertainty ? fmt::format("± {:<10.3g}", *v.uncertainty) : std::string(12, ' ');
    fmt::print("  {:<{}}  {:>14.8g} {} {:<3}  {}\n", v.name, width, v.value, band, o.stored_unit, o.label);
  }
  for (const std::string& note : m.notes) fmt::print("  ({})\n", note);
}

void run_measure(const MeasureArgs& a) {
  if (!a.photograph.empty()) return run_compare_lab(a);
  if (std::filesystem::is_regular_file(a.folder)) {
    const experiments::Experiment* e = experiments::for_lab_file(a.folder);
    if (!e)
      throw util::UserError(
          fmt::format("{}: not a case folder, and no experiment measures files of this kind", a.folder));
    return run_measure_lab(a, *e);
  }
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
    run_measure(*args);
    state.exit_code = 0;
  });
}

}  // namespace demsa::cli
