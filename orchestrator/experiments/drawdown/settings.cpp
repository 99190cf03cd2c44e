#include "orchestrator/experiments/drawdown/drawdown.hpp"

#include "orchestrator/experiments/particle_sets.hpp"
#include "orchestrator/study/setting_row.hpp"

#include <fmt/core.h>

#include <cmath>
#include <numbers>
#include <vector>

// The [drawdown] section of the study file: its rows, the rules between them, and its prose in
// docs/reference/study-file.md.
namespace demsa::experiments::drawdown {

using namespace demsa::study;

namespace {

void apply_preset(DrawdownSettings& s, const std::string& preset) {
  // Paper Table 2: the radii of particle sets 1 and 2.
  s.radii = preset_radii(preset);
  s.preset = preset;
}

#define DRAWDOWN(member) \
  [](auto& c) -> auto& { return settings(c).member; }

}  // namespace

const DrawdownSettings& settings(const StudyConfig& config) {
  return config.experiment_settings.get<DrawdownSettings>();
}
DrawdownSettings& settings(StudyConfig& config) { return config.experiment_settings.get<DrawdownSettings>(); }

std::vector<Setting> drawdown_settings() {
  std::vector<Row> rows;
  const auto add = [&](Row& row) { rows.push_back(std::move(row)); };
  const auto length = [&](const char* key, auto field, const char* doc) {
    add(Row("drawdown", key)
            .number(field, between(0, false, 10, true))
            .unit("m")
            .cases(fmt::format("drawdown.{}", key))
            .doc(doc));
  };
  const auto time = [&](const char* key, auto field, const char* doc) {
    add(Row("drawdown", key)
            .number(field, between(0, false, 100, true))
            .unit("s")
            .cases(fmt::format("drawdown.{}", key))
            .doc(doc));
  };
  add(preset("drawdown", DRAWDOWN(preset), {"set1", "set2"}, [](StudyConfig& c, const std::string& name) {
        apply_preset(settings(c), name);
      }).doc("`set1` or `set2`: the radii of the paper's particle sets (Table 2). Other keys override it"));
  add(Row("drawdown", "particles")
          .integer(DRAWDOWN(particles), between(1, true, k_max_particles, true,
                                                "the case writer holds every particle, and the text of its data "
                                                "file, in memory"))
          .cases("drawdown.particles")
          .doc("the loose fill"));
  radius_rows(rows, "drawdown", "drawdown.", DRAWDOWN(radii));
  length("slot_width", DRAWDOWN(slot_width),
         "the slot across the floor, along y (at least 6 mean diameters, or the "
         "outlet arches)");
  length("side_width", DRAWDOWN(side_width), "floor from the slot's edge to each side wall (the slope's run)");
  length("depth", DRAWDOWN(depth),
         "the box's length along the slot; the box is periodic along it (no front and back "
         "walls)");
  length("fill_height", DRAWDOWN(fill_height),
         "the loose fill is placed up to this height above the floor (it "
         "settles to about half)");
  add(Row("drawdown", "floor")
          .choice(DRAWDOWN(floor),
                  std::vector<std::pair<std::string, DrawdownFloor>>{{"wall", DrawdownFloor::wall},
                                                                     {"particles", DrawdownFloor::particles}})
          .cases("drawdown.floor")
          .doc("`particles`: a frozen layer of the material's particles glued onto the floor, so that the mass left in "
               "the box does not depend on the wall frictions (docs/explanation/experiments.md); `wall`: the wall "
               "material"));
  time("fill_time", DRAWDOWN(fill_time), "the fill settles on the closed floor before the slot opens");
  time("check_time", DRAWDOWN(check_time), "the discharge is recorded and fallen particles removed every this long");
  time("window", DRAWDOWN(window),
       "the flow has stopped once less than `stop_share` of the fill left the box in the "
       "last window");
  add(Row("drawdown", "stop_share")
          .number(DRAWDOWN(stop_share), between(0, false, 1, false))
          .cases("drawdown.stop_share")
          .doc("see `window`"));
  time("min_time", DRAWDOWN(min_time), "the flow is judged stopped at this time after the opening at the earliest");
  time("time_cap", DRAWDOWN(time_cap),
       "the run ends here still flowing: measured, stored with `settled` = 0 and "
       "flagged");
  length("removal_depth", DRAWDOWN(removal_depth),
         "a particle this far below the floor has left the box: discharged "
         "and removed (counted, not lost)");
  add(Row("drawdown", "slices")
          .integer(DRAWDOWN(slices), between(1, true, 1000, true))
          .measurement("drawdown.slices")
          .doc("planes across the slope in which the surface is fitted (the median over them is a side's angle)"));
  add(Row("drawdown", "bin_width")
          .number(DRAWDOWN(bin_width), bin_width_bounds())
          .unit("m")
          .measurement("drawdown.bin_width")
          .doc("the surface of a slice is the highest particle top in bins this wide"));
  add(Row("drawdown", "edge_skip")
          .number(DRAWDOWN(edge_skip), between(0, true, 1, true))
          .unit("m")
          .measurement("drawdown.edge_skip")
          .doc("surface points this close to the slot's edge are not fitted"));
  add(Row("drawdown", "wall_skip")
          .number(DRAWDOWN(wall_skip), between(0, true, 1, true))
          .unit("m")
          .measurement("drawdown.wall_skip")
          .doc("surface points this close to a wall are not fitted"));
  return finish_rows(rows);
}

#undef DRAWDOWN

std::vector<SettingSection> drawdown_sections() {
  return {
      {"drawdown", "Defaults: the radii of the paper's particle set 1 (Table 2), a 102 mm wide box with a 30 mm slot.",
       "The fill is placed by random sequential addition, settles for `fill_time` on the closed floor, then the "
       "slot's plate is removed. Observables: `slope_angle` (the surface of what is left, per slice across the "
       "slope the highest particle top per bin between the slot's edge and the wall, a Theil–Sen line per side and "
       "slice, the median over the slices, the mean of the two sides), `discharged_mass` and `discharge_rate` "
       "(the least-squares slope of the discharged mass against time between 20 % and 80 % of the final); "
       "`retained_fraction` is recorded. docs/explanation/experiments.md has the measured values and their noise."}};
}

void check_drawdown(const StudyConfig& config, const SectionCheck& at) {
  const DrawdownSettings& s = settings(config);
  check_radii(s.radii, at);
  if (!(s.slot_width > 2 * s.radii.r_max))
    at.fail("slot_width",
            fmt::format("{} m cannot let a particle of radius r_max = {} m through", s.slot_width, s.radii.r_max));
  if (!(s.depth > 4 * s.radii.r_max))
    at.fail("depth", fmt::format("{} m must exceed 4 r_max = {} m: a particle would meet its own periodic image",
                                 s.depth, 4 * s.radii.r_max));
  if (!(s.side_width > 2 * s.radii.r_max + s.edge_skip + s.wall_skip))
    at.fail("side_width", fmt::format("{} m leaves no surface to fit between edge_skip and wall_skip", s.side_width));
  if (!(s.fill_height > 4 * s.radii.r_max))
    at.fail("fill_height",
            fmt::format("{} m holds no layer of particles of radius r_max = {} m", s.fill_height, s.radii.r_max));
  // The fill is placed by random sequential addition, which jams: monodisperse spheres saturate at a solid fraction
  // of 0.3841 (Zhang & Torquato 2013, "Precise algorithm to generate random sequential addition of hard
  // hyperspheres at saturation", Phys. Rev. E 88, 053312). The study's own radii (its seed's draw) over the box up to
  // fill_height must stay below it, or the case writer tries 100000 places per particle and fails in every case.
  {
    const std::vector<double> radii = fill_radii(s, config.seed);
    double volume = 0;
    for (const double r : radii) volume += 4.0 / 3.0 * std::numbers::pi * r * r * r;
    const double box_width = s.slot_width + 2 * s.side_width;
    const double box = box_width * s.depth * s.fill_height;
    if (volume > k_max_fill_fraction * box)
      at.fail(
          "particles",
          fmt::format("{} particles (their volume {:.3g} m³) fill {:.2f} of the box up to fill_height ({} × {} × "
                      "{} m = {:.3g} m³); placed one by one at random they jam near {}: lower particles to at most "
                      "{} or raise fill_height to at least {:.3g} m",
                      s.particles, volume, volume / box, box_width, s.depth, s.fill_height, box, k_max_fill_fraction,
                      static_cast<long>(std::floor(s.particles * k_max_fill_fraction * box / volume)),
                      volume / (k_max_fill_fraction * box_width * s.depth)));
  }
  if (!(s.check_time <= s.window))
    at.fail("check_time", fmt::format("{} s must not exceed window = {} s", s.check_time, s.window));
  if (!(s.min_time < s.time_cap))
    at.fail("min_time", fmt::format("{} s must lie below time_cap = {} s", s.min_time, s.time_cap));
}

}  // namespace demsa::experiments::drawdown
