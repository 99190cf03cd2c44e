#include "orchestrator/experiments/oedometer/plate_files.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/oedometer/oedometer.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/dump.hpp"

#include <cstdio>
#include <stdexcept>

namespace demsa::experiments::oedometer {

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

namespace {

/// True when the file's column header is the `# step ...` of a plate history.
bool looks_like_history(const fs::path& path) {
  const std::string name = path.filename().string();
  if (name.find("history") != std::string::npos) return true;
  if (name.find("states") != std::string::npos) return false;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return false;
  char line[4096];
  bool history = false;
  while (std::fgets(line, sizeof line, f) != nullptr) {
    std::string s(line);
    if (s.rfind("#", 0) != 0) break;
    const std::size_t k = s.find_first_not_of("# \t");
    if (k != std::string::npos && s.compare(k, 5, "step ") == 0) history = true;
  }
  std::fclose(f);
  return history;
}

}  // namespace

PlateFiles measure_plate_files(const PlateFilesRequest& request) {
  PlateFiles out;
  if (!request.dump.empty()) out.dump_file = final_dump_path(request.dump, k_final_dump);
  for (const std::string& arg : request.files) {
    const fs::path p(arg);
    std::error_code ec;
    if (fs::is_directory(p, ec)) {  // a case folder: its plate files and final dump
      if (fs::exists(p / k_plate_states, ec)) out.states_file = p / k_plate_states;
      if (fs::exists(p / k_plate_history, ec)) out.history_file = p / k_plate_history;
      if (!out.dump_file && fs::exists(p / k_final_dump, ec)) out.dump_file = p / k_final_dump;
      if (!out.states_file && !out.history_file)
        throw util::UserError(arg, 0, "case folder has neither plate_states.txt nor plate_history.txt");
      continue;
    }
    if (!fs::exists(p, ec)) throw util::UserError(arg, 0, "no such file or folder");
    (looks_like_history(p) ? out.history_file : out.states_file) = p;
  }
  std::optional<pp::PlateHistory> history;
  if (out.history_file) history = pp::read_plate_history(*out.history_file);
  std::vector<pp::PlateState> states;
  if (out.states_file)
    states = pp::read_plate_states(*out.states_file);
  else
    states = pp::states_from_history(*history, request.load_tolerance);

  pp::OedometerOptions options = request.options;
  if (out.dump_file) options.solid_volume = pp::solid_volume(pp::read_particles(*out.dump_file, 1));
  try {
    options.validate();
  } catch (const std::invalid_argument& e) {
    throw util::UserError(e.what());
  }
  out.source = (out.states_file ? *out.states_file : *out.history_file).string();
  try {
    out.result = pp::measure_oedometer(states, options, std::move(history));
  } catch (const pp::InputError& e) {
    throw util::UserError(out.source, 0, e.what());
  }
  return out;
}

}  // namespace demsa::experiments::oedometer
