// `demsa case`: one LIGGGHTS case folder, runnable by hand; and the hidden commands of the experiments' in-process
// drivers (`demsa drive-oedometer`, which run.sh of a trial-step oedometer case starts under mpirun).
#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/exec/liggghts_locator.hpp"
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/process.hpp"
#include "orchestrator/util/signals.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::cases;
using namespace demsa::exec;

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

/// "0-11, 1000001-1000002, 1001001": sorted ids, consecutive runs joined.
std::string id_ranges(std::vector<int> ids) {
  std::sort(ids.begin(), ids.end());
  std::string out;
  for (std::size_t i = 0; i < ids.size();) {
    std::size_t j = i;
    while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1) ++j;
    out += (out.empty() ? "" : ", ") + (j == i ? std::to_string(ids[i]) : fmt::format("{}-{}", ids[i], ids[j]));
    i = j + 1;
  }
  return out.empty() ? "none" : out;
}

/// The case of id `id` as `demsa run` writes it: a sample of the study folder's store (the design with what
/// `demsa extend` and `demsa refine` added, and the replicate cases, ids as `demsa status` prints them), or, before
/// the study has a folder, of the design and replicates drawn from the study file.
CaseRequest request_for_sample(const StudyConfig& config, int id, const std::filesystem::path& dir) {
  std::vector<SampleRow> samples;
  std::vector<ReplicateRow> replicates;
  std::string source;
  if (std::filesystem::exists(dir / k_store_file)) {
    const Store store = Store::open_read_only((dir / k_store_file).string());
    samples = store.samples();
    replicates = store.replicates();
    source = fmt::format("study folder {}", dir.string());
  } else {
    // The study's design, drawn again from its seed exactly as `demsa run` draws it.
    samples = draw_design(config);
    replicates = replicate_rows(config, samples);
    source = fmt::format("{} (no study folder {} yet)", config.file.string(), dir.string());
  }
  for (const SampleRow& s : samples)
    if (s.sample == id) return request_from_unit_point(config, id, s.unit);
  for (const ReplicateRow& r : replicates)
    if (r.sample == id) {
      CaseRequest request = request_from_unit_point(config, id, r.unit);
      request.replicate_point = r.point;
      request.replicate_repeat = r.repeat;
      request.assembly_seed = r.seed;
      return request;
    }
  std::vector<int> ids;
  for (const SampleRow& s : samples) ids.push_back(s.sample);
  std::string message = fmt::format("--sample {}: no such case in {}: design samples {}", id, source, id_ranges(ids));
  if (!replicates.empty()) {
    ids.clear();
    for (const ReplicateRow& r : replicates) ids.push_back(r.sample);
    message += fmt::format("; replicate cases {}", id_ranges(ids));
  }
  throw UserError(message);
}

void run_case(const CaseOptions& o, CliState& state) {
  StudyConfig config = experiments::load_study(o.study);
  // run.sh names the LIGGGHTS found for the study's rolling model; one without it is a warning here (the case may
  // run elsewhere) and refused by `demsa run`.
  resolve_liggghts(config, false);
  CaseRequest request;
  if (o.sample >= 0) {
    request =
        request_for_sample(config, o.sample, o.dir.empty() ? default_study_dir(o.study) : std::filesystem::path(o.dir));
  } else {
    request = request_from_values(config, parse_sets(o.sets));
  }
  request.demsa_executable = util::self_executable();
  if (find_on_path(config.run.liggghts)) request.liggghts_version = query_liggghts_at(config.run.liggghts).version;
  const std::filesystem::path dir =
      o.output.empty() ? std::filesystem::path(o.sample >= 0 ? fmt::format("case-{:06d}", o.sample) : "case-set")
                       : std::filesystem::path(o.output);
  const CaseSummary summary =
      write_case(config, request, dir, o.overwrite ? ExistingCaseFiles::remove : ExistingCaseFiles::refuse);
  if (o.json) {
    nlohmann::ordered_json j{
        {"dir", summary.dir.string()},
        {"sample", request.sample >= 0 ? nlohmann::ordered_json(request.sample) : nlohmann::ordered_json(nullptr)},
        {"particles", summary.particles},
        {"dt", summary.dt},
        {"rayleigh_time", summary.rayleigh_time},
        {"dt_source", summary.dt_source},
        {"final_dump", summary.final_dump}};
    fmt::print("{}\n", j.dump(2));
  } else {
    fmt::print("wrote {} ({} particles, dt = {:.4g} s = {:.3f} T_R); run it with: cd {} && ./run.sh\n",
               summary.dir.string(), summary.particles, summary.dt, summary.dt / summary.rayleigh_time,
               summary.dir.string());
  }
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
