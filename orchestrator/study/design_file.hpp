#pragma once
// DIR/design.csv (folder.hpp's k_design_file), the study's samples for a reader outside demsa: its one writer.
//
//   sample,u_P1,...,u_Pd,P1,...,Pd     one row per sample: its number, unit-cube values, physical values (%.17g)
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"

#include <string>
#include <vector>

namespace demsa::study {

/// The text of DIR/design.csv for these samples.
std::string design_csv(const StudyConfig& config, const std::vector<SampleRow>& samples);

}  // namespace demsa::study
