#pragma once
// Two dumps, or the `*_final.dump` files of two case folders, compared (`demsa compare`): particles matched by id
// (postprocess/dump_compare.hpp) and, for an experiment that measures an angle of repose (Experiment::case_angle),
// the angle and h_P too, each case as it measures itself: on its own pedestal and without its base layer, whose
// particles leave the counts and the displacements too. A mistake in the options names the field
// ("CompareOptions.position_tolerance", "PileAngleOptions.pedestal_top"), which a command line writes as its option.
#include "orchestrator/experiments/angle_of_repose.hpp"
#include "postprocess/dump_compare.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace demsa::experiments {

struct CaseComparisonRequest {
  std::string a, b;  ///< two dump files or two case folders
  /// Tolerances; `pile` asks for the angle of every pair (automatic for the final dump of an experiment that
  /// measures one); pile_options hold the pedestal used where no case.json gives one.
  postprocess::CompareOptions options;
  bool pedestal_radius = false;  ///< options.pile_options.pedestal_radius chosen: it overrides the cases' pedestals
  bool pedestal_top = false;     ///< options.pile_options.pedestal_top chosen
};

/// One pair of dumps compared.
struct ComparedDumps {
  std::filesystem::path a, b;
  postprocess::DumpComparison result;
  CaseAngle angle_a, angle_b;  ///< the pedestals the angles were measured on, and the base layers left out
};

struct CaseComparison {
  std::vector<ComparedDumps> pairs;
  bool within_tolerance = true;  ///< every pair
};

/// Compares request.a with request.b. Throws util::UserError naming the file or folder on input it cannot compare.
CaseComparison compare_cases(const CaseComparisonRequest& request);

/// {"within_tolerance", "comparisons": [{"a", "b", "particles_a", ..., "pile": {...} or null}]}.
nlohmann::json case_comparison_json(const CaseComparison& comparison);
/// The comparison in words, pair by pair: particles, displacements, radius mismatches, the piles' angles, heights,
/// pedestals and base layers, and what lies beyond the tolerances.
std::string case_comparison_text(const CaseComparison& comparison);

}  // namespace demsa::experiments
