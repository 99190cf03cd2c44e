#include "orchestrator/exec/case_vtk.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "postprocess/dump.hpp"
#include "postprocess/vtk.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <exception>
#include <fstream>
#include <string>

namespace demsa::exec {

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

namespace {

void write(const fs::path& path, const std::string& text, std::vector<fs::path>& written) {
  util::write_file_atomically(path, text);
  written.push_back(path);
}

}  // namespace

std::vector<fs::path> write_case_vtk(const fs::path& case_dir, const fs::path& out_dir) {
  std::error_code ec;
  if (fs::is_directory(case_dir, ec) && !fs::exists(case_dir / study::k_case_json, ec))
    throw util::UserError(
        case_dir.string(), 0,
        fmt::format("not a case folder (no {}); give a dump file to convert its particles only", study::k_case_json));
  const nlohmann::json doc = experiments::read_case_json(case_dir);
  const experiments::Experiment& experiment = experiments::of_case(doc, case_dir / study::k_case_json);
  const fs::path dump = case_dir / std::string(experiment.final_dump);
  if (!fs::exists(dump, ec))
    throw util::UserError(
        case_dir.string(), 0,
        fmt::format("the case has no {} (not run yet, or it did not finish)", dump.filename().string()));
  // Everything is read and checked before the first file is written.
  pp::DumpReaderOptions options;
  options.required_columns = {"id", "type", "radius"};
  const pp::DumpFrame frame = pp::read_last_frame(dump, options);
  std::vector<std::pair<std::string, std::string>> files{{k_vtk_particles, pp::particles_vtp(frame)}};
  std::vector<std::string> stale;
  for (const experiments::CaseSurface& s : experiment.vtk_surfaces(case_dir, doc, frame)) {
    if (s.surface)
      files.emplace_back(s.name + ".vtp", pp::surface_vtp(*s.surface));
    else
      stale.push_back(s.name + ".vtp");
  }
  fs::create_directories(out_dir);
  std::vector<fs::path> written;
  for (const auto& [name, text] : files) write(out_dir / name, text, written);
  for (const std::string& name : stale) fs::remove(out_dir / name, ec);  // not one of an earlier state
  return written;
}

void write_dump_vtk(const fs::path& dump, const fs::path& out) {
  pp::DumpReaderOptions options;
  options.required_columns = {"id", "type", "radius"};
  const std::string text = pp::particles_vtp(pp::read_last_frame(dump, options));
  if (!out.parent_path().empty()) fs::create_directories(out.parent_path());
  util::write_file_atomically(out, text);
}

void write_case_vtk_or_warn(const fs::path& case_dir) {
  try {
    write_case_vtk(case_dir, case_dir / study::k_case_vtk_folder);
  } catch (const std::exception& e) {
    util::log::warn("{}: the case was measured, but its ParaView files were not written: {}", case_dir.string(),
                    e.what());
  }
}

}  // namespace demsa::exec
