#include "orchestrator/exec/hand_case.hpp"

#include "orchestrator/exec/liggghts_locator.hpp"
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/process.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace demsa::exec {

using namespace demsa::study;
using namespace demsa::cases;

namespace {

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
/// `demsa extend` and `demsa refine` added, and the replicate cases), or, before the study has a folder, of the design
/// and replicates drawn from the study file.
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
  std::string message =
      fmt::format("HandCaseOptions.sample {}: no such case in {}: design samples {}", id, source, id_ranges(ids));
  if (!replicates.empty()) {
    ids.clear();
    for (const ReplicateRow& r : replicates) ids.push_back(r.sample);
    message += fmt::format("; replicate cases {}", id_ranges(ids));
  }
  throw util::UserError(message);
}

}  // namespace

HandCase write_hand_case(const HandCaseOptions& o) {
  StudyConfig config = experiments::load_study(o.study);
  resolve_liggghts(config, false);
  CaseRequest request;
  if (o.sample)
    request = request_for_sample(config, *o.sample, o.dir.empty() ? default_study_dir(o.study) : o.dir);
  else
    try {
      request = request_from_values(config, o.values);
    } catch (const util::UserError& e) {
      throw util::UserError(fmt::format("HandCaseOptions.values: {}", e.what()));
    }
  request.demsa_executable = util::self_executable();
  if (find_on_path(config.run.liggghts)) request.liggghts_version = query_liggghts_at(config.run.liggghts).version;
  const std::filesystem::path dir =
      o.output.empty() ? std::filesystem::path(o.sample ? fmt::format("case-{:06d}", *o.sample) : "case-set")
                       : o.output;
  return {write_case(config, request, dir, o.overwrite ? ExistingCaseFiles::remove : ExistingCaseFiles::refuse),
          o.sample};
}

std::vector<std::pair<std::string, double>> parse_parameter_values(const std::vector<std::string>& texts) {
  std::vector<std::pair<std::string, double>> out;
  for (const std::string& text : texts) {
    for (const std::string& item : util::split(text, ',')) {
      if (item.empty()) continue;
      const std::size_t eq = item.find('=');
      if (eq == std::string::npos || eq == 0)
        throw util::UserError(fmt::format("HandCaseOptions.values: '{}' is not name=value", item));
      const std::string name = item.substr(0, eq), value_text = item.substr(eq + 1);
      char* end = nullptr;
      const double value = std::strtod(value_text.c_str(), &end);
      if (value_text.empty() || *end != '\0' || !std::isfinite(value))
        throw util::UserError(fmt::format("HandCaseOptions.values: {}: '{}' is not a number", name, value_text));
      // A name given twice would silently take its last value.
      for (const auto& [given, first] : out)
        if (given == name)
          throw util::UserError(
              fmt::format("HandCaseOptions.values: {} is given twice ({}={} and {}={}); give each parameter once", name,
                          name, first, name, value_text));
      out.emplace_back(name, value);
    }
  }
  return out;
}

std::string hand_case_text(const HandCase& written) {
  const CaseSummary& summary = written.summary;
  return fmt::format("wrote {} ({} particles, dt = {:.4g} s = {:.3f} T_R); run it with: cd {} && ./run.sh\n",
                     summary.dir.string(), summary.particles, summary.dt, summary.dt / summary.rayleigh_time,
                     summary.dir.string());
}

nlohmann::ordered_json hand_case_json(const HandCase& written) {
  const CaseSummary& summary = written.summary;
  return {{"dir", summary.dir.string()},
          {"sample", written.sample ? nlohmann::ordered_json(*written.sample) : nlohmann::ordered_json(nullptr)},
          {"particles", summary.particles},
          {"dt", summary.dt},
          {"rayleigh_time", summary.rayleigh_time},
          {"dt_source", summary.dt_source},
          {"final_dump", summary.final_dump}};
}

}  // namespace demsa::exec
