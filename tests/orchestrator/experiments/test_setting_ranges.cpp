// The ranges of the experiments' settings (issue 45): a measurement setting that case.json records has one range,
// checked by its study-file row and by the measurement's reader; a draw-down fill that cannot fit its box is refused
// at its line.
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/drawdown/drawdown.hpp"
#include "orchestrator/experiments/incline/incline.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

namespace demsa {

using namespace demsa::study;
using namespace demsa::experiments;
namespace {

/// Section -> key -> TOML value text.
using StudyMap = std::map<std::string, std::map<std::string, std::string>>;

/// The study file of `values`, sections in the table's order.
std::string study_text(const StudyMap& values) {
  std::string text;
  for (const SettingSection& section : settings_table().sections()) {
    const auto it = values.find(section.name);
    if (it == values.end()) continue;
    text += "[" + section.name + "]\n";
    for (const auto& [key, value] : it->second) text += key + " = " + value + "\n";
  }
  return text;
}

StudyMap minimal_study() {
  return {{"study", {{"name", "\"s\""}, {"experiment", "\"pile\""}}},
          {"parameters", {{"E", "{ low = 1e8, high = 1e9, scale = \"log\" }"}}}};
}

TEST(SettingRanges, AMeasurementSettingHasOneRangeForTheStudyFileAndTheCaseReader) {
  // issue 45: [pile] drift_window = 1e-300 passed the study file (> 0) and the dry run; every case then ran, was
  // retried and failed at its measurement, whose reader of case.json asked for >= 1e-12. Each such setting now has
  // one range, its experiment's, that the row and the reader both check.
  struct Shared {
    std::string experiment, section, key, case_path;
    SettingBounds bounds;
    std::string refused;  ///< a value beyond the range, TOML
    double accepted;      ///< the value at its end
  };
  const std::vector<Shared> shared{
      {"pile", "pile", "drift_window", "pile.angle_measurement.drift_window_s", pile::drift_window_bounds(), "1e-300",
       1e-6},
      {"pile", "pile", "drift_limit", "pile.angle_measurement.drift_limit_deg_s", pile::drift_limit_bounds(), "1e-300",
       1e-9},
      {"incline", "incline", "onset_distance", "incline.onset_distance_m", incline::onset_distance_bounds(), "1e-300",
       1e-6},
      {"incline", "incline", "speed_angle", "incline.speed_angle_deg", incline::tilt_bounds(), "90", 89},
      {"incline", "incline", "max_angle", "incline.max_angle_deg", incline::tilt_bounds(), "90", 89},
      {"drawdown", "drawdown", "bin_width", "drawdown.measurement.bin_width_m", drawdown::bin_width_bounds(), "1e-300",
       1e-6},
  };
  for (const Shared& x : shared) {
    SCOPED_TRACE(x.section + "." + x.key);
    EXPECT_EQ(settings_table().find(x.section, x.key)->bounds.text(), x.bounds.text());
    StudyMap study = minimal_study();
    study["study"]["experiment"] = "\"" + x.experiment + "\"";
    study[x.section][x.key] = x.refused;
    try {
      parse_study(study_text(study), "study.toml");
      ADD_FAILURE() << x.refused << " accepted";
    } catch (const util::UserError& e) {
      EXPECT_NE(
          std::string(e.what()).find(fmt::format("[{}] {}: {}, got {}", x.section, x.key, x.bounds.rule(), x.refused)),
          std::string::npos)
          << e.what();
    }
    // The reader takes the end of the range the study file accepts, and refuses what it refuses.
    nlohmann::json doc;
    std::string pointer = "/" + x.case_path;
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    doc[nlohmann::json::json_pointer(pointer)] = x.accepted;
    EXPECT_EQ(case_number(doc, "case.json", x.case_path, x.bounds), x.accepted);
    doc[nlohmann::json::json_pointer(pointer)] = std::stod(x.refused);
    EXPECT_THROW(case_number(doc, "case.json", x.case_path, x.bounds), util::UserError);
  }
  // [incline] record_angle: each record is a LIGGGHTS run and a dump frame; near 0 it asked for millions of them.
  StudyMap study = minimal_study();
  study["study"]["experiment"] = "\"incline\"";
  study["incline"]["record_angle"] = "1e-6";
  EXPECT_THROW(parse_study(study_text(study), "study.toml"), util::UserError);
}

TEST(SettingRanges, ADrawdownBoxTooSmallForItsParticlesIsRefusedAtItsLine) {
  // issue 45: the case writer found out in every case, without the study file's name or line, and its count ("only N
  // of M particles fit") was the count when one particle jammed, not how many fit.
  StudyMap study = minimal_study();
  study["study"]["experiment"] = "\"drawdown\"";
  study["drawdown"]["particles"] = "20000";
  try {
    parse_study(study_text(study), "study.toml");
    ADD_FAILURE() << "20000 particles accepted";
  } catch (const util::UserError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("study.toml:7: [drawdown] particles: 20000 particles"), std::string::npos) << m;
    EXPECT_NE(m.find("placed one by one at random they jam near 0.38: lower particles to at most"), std::string::npos)
        << m;
  }
  study["drawdown"]["particles"] = "1850";  // the default fills about a tenth of the box
  EXPECT_NO_THROW(parse_study(study_text(study), "study.toml"));
}

}  // namespace
}  // namespace demsa
