#include "orchestrator/study/pile_measurement.hpp"

namespace demsa::study {

postprocess::PileAngleOptions pile_angle_options(const PileSettings& pile) {
  postprocess::PileAngleOptions options;
  options.pedestal_radius = pile.pedestal_radius;
  options.pedestal_top = pile.pedestal_height;  // the ground is at z = 0
  options.directions = pile.directions;
  options.levels = pile.levels;
  options.target_angle = pile.target_angle;
  // [pile] angle_estimator holds one of postprocess::angle_estimator_names() (a choice of study/settings.cpp).
  options.estimator = postprocess::angle_estimator_from_string(pile.angle_estimator);
  return options;
}

}  // namespace demsa::study
