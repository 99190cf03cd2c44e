#include "orchestrator/experiments/drum/drum.hpp"

#include "orchestrator/study/setting_row.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

// The [drum] section of the study file: its rows, the rules between them, and its prose in
// docs/reference/study-file.md.
namespace demsa::experiments::drum {

using namespace demsa::study;
namespace pp = demsa::postprocess;

namespace {

void apply_preset(DrumSettings& s, const std::string& preset) {
  // GranuTools' GranuDrum: inner radius 42 mm, 20 mm between its end plates (examples/drum-mcc/README.md).
  s.radius = 0.042;
  s.depth = 0.020;
  s.preset = preset;
}

#define DRUM(member) \
  [](auto& c) -> auto& { return settings(c).member; }

}  // namespace

const DrumSettings& settings(const StudyConfig& config) { return config.experiment_settings.get<DrumSettings>(); }
DrumSettings& settings(StudyConfig& config) { return config.experiment_settings.get<DrumSettings>(); }

pp::DrumSurfaceOptions surface_options(const DrumSettings& s) {
  pp::DrumSurfaceOptions o;
  o.judged_radius = s.judged_radius;
  o.angle_half_width = s.angle_half_width;
  o.stations = s.stations;
  o.threshold = s.threshold;
  return o;
}

std::vector<Setting> drum_settings() {
  std::vector<Row> rows;
  const auto add = [&](Row& row) { rows.push_back(std::move(row)); };
  const auto time = [&](const char* key, auto field, const char* doc) {
    add(Row("drum", key)
            .number(field, between(0, false, 1000, true))
            .unit("s")
            .cases(fmt::format("drum.{}", key))
            .doc(doc));
  };
  add(preset("drum", DRUM(preset), {"granudrum"},
             [](StudyConfig& c, const std::string& name) { apply_preset(settings(c), name); })
          .doc("`granudrum`: GranuTools' GranuDrum, inner radius 42 mm and 20 mm between the end plates. Other keys "
               "override it"));
  add(Row("drum", "radius")
          .number(DRUM(radius), between(1e-3, true, 10, true))
          .unit("m")
          .cases("drum.radius")
          .doc("inner radius R of the drum"));
  add(Row("drum", "depth")
          .number(DRUM(depth), between(1e-4, true, 10, true))
          .unit("m")
          .cases("drum.depth")
          .doc("inner depth between the end plates (along the axis, LIGGGHTS y); at least 2 coarse-grained largest "
               "diameters"));
  add(Row("drum", "rpm")
          .number(DRUM(rpm), between(0, false, 1000, true))
          .unit("1/min")
          .cases("drum.rpm")
          .doc("speed: one turn every 60/rpm s (the GranuDrum's images: 10, 15, 30, 45)"));
  add(Row("drum", "rotation")
          .choice(
              DRUM(rotation),
              std::vector<std::pair<std::string, pp::DrumRotation>>{
                  {"clockwise", pp::DrumRotation::clockwise}, {"counterclockwise", pp::DrumRotation::counterclockwise}})
          .cases("drum.rotation")
          .doc("the sense of rotation as the camera sees it through the end plate; `clockwise` (the GranuDrum's "
               "images): the wall on the left carries the powder up, the surface is high on the left"));
  add(Row("drum", "bulk_volume")
          .number(DRUM(bulk_volume), between(0, false, 100, true))
          .unit("m³")
          .cases("drum.bulk_volume")
          .doc("the fill as a bulk volume (the lab's 50 mL = 5e-5 m³): count = bulk_volume × `packing_fraction` / "
               "mean particle volume, divided by K³; at most 90 % of the drum, at least the segment below "
               "`judged_radius` (6.4 % "
               "for 0.77: a level bed's surface must lie in the judged circle), at most 1e7 particles"));
  add(Row("drum", "particles")
          .integer(DRUM(particles), between(0, true, k_max_particles, true))
          .cases("drum.particles")
          .doc("the fill as a full-size particle count instead of `bulk_volume` (0: from `bulk_volume`); a coarse "
               "grain K divides it by K³"));
  add(Row("drum", "packing_fraction")
          .number(DRUM(packing_fraction), between(0.3, true, 0.74, true,
                                                  "from a very loose bed to the densest "
                                                  "packing of spheres"))
          .cases("drum.packing_fraction")
          .doc("solid fraction of the settled bed, which turns `bulk_volume` into a count (0.6: 31,000 MCC particles "
               "for 50 mL, the lab's \"about 30,000\")"));
  add(Row("drum", "diameters")
          .numbers(DRUM(diameters), between(1e-6, true, 1, true))
          .unit("m")
          .cases("drum.diameters")
          .default_text("[] (the radius rows)")
          .doc("size classes (full size), with `fractions`: the particles take these diameters in these number "
               "fractions (a particle-size analyser's classes); empty: the truncated normal of `r_min`...`r_sd`"));
  add(Row("drum", "fractions")
          .numbers(DRUM(fractions), between(0, true, 1, true))
          .cases("drum.fractions")
          .default_text("[]")
          .doc("number fraction of each class of `diameters` (as many, positive, summing to 1 within 1e-3; "
               "renormalised)"));
  radius_rows(rows, "drum", "drum.", DRUM(radii));
  add(Row("drum", "coarse_grain")
          .number(DRUM(coarse_grain), between(1, true, 20, true))
          .cases("drum.coarse_grain")
          .doc("K: every radius × K and the count / K³ at the same bulk volume (a coarse twin, K⁴ cheaper: "
               "docs/explanation/experiments.md says what it keeps and what it cannot)"));
  add(Row("drum", "wall_sides")
          .integer(DRUM(wall_sides), between(12, true, 720, true))
          .cases("drum.wall_sides")
          .doc("sides of the polygon of the wall mesh (rim and end plates one mesh of 6 × sides triangles): a lean "
               "mesh is cheap, a mesh of thousands of triangles costs more than the particles"));
  time("settle_time", DRUM(settle_time), "the fill settles in the drum at rest");
  time("spin_up", DRUM(spin_up),
       "the drum turns this long before the first snapshot (the flow reaches its steady "
       "state); at least a quarter turn, 15/rpm s");
  time("window", DRUM(window), "snapshots are taken over this time (the lab's images average a video)");
  time("snapshot_interval", DRUM(snapshot_interval),
       "one snapshot every this much time within the window; at most 10000 snapshots a window");
  add(Row("drum", "image_size")
          .integer(DRUM(image_size), between(32, true, 4096, true))
          .measurement("drum.image_size")
          .doc("side of the occupancy image in pixels, spanning the inner diameter (the lab's images: 406)"));
  add(Row("drum", "judged_radius")
          .number(DRUM(judged_radius), between(0, false, 1, true))
          .measurement("drum.judged_radius")
          .doc("only the region within this fraction of R is judged (near the rim a photograph is least reliable)"));
  add(Row("drum", "angle_half_width")
          .number(DRUM(angle_half_width), between(0, false, 1, true))
          .measurement("drum.angle_half_width")
          .doc("the dynamic angle's line is fitted to the surface within this fraction of R of the centre, in x; at "
               "most `judged_radius`"));
  add(Row("drum", "stations")
          .numbers(DRUM(stations), between(-1, true, 1, true))
          .measurement("drum.stations")
          .doc("positions across the drum, as fractions of R in x, at which the surface height is an observable "
               "(`surface_1`...: left to right for a clockwise drum, mirrored for counterclockwise); each within "
               "`judged_radius`, none twice"));
  add(Row("drum", "threshold")
          .number(DRUM(threshold), between(0, false, 1, false))
          .measurement("drum.threshold")
          .doc("the material fraction of a pixel that counts as the free surface"));
  return finish_rows(rows);
}

#undef DRUM

std::vector<SettingSection> drum_sections() {
  return {{"drum", "Defaults: the GranuDrum's geometry (R = 42 mm, depth 20 mm), 15 rpm clockwise, 50 mL of bulk.",
           "A horizontal cylinder (axis LIGGGHTS y, gravity −z) holds the fill; it settles for `settle_time`, the wall "
           "mesh then turns at `rpm` (fix move/mesh), and after `spin_up` a snapshot of every particle is dumped every "
           "`snapshot_interval` over `window`. The camera looks through the end plate at y = 0: the picture's x is "
           "LIGGGHTS x and its up LIGGGHTS z. The measurement projects every snapshot onto a picture of `image_size` "
           "pixels spanning the inner diameter, averages them into the occupancy image (occupancy.png in the case "
           "folder) and measures it as a laboratory photograph is measured (postprocess/drum.hpp): `dynamic_angle`, "
           "`surface_K` at each of `stations`, `s_shape`, `fill_fraction` (docs/explanation/experiments.md). `demsa "
           "measure "
           "IMAGE` measures a photograph the same way."}};
}

void check_drum(const StudyConfig& config, const SectionCheck& at) {
  const DrumSettings& s = settings(config);
  if (!s.diameters.empty() || !s.fractions.empty()) {
    if (s.diameters.size() != s.fractions.size())
      at.fail("fractions", fmt::format("{} fractions for {} diameters: give one number fraction per size class",
                                       s.fractions.size(), s.diameters.size()));
    for (std::size_t i = 0; i < s.fractions.size(); ++i)
      if (!(s.fractions[i] > 0))
        at.fail("fractions", fmt::format("fraction {} = {}: every class needs a positive fraction (leave out an "
                                         "empty class)",
                                         i + 1, s.fractions[i]));
    const double sum = std::accumulate(s.fractions.begin(), s.fractions.end(), 0.0);
    if (std::abs(sum - 1.0) > 1e-3)
      at.fail("fractions", fmt::format("the fractions sum to {}, not 1 (within 1e-3)", sum));
    for (const char* key : {"r_min", "r_max", "r_mean", "r_sd"})
      if (at.given(key))
        at.fail(key,
                "give the sizes either as classes (`diameters`, `fractions`) or as a truncated normal (`r_min`, "
                "`r_max`, `r_mean`, `r_sd`), not both");
  } else {
    check_radii(s.radii, at);
  }
  if (s.particles > 0 && at.given("bulk_volume"))
    at.fail("particles", "give the fill either as `bulk_volume` or as `particles`, not both");
  double d_max = 0;
  for (const double d : s.diameters) d_max = std::max(d_max, d);
  if (s.diameters.empty()) d_max = 2 * s.radii.r_max;
  d_max *= s.coarse_grain;
  if (!(s.depth >= 2 * d_max))
    at.fail("depth", fmt::format("{} m holds less than two of the largest (coarse-grained) particles, {} m across",
                                 s.depth, d_max));
  if (!(s.radius >= 4 * d_max))
    at.fail("radius", fmt::format("{} m is less than four of the largest (coarse-grained) particles, {} m across",
                                  s.radius, d_max));
  const double drum_volume = std::numbers::pi * s.radius * s.radius * s.depth;
  const double bulk =
      s.particles > 0 ? static_cast<double>(s.particles) * mean_particle_volume(s) / s.packing_fraction : s.bulk_volume;
  const std::string fill_key = s.particles > 0 ? "particles" : "bulk_volume";
  if (!(bulk <= 0.9 * drum_volume))
    at.fail(fill_key,
            fmt::format("a bulk volume of {:.4g} m³ fills more than 90 % of the drum ({:.4g} m³)", bulk, drum_volume));
  // A level bed's surface lies below the judged circle when the bed is less than the circular segment cut off by a
  // chord at judged_radius R from the centre: (θ − sin θ) / 2π of the cross-section, θ = 2 acos(judged_radius). Its
  // measurement would find no surface (after every case had run).
  const double theta = 2 * std::acos(s.judged_radius);
  const double least = (theta - std::sin(theta)) / (2 * std::numbers::pi);
  if (!(bulk >= least * drum_volume))
    at.fail(fill_key, fmt::format("a bulk volume of {:.4g} m³ fills {:.3g} % of the drum ({:.4g} m³): a level bed's "
                                  "surface would lie below judged_radius = {} of R, where the measurement finds no "
                                  "surface; at least {:.3g} % ({:.4g} m³)",
                                  bulk, 100 * bulk / drum_volume, drum_volume, s.judged_radius, 100 * least,
                                  least * drum_volume));
  if (!(exact_fill_count(s) <= k_max_particles))
    at.fail(
        fill_key,
        fmt::format("{:.4g} particles (coarse_grain = {}), more than {:.0e}: a larger coarse_grain or a smaller fill",
                    exact_fill_count(s), s.coarse_grain, k_max_particles));
  if (!(s.snapshot_interval <= s.window))
    at.fail("snapshot_interval", fmt::format("{} s is longer than the window, {} s: no snapshot would be taken",
                                             s.snapshot_interval, s.window));
  if (!(s.window / s.snapshot_interval <= k_max_snapshots))
    at.fail("snapshot_interval",
            fmt::format("{} s over a window of {} s is {:.3g} snapshots, more than {} (each is a dump frame of every "
                        "particle; the GranuDrum averages 40 images)",
                        s.snapshot_interval, s.window, s.window / s.snapshot_interval, k_max_snapshots));
  // A bed turned as a rigid body by less than its angle of repose has not begun to flow, and every material's lies
  // below 90°: before a quarter turn the snapshots may show a bed at rest, not its dynamic angle.
  if (!(s.spin_up * s.rpm / 60 >= 0.25))
    at.fail(at.given("spin_up") || !at.given("rpm") ? "spin_up" : "rpm",
            fmt::format("{} s at {} rpm turns the drum {:.3g} of a turn before the first snapshot: at least "
                        "a quarter turn ({:.4g} s), beyond any material's angle of repose, before the bed "
                        "is sure to flow",
                        s.spin_up, s.rpm, s.spin_up * s.rpm / 60, 15 / s.rpm));
  if (s.stations.empty()) at.fail("stations", "give at least one station");
  if (!(s.angle_half_width <= s.judged_radius))
    at.fail("angle_half_width",
            fmt::format("{} must not exceed judged_radius = {}", s.angle_half_width, s.judged_radius));
  for (const double x : s.stations)
    if (!(std::abs(x) <= s.judged_radius))
      at.fail("stations", fmt::format("station {} lies outside judged_radius = {}", shortest(x), s.judged_radius));
  for (std::size_t i = 0; i < s.stations.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (s.stations[i] == s.stations[j])
        at.fail("stations", fmt::format("station {} is given twice: its height would be two observables of one "
                                        "measurement",
                                        shortest(s.stations[i])));
  const long count = fill_count(s);
  if (count < 1) at.fail("coarse_grain", "leaves no particle in the drum");
  if (const long sites = lattice_capacity(s, count); sites < count)
    at.fail(fill_key,
            fmt::format("{} particles (coarse_grain = {}) do not fit into the drum: it holds {} of the lattice sites "
                        "where they start before they settle; lower {}",
                        count, s.coarse_grain, sites, fill_key));
}

}  // namespace demsa::experiments::drum
