#include "orchestrator/exec/measure.hpp"

#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/parameters.hpp"
#include "postprocess/dump.hpp"
#include "postprocess/oedometer.hpp"
#include "postprocess/pile_angle.hpp"

namespace demsa::exec {

using namespace demsa::util;
using namespace demsa::study;

namespace fs = std::filesystem;

std::map<std::string, double> measure_case(const StudyConfig& config, const fs::path& folder) {
  std::map<std::string, double> values;
  if (config.experiment == Experiment::pile) {
    const postprocess::Particles particles = postprocess::read_particles(folder / k_pile_final_dump, 1);
    postprocess::PileAngleOptions options;
    options.pedestal_radius = config.pile.pedestal_radius;
    options.pedestal_top = config.pile.pedestal_height;
    options.directions = config.pile.directions;
    options.levels = config.pile.levels;
    options.target_angle = config.pile.target_angle;
    options.estimator = postprocess::angle_estimator_from_string(config.pile.angle_estimator);
    const postprocess::PileAngleResult result = postprocess::measure_pile_angle(particles, options);
    values[std::string(k_angle)] = result.angle_mean;
    values[std::string(k_pile_height)] = result.pile_height;
    values[std::string(k_angle_sd)] = result.angle_sd;
    values[std::string(k_particles_on_pedestal)] = static_cast<double>(result.particles_on_pedestal);
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
