#pragma once
// The settlements of one oedometer case outside a study run (`demsa postprocess oedometer`; paper §4), from its plate
// files (plate_states.txt and/or plate_history.txt, or a case folder holding them) and, for the void ratio, the solid
// volume of a dump. A mistake in the options names the field ("OedometerOptions.box_side"), which a command line
// writes as its own option.
#include "postprocess/oedometer.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demsa::experiments::oedometer {

struct PlateFilesRequest {
  std::vector<std::string> files;         ///< plate_states.txt, plate_history.txt, or case folders
  std::string dump;                       ///< "": the case folder's final dump, if any
  postprocess::OedometerOptions options;  ///< measured_settlements included; solid_volume from the dump
  double load_tolerance = 0.03;           ///< without plate_states.txt: |force - load| that counts as converged [N]
};

struct PlateFiles {
  std::optional<std::filesystem::path> states_file, history_file, dump_file;
  std::string source;  ///< the file the load states came from
  postprocess::OedometerResult result;
};

/// Measures the plate files of `request`. Throws util::UserError naming the file on input it cannot measure, and
/// on options that fail OedometerOptions::validate ("OedometerOptions.box_side ...").
PlateFiles measure_plate_files(const PlateFilesRequest& request);

}  // namespace demsa::experiments::oedometer
