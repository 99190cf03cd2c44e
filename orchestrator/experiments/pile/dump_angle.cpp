#include "orchestrator/experiments/pile/dump_angle.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "postprocess/dump.hpp"

#include <fmt/core.h>

#include <stdexcept>

namespace demsa::experiments::pile {

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

namespace {

/// Takes the pile's pedestal and measurement settings from the case.json of the case that holds `dump` (the folder
/// given, or the dump's own folder; case_angle); the caller's choices win. Without a case.json the options stand,
/// defaults included, with a warning when the pedestal was not chosen.
void apply_case_settings(const DumpAngleRequest& request, DumpAngle& measured, long& base_particles) {
  const fs::path folder = measured.dump.parent_path().empty() ? fs::path(".") : measured.dump.parent_path();
  const fs::path file = folder / study::k_case_json;
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    if (!request.chosen.pedestal_radius || !request.chosen.pedestal_top) {
      const std::string message = fmt::format(
          "{}: no {} beside the dump: measured on the pedestal of the options (radius {} m, top at z = {} m); "
          "give PileAngleOptions.pedestal_radius and PileAngleOptions.pedestal_top if the pile stood on another",
          measured.dump.string(), study::k_case_json, measured.options.pedestal_radius, measured.options.pedestal_top);
      if (request.warn)
        request.warn(message);
      else
        util::log::warn("{}", message);
    }
    return;
  }
  ChosenAngleOptions chosen = request.chosen;
  chosen.options = measured.options;
  const CaseAngle angle = case_angle(read_case_json(folder), file, chosen);
  measured.options = angle.options;
  base_particles = angle.base_particles;
  try {
    measured.options.validate();
  } catch (const std::invalid_argument& e) {
    throw util::UserError(file.string(), 0, e.what());
  }
  measured.case_json = file.string();
}

}  // namespace

DumpAngle measure_dump_angle(const DumpAngleRequest& request) {
  DumpAngle measured;
  measured.options = request.chosen.options;
  measured.dump = final_dump_path(request.dump, k_final_dump);
  long base_particles = 0;
  apply_case_settings(request, measured, base_particles);
  const pp::Particles particles = without_base(pp::read_particles(measured.dump), base_particles);
  try {
    measured.result = pp::measure_pile_angle(particles, measured.options);
  } catch (const pp::InputError& e) {
    throw util::UserError(measured.dump.string(), 0, e.what());
  }
  return measured;
}

}  // namespace demsa::experiments::pile
