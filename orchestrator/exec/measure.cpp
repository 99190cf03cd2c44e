#include "orchestrator/exec/measure.hpp"

#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/observables.hpp"
#include "orchestrator/study/parameters.hpp"
#include "orchestrator/study/pile_measurement.hpp"
#include "postprocess/dump.hpp"
#include "postprocess/error.hpp"
#include "postprocess/oedometer.hpp"
#include "postprocess/pile_angle.hpp"

#include <fmt/core.h>

#include <fstream>
#include <sstream>

namespace demsa::exec {

using namespace demsa::util;
using namespace demsa::study;

namespace fs = std::filesystem;

std::optional<PileSettling> read_pile_settling(const fs::path& folder) {
  const fs::path file = folder / k_pile_settling;
  std::ifstream in(file);
  if (!in) return std::nullopt;
  std::map<std::string, double> values;
  std::string line;
  long number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream words(line);
    std::string key;
    std::string value;
    std::string extra;
    if (!(words >> key)) continue;
    double v = 0;
    if (!(words >> value) || (words >> extra) || !(std::istringstream(value) >> v))
      throw postprocess::ParseError(file.string(), number, fmt::format("expected 'key number', got '{}'", line));
    values[key] = v;
  }
  const auto get = [&](const char* key) {
    const auto it = values.find(key);
    if (it == values.end()) throw postprocess::ParseError(file.string(), 0, fmt::format("no '{}' line", key));
    return it->second;
  };
  PileSettling s;
  s.criterion = get("criterion") > 0;
  s.settled = s.criterion && get("settled") > 0;
  s.end_step = static_cast<long>(get("end_step"));
  s.fastest = get("fastest_on_pedestal");
  s.speed_limit = get("speed_limit");
  s.on_pedestal = static_cast<long>(get("on_pedestal"));
  s.fast_on_pedestal = static_cast<long>(get("fast_on_pedestal"));
  s.removed = static_cast<long>(get("removed"));
  return s;
}

std::map<std::string, double> measure_case(const StudyConfig& config, const fs::path& folder) {
  std::map<std::string, double> values;
  if (config.experiment == Experiment::pile) {
    const postprocess::Particles particles = postprocess::read_particles(folder / k_pile_final_dump, 1);
    const postprocess::PileAngleResult result =
        postprocess::measure_pile_angle(particles, pile_angle_options(config.pile));
    values[std::string(k_angle)] = result.angle_mean;
    values[std::string(k_pile_height)] = result.pile_height;
    values[std::string(k_angle_sd)] = result.angle_sd;
    values[std::string(k_particles_on_pedestal)] = static_cast<double>(result.particles_on_pedestal);
    if (const std::optional<PileSettling> settling = read_pile_settling(folder)) {
      if (settling->criterion) values[std::string(k_settled)] = settling->settled ? 1.0 : 0.0;
      values[std::string(k_removed_off_pedestal)] = static_cast<double>(settling->removed);
    }
    return values;
  }
  const std::vector<postprocess::PlateState> states = postprocess::read_plate_states(folder / k_plate_states);
  postprocess::OedometerOptions options;
  options.box_side = config.oedometer.box_side;
  options.measured_settlements = config.oedometer.measured_settlements;
  const postprocess::OedometerResult result = postprocess::measure_oedometer(states, options);
  for (std::size_t i = 0; i < result.settlements.size(); ++i) values[settlement_name(i + 1)] = result.settlements[i];
  if (result.settlement_error) values[std::string(k_settlement_error)] = *result.settlement_error;
  return values;
}

}  // namespace demsa::exec
