#include "orchestrator/experiments/incline/incline.hpp"

#include "orchestrator/experiments/particle_sets.hpp"
#include "orchestrator/study/setting_row.hpp"

#include <fmt/core.h>

// The [incline] section of the study file: its rows, the rules between them, and its prose in
// docs/reference/study-file.md.
namespace demsa::experiments::incline {

using namespace demsa::study;

namespace {

void apply_preset(InclineSettings& s, const std::string& preset) {
  // Paper Table 2: the radii of particle sets 1 and 2 (the probes are few; their count stays).
  s.radii = preset_radii(preset);
  s.preset = preset;
}

#define INCLINE(member) \
  [](auto& c) -> auto& { return settings(c).member; }

}  // namespace

const InclineSettings& settings(const StudyConfig& config) { return config.experiment_settings.get<InclineSettings>(); }
InclineSettings& settings(StudyConfig& config) { return config.experiment_settings.get<InclineSettings>(); }

std::vector<Setting> incline_settings() {
  std::vector<Row> rows;
  const auto add = [&](Row& row) { rows.push_back(std::move(row)); };
  add(preset("incline", INCLINE(preset), {"set1", "set2"}, [](StudyConfig& c, const std::string& name) {
        apply_preset(settings(c), name);
      }).doc("`set1` or `set2`: the radii of the paper's particle sets (Table 2). Other keys override it"));
  radius_rows(rows, "incline", "incline.", INCLINE(radii));
  add(Row("incline", "rolling_probes")
          .integer(INCLINE(rolling_probes), between(1, true, 1000, true))
          .cases("incline.rolling_probes")
          .doc("free spheres: they roll once the tilt overcomes the rolling resistance (`cdt`: tan θ = μ_R,PW)"));
  add(Row("incline", "sliding_probes")
          .integer(INCLINE(sliding_probes), between(1, true, 1000, true))
          .cases("incline.sliding_probes")
          .doc("spheres whose rotation is locked (the DEM twin of a sled of glued particles): they slide once tan θ = "
               "μ_PW"));
  add(Row("incline", "lane_spacing")
          .number(INCLINE(lane_spacing), between(0, false, 1, true))
          .unit("m")
          .cases("incline.lane_spacing")
          .doc("each probe runs down its own lane, this far from the next; more than 2 `r_max`, so that no two probes "
               "ever touch"));
  add(Row("incline", "settle_time")
          .number(INCLINE(settle_time), between(0, false, 10, true))
          .unit("s")
          .cases("incline.settle_time")
          .doc("the probes settle on the level plate before the tilt begins"));
  add(Row("incline", "tilt_rate")
          .number(INCLINE(tilt_rate), between(0, false, 90, true))
          .unit("deg/s")
          .cases("incline.tilt_rate")
          .doc(
              "Ω: gravity turns at this rate in the plate's frame (a slow tilt); the measured onsets are corrected for "
              "the lag of a start from rest at this rate (docs/explanation/experiments.md)"));
  add(Row("incline", "max_angle")
          .number(INCLINE(max_angle), tilt_bounds())
          .unit("deg")
          .cases("incline.max_angle")
          .doc("the tilt stops here; a probe that has not moved by then gives no onset (more than half of a kind must "
               "move: a μ_PW of 1.9 slides at 62°)"));
  add(Row("incline", "record_angle")
          .number(INCLINE(record_angle), record_angle_bounds())
          .unit("deg")
          .cases("incline.record_angle")
          .doc("every probe is recorded every this much tilt (incline_probes.dump); onsets are interpolated between "
               "records"));
  add(Row("incline", "onset_distance")
          .number(INCLINE(onset_distance), onset_distance_bounds())
          .unit("m")
          .measurement("incline.onset_distance")
          .doc("a probe has started once it moved this far down the slope (`cdt` spheres creep up to 0.2 mm below "
               "their threshold at 5 deg/s: keep it well above)"));
  add(Row("incline", "speed_angle")
          .number(INCLINE(speed_angle), tilt_bounds())
          .unit("deg")
          .measurement("incline.speed_angle")
          .doc("the free probes' down-slope speed is read at this tilt (`roll_speed`, the observable of the `viscous` "
               "model, whose spheres roll at any tilt)"));
  add(Row("incline", "stop_distance")
          .number(INCLINE(stop_distance), between(0, false, 10, true))
          .unit("m")
          .cases("incline.stop_distance")
          .doc("a probe this far down the slope has left the test and is removed (counted, not lost); the plate is "
               "this long"));
  return finish_rows(rows);
}

#undef INCLINE

std::vector<SettingSection> incline_sections() {
  return {
      {"incline", "Defaults: the radii of the paper's particle set 1 (Table 2).",
       "Probe spheres rest on a flat plate of the wall material (a primitive plane, atom type 2), one per lane; "
       "after `settle_time` gravity turns at `tilt_rate` in the plate's frame, which for a slow tilt is the plate "
       "tilting (the centrifugal term is below 1e-4 g at 0.1 m from a real plate's axis at 5 deg/s). Observables: "
       "`roll_angle` and `slide_angle`, the medians over the free and the locked probes of the tilt at which a probe "
       "had moved `onset_distance` down the slope, less the lag of its start from rest (x = k g √(1 + μ²) Ω t³ / 6 "
       "with μ = tan θ_c, k = 5/7 rolling and 1 sliding). With `[contact] rolling_model = \"viscous\"` (no static "
       "rolling resistance: the free probes roll at once) `roll_speed`, their median speed at `speed_angle`, takes "
       "the place of `roll_angle`. docs/explanation/experiments.md has the measured onsets against atan(μ)."}};
}

void check_incline(const StudyConfig& config, const SectionCheck& at) {
  const InclineSettings& s = settings(config);
  check_radii(s.radii, at);
  if (!(s.lane_spacing > 2 * s.radii.r_max))
    at.fail("lane_spacing", fmt::format("{} m must exceed 2 r_max = {} m: neighbouring probes would touch",
                                        s.lane_spacing, 2 * s.radii.r_max));
  if (!(s.speed_angle < s.max_angle))
    at.fail("speed_angle", fmt::format("{} deg must lie below max_angle = {} deg", s.speed_angle, s.max_angle));
  if (!(s.record_angle < s.max_angle))
    at.fail("record_angle", fmt::format("{} deg must lie below max_angle = {} deg", s.record_angle, s.max_angle));
  if (!(s.onset_distance < s.stop_distance))
    at.fail("onset_distance",
            fmt::format("{} m must lie below stop_distance = {} m", s.onset_distance, s.stop_distance));
}

}  // namespace demsa::experiments::incline
