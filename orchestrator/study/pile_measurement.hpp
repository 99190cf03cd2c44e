#pragma once
// A study's pile measurement ([pile] pedestal and angle settings) as the options of postprocess's angle of repose:
// the one place `demsa run` (exec/measure) and the report (report/pile_section) take them from.
#include "orchestrator/study/config.hpp"
#include "postprocess/pile_angle.hpp"

namespace demsa::study {

/// The pedestal (pedestal_radius, its top at pedestal_height), directions, levels, target angle and estimator of
/// `pile`; the band of levels is left unset, so each estimator measures on its own (postprocess::PileAngleOptions).
postprocess::PileAngleOptions pile_angle_options(const PileSettings& pile);

}  // namespace demsa::study
