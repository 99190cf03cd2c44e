#pragma once
// The angle of repose of one pile dump outside a study run (`demsa postprocess pile`; paper §3.3): a dump given
// directly or a case folder's pile_final.dump, measured with the pedestal and the measurement settings its case.json
// records (case_angle.hpp) as `demsa run` measured it, but for the options the caller chose itself. A mistake in the
// options names the field ("PileAngleOptions.levels"), which a command line writes as its own option.
#include "orchestrator/experiments/pile/case_angle.hpp"
#include "postprocess/pile_angle.hpp"

#include <filesystem>
#include <functional>
#include <string>

namespace demsa::experiments::pile {

struct DumpAngleRequest {
  std::string dump;           ///< the dump, or a case folder holding pile_final.dump
  ChosenAngleOptions chosen;  ///< the caller's options and which of them it chose
  /// Where the warnings go (a pile measured without case.json on the options' pedestal); empty: util::log::warn.
  std::function<void(const std::string&)> warn;
};

struct DumpAngle {
  std::filesystem::path dump;             ///< the dump measured
  std::string case_json;                  ///< the case.json whose settings it took, "" when there is none
  postprocess::PileAngleOptions options;  ///< as measured
  postprocess::PileAngleResult result;
};

/// Measures the pile of `request.dump`. Throws util::UserError naming the dump or case.json on input it cannot
/// measure.
DumpAngle measure_dump_angle(const DumpAngleRequest& request);

}  // namespace demsa::experiments::pile
