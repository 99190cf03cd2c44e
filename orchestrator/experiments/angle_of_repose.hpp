#pragma once
// An angle of repose measured outside a study run (`demsa postprocess`, `demsa compare`) as its case measured it:
// what the caller chose, what an experiment's case.json gives (Experiment::case_angle), and the base layer the
// measurement leaves out.
#include "postprocess/dump.hpp"
#include "postprocess/pile_angle.hpp"

namespace demsa::experiments {

/// Angle options a caller chose itself (a command line's): each flagged one wins over what a case records.
struct ChosenAngleOptions {
  postprocess::PileAngleOptions options;  ///< the caller's values (the defaults where it chose none)
  bool pedestal_radius = false;           ///< options.pedestal_radius was chosen
  bool pedestal_top = false;              ///< options.pedestal_top was chosen (a base layer's top then does not count)
  bool directions = false;                ///< options.directions was chosen
  bool levels = false;                    ///< options.levels was chosen
  bool estimator = false;                 ///< options.estimator was chosen
};

/// A pile case's angle options with the caller's choices, and the particles of its base layer.
struct CaseAngle {
  postprocess::PileAngleOptions options;  ///< not validated: the caller's own choices are its to check
  long base_particles = 0;                ///< atoms 1..N are the base layer, left out of the measurement
};

/// The particles of `particles` but the base layer's (ids 1..base_particles; all of them when it is 0).
postprocess::Particles without_base(const postprocess::Particles& particles, long base_particles);

}  // namespace demsa::experiments
