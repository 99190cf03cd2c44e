#include "orchestrator/experiments/pile/pile.hpp"

#include "orchestrator/experiments/particle_sets.hpp"
#include "orchestrator/study/setting_row.hpp"

#include <fmt/core.h>

#include <cmath>
#include <numbers>

// The [pile] section of the study file: its rows, the rules between them, and its prose in
// docs/reference/study-file.md.
namespace demsa::experiments::pile {

using namespace demsa::study;

namespace {

void apply_preset(PileSettings& pile, const std::string& preset) {
  // Paper Table 2: particle sets 1 and 2.
  pile.particles = preset == "set1" ? 6000 : 8000;
  pile.radii = preset_radii(preset);
  pile.preset = preset;
}

#define PILE(member) \
  [](auto& c) -> auto& { return settings(c).member; }

}  // namespace

const PileSettings& settings(const StudyConfig& config) { return config.experiment_settings.get<PileSettings>(); }
PileSettings& settings(StudyConfig& config) { return config.experiment_settings.get<PileSettings>(); }

bool plane_pedestal(const PileSettings& s) { return s.pedestal_top == PedestalTop::plane; }

std::vector<Setting> pile_settings() {
  std::vector<Row> rows;
  const auto add = [&](Row& row) { rows.push_back(std::move(row)); };
  add(preset("pile", PILE(preset), {"set1", "set2"},
             [](StudyConfig& c, const std::string& name) { apply_preset(settings(c), name); })
          .doc("`set1` (6000 particles, radii [1, 3.5] mm, mean 2, sd 0.5) or `set2` (8000, [0.8, 2.5] mm, 1.5, "
               "0.35): paper Table 2. Other keys override it"));
  add(Row("pile", "particles")
          .integer(PILE(particles),
                   between(1, true, k_max_particles, true,
                           "the case writer holds every particle, and the text of its data file, in memory"))
          .cases("pile.particles")
          .doc("number of particles"));
  radius_rows(rows, "pile", "pile.", PILE(radii));
  add(Row("pile", "disc_radius")
          .number(PILE(disc_radius), between(0, false, 10, true))
          .unit("m")
          .cases("pile.disc_radius")
          .doc("r_fu, radius of the filling discs; at least `r_max`"));
  add(Row("pile", "fill_height")
          .number(PILE(fill_height), between(0, false, 100, true))
          .unit("m")
          .cases("pile.fill_height")
          .doc("h_fu above the pedestal top (above the top of the base layer with `base = \"particles\"`): discs "
               "below are present at start, later ones are appended there; a case "
               "whose pile grows into the layer of a new disc (a particle centre above h_fu − r_U) stops with an "
               "error naming this key"));
  add(Row("pile", "pedestal_radius")
          .number(PILE(pedestal_radius),
                  between(1e-3, true, 1, true, "its mesh has rings 5 mm apart: up to 200 rings and 250000 triangles"))
          .unit("m")
          .cases("pile.pedestal_radius")
          .doc("r_cy"));
  add(Row("pile", "pedestal_height")
          .number(PILE(pedestal_height),
                  between(1e-4, true, 1, true, "its side band is split into bands of 5 mm: up to 200"))
          .unit("m")
          .cases("pile.pedestal_height")
          .doc("h_cy (the pedestal top)"));
  add(Row("pile", "settle_time")
          .number(PILE(settle_time), k_duration_bounds)
          .unit("s")
          .cases("pile.settle_time")
          .doc("settling after the last disc: the cap; a pile still moving then is recorded as unsettled and flagged "
               "by `demsa status` and the report"));
  // The settling rows replaced `ke_stop` (0: settle for settle_time). At their defaults they give the hash text of
  // that version (`pile.ke_stop=0`, nothing more), so its studies keep their hash and their fixed settling time.
  add(Row("pile", "settle_speed")
          .number(PILE(settle_speed), between(0, true, 1e3, true))
          .cases("pile.settle_speed")
          .canonical([](const StudyConfig& c) -> Lines {
            if (settings(c).settle_speed == 0) return {{"pile.ke_stop", canonical_number(0)}};
            return {{"pile.settle_speed", canonical_number(settings(c).settle_speed)}};
          })
          .doc("the pile is settled once the particles on the pedestal (centre above its top, within its radius) "
               "move slower than `settle_speed` × √(\\|g\\| r_min) (the share `settle_quantile` of them at "
               "least) at every check for `settle_window`; 0 = settle for `settle_time` (the paper's schedule)"));
  add(Row("pile", "settle_quantile")
          .number(PILE(settle_quantile), between(0, false, 1, true))
          .cases("pile.settle_quantile")
          .canonical(unless_default("pile.settle_quantile", PILE(settle_quantile)))
          .doc("share of the particles on the pedestal that must be slow; 1 = every one (the fastest is judged)"));
  add(Row("pile", "settle_window")
          .number(PILE(settle_window), between(0, false, k_max_duration, true))
          .unit("s")
          .cases("pile.settle_window")
          .canonical(unless_default("pile.settle_window", PILE(settle_window)))
          .doc("how long the settling criterion must hold"));
  add(Row("pile", "settle_check_time")
          .number(PILE(settle_check_time), between(0, false, k_max_duration, true))
          .unit("s")
          .cases("pile.settle_check_time")
          .doc("how often the settling criterion is checked and fallen particles removed (also after every disc)"));
  add(Row("pile", "remove_fallen")
          .boolean(PILE(remove_fallen))
          .cases("pile.remove_fallen")
          .canonical(unless_default("pile.remove_fallen", PILE(remove_fallen)))
          .doc("delete particles whose centre is below the pedestal top and outside its radius (§3.2's filter "
               "applied during the run); they are counted as removed, not lost"));
  add(Row("pile", "domain_half_width")
          .number(PILE(domain_half_width), between(0, false, 10, true))
          .unit("m")
          .cases("pile.domain_half_width")
          .doc("simulation box half width; particles leaving it are lost. Must exceed `disc_radius` + `r_max` and "
               "`pedestal_radius`"));
  add(Row("pile", "target_angle")
          .number(PILE(target_angle), between(0, false, 90, false))
          .unit("deg")
          .doc("φ̂ of E_φ = (φ̂ − φ)²: the calibration target of `demsa calibrate` and the report (not stored with "
               "the cases)"));
  add(Row("pile", "directions")
          .integer(PILE(directions), between(1, true, 100000, true))
          .measurement("pile.directions")
          .doc("φ_N of §3.3: the angle of a finished pile is measured in this many directions"));
  add(Row("pile", "levels")
          .integer(PILE(levels), between(2, true, 100000, true))
          .measurement("pile.levels")
          .doc("height levels at which the angle is measured: between 0.2 h_P and 0.75 h_P (paper), 0.25 h_P (but "
               "at least 1.5 times the largest radius above the pedestal) and 0.8 h_P (robust)"));
  add(Row("pile", "angle_estimator")
          .choice(PILE(angle_estimator),
                  std::vector<std::pair<std::string, std::string>>{{"paper", "paper"}, {"robust", "robust"}})
          .measurement("pile.angle_estimator")
          .doc("`paper`: §3.3 (outermost particle per direction and level, orthogonal line, mean over directions), "
               "which reads up to 1.4° low on rough flanks and 0.9° high on mounds; `robust`: the outermost points of "
               "the pile's horizontal sections at the exact level heights, in a sector about each direction, a "
               "Theil–Sen line per direction and the median over directions, within 0.14° on average on synthetic "
               "cones of nine kinds of surface (jitter, holes, mounds, two radius sets) and 0.33° on held-out cones "
               "with Gaussian jitter from 22° to 45° (docs/explanation/benchmarks.md, angle estimators)"));
  add(Row("pile", "base")
          .choice(PILE(base), std::vector<std::pair<std::string, PileBase>>{{"wall", PileBase::wall},
                                                                            {"particles", PileBase::particles}})
          .cases("pile.base")
          .canonical([](const StudyConfig& c) -> Lines {
            // Absent at its default: the studies made before the key existed keep their hash.
            if (settings(c).base == PileBase::wall) return {};
            return {{"pile.base", "particles"}};
          })
          .doc("what the pile stands on: `wall`, the pedestal's top (particle-wall contacts, μ_PW and μ_R,PW), or "
               "`particles`, a fixed layer of the material's own particles glued to the pedestal top (a rough base: "
               "the pile's base contacts are particle-particle). The layer is drawn once from the study seed "
               "(identical for every sample), frozen, and left out of the measurement, which measures heights from "
               "its mean top"));
  add(Row("pile", "pedestal_top")
          .choice(PILE(pedestal_top), std::vector<std::pair<std::string, PedestalTop>>{{"mesh", PedestalTop::mesh},
                                                                                       {"plane", PedestalTop::plane}})
          .cases("pile.pedestal_top")
          .canonical([](const StudyConfig& c) -> Lines {
            // The mesh was the only top before the key existed: its studies keep their hash; a plane is another case.
            if (!plane_pedestal(settings(c))) return {};
            return {{"pile.pedestal_top", "plane"}};
          })
          .doc("the pedestal top's wall in LIGGGHTS: `mesh` (the default), the pedestal's mesh (rim, side band and a "
               "top of 5 mm triangles), or `plane`, a primitive plane at the top's height whose particles past the "
               "rim are deleted at every check (it needs `remove_fallen` and `base = \"wall\"`). On the quickstart's "
               "piles the plane takes 1.53 times fewer CPU-seconds and gives the same mean angle, but the angle "
               "follows μ_R,PW less (the GP's S1 0.10 against 0.24) and 4 of the 20 piles end unsettled against 1 "
               "(docs/explanation/benchmarks.md, \"The pedestal top as a plane\"). `pedestal.stl` is written either "
               "way (`demsa export-vtk` draws it)"));
  add(Row("pile", "history_interval")
          .number(PILE(history_interval), k_duration_bounds)
          .unit("s")
          .cases("pile.history_interval")
          .canonical(unless_default("pile.history_interval", PILE(history_interval)))
          .doc("the pile in time: a snapshot of the particles every this long during settling (rounded to a whole "
               "number of settling checks, at least one), from the end of the last disc; each is measured like the "
               "final pile (both estimators, height, particles on the pedestal) into the case's "
               "`pile_history.csv` and the store (`angle_series@T`), and gives `angle_drift`; 0 = none"));
  add(Row("pile", "keep_snapshots")
          .boolean(PILE(keep_snapshots))
          .doc("keep the snapshot dumps (`pile_snapshot_K.dump`, K the settling check) once measured; by default "
               "they are removed, their measurement stays in `pile_history.csv`"));
  add(Row("pile", "measure_times")
          .numbers(PILE(measure_times), k_duration_bounds)
          .check([](const SettingValue& v) {
            const auto& times = std::get<std::vector<double>>(v);
            if (times.size() > 100) throw SettingError(fmt::format("{} times; at most 100", times.size()));
            for (std::size_t i = 1; i < times.size(); ++i)
              if (!(times[i] > times[i - 1]))
                throw SettingError(fmt::format("times must increase: {} s follows {} s", times[i], times[i - 1]));
          })
          .range("up to 100, increasing, each in [0, `settle_time`]")
          .unit("s")
          .cases("pile.measure_times")
          .doc("the angle at these times after the last disc, from the same runs: observables `angle@T` (e.g. "
               "`angle@0.6`), analysed like `angle` (each taken at the settling check nearest to T; settling runs "
               "at least to the last of them)"));
  add(Row("pile", "drift_window")
          .number(PILE(drift_window), drift_window_bounds())
          .unit("s")
          .measurement("pile.drift_window")
          .doc("`angle_drift` is the Theil–Sen slope of the angle over the snapshots within this long of the end "
               "of settling"));
  add(Row("pile", "drift_limit")
          .number(PILE(drift_limit), drift_limit_bounds())
          .unit("deg/s")
          .measurement("pile.drift_limit")
          .doc("a pile is settled only when \\|`angle_drift`\\| is at most this (besides the speed criterion, when "
               "it is on); a pile whose angle still moves at the end is stored with `settled` = 0 and flagged, with "
               "its drift, by `demsa status`, the analysis and the report"));

  return finish_rows(rows);
}

#undef PILE

std::vector<SettingSection> pile_sections() {
  return {
      {"pile", "Defaults: particle set 1 of the paper's Table 2.",
       "Discs: ring k of a disc has radius 2 r_U k; disc k of the column is at pedestal top + r_U + 2 r_U k; one "
       "more disc is appended every sqrt(4 r_U/\\|g\\|).\n\n"
       "Settling and removal (both off by default: the paper's schedule; the quickstart and the paper presets turn "
       "them on): every `settle_check_time` (and after every disc) the particles whose centre lies below "
       "the pedestal top and outside its radius are deleted (`remove_fallen`; §3.2's filter, applied during the run: "
       "they cannot come back) and counted; they are stored as `removed_off_pedestal` and are not lost atoms. The "
       "pile is settled once no more than the share 1 − `settle_quantile` of the particles on the pedestal move "
       "faster than `settle_speed` √(\\|g\\| r_min) at every check for `settle_window`; a pile that reaches "
       "`settle_time` still moving is measured, stored with `settled` = 0 and flagged by `demsa status` and the "
       "report. One-at-a-time runs (set 1, E = 1e8 Pa, ν = 0.3, μ_PP = 1.3, μ_PW = 1.15, e_r = 0.4, baseline "
       "μ_R,PP = μ_R,PW = 0.275, `cdt`; the quickstart's settling and removal of 2026-12-01, a 0.05 s window capped "
       "at 0.6 s; one LIGGGHTS run each; angle by §3.3):\n\n"
       "| pedestal radius, particles | baseline angle (h_P) | doubled particles | μ_R,PP 0.05 → 0.5 | μ_R,PW 0.05 → "
       "0.5 |\n"
       "|---|---|---|---|---|\n"
       "| 25 mm, 300 | 22.5° (15 mm)¹ | 25.4° (15 mm)¹ | 18.3° → 23.1° | 12.7° → 26.3° |\n"
       "| 35 mm, 700 (the quickstart before 2400 on 50 mm) | 23.8° (19 mm) | 23.1° (18 mm) | 21.7° (unsettled) → 27.9° "
       "| 20.2° → 26.5° |\n"
       "| 40 mm, 1000 | 25.9° (21 mm) | 27.2° (24 mm) | not run | 20.0° → 26.4° |\n\n"
       "At these sizes particle-wall rolling friction moves the angle as much as particle-particle rolling friction. ¹ "
       "with `settle_quantile` = 1.\n\n"
       "How the pile is poured decides the ranking more than its size. One-at-a-time runs of 2400 particles on the "
       "paper's 50 mm pedestal (E = 1e7 Pa, the rest as above, removal on unless said; one run each; angle by §3.3; "
       "share of Δ² over the parameters run; atom-steps: mean of the four rolling runs):\n\n"
       "| pour | μ_R,PP 0.05 → 0.5 | μ_R,PW 0.05 → 0.5 | μ_PP 0.7 → 1.9 | share of Δ² (μ_R,PW / μ_R,PP / μ_PP) | "
       "atom-steps |\n"
       "|---|---|---|---|---|---|\n"
       "| a wide dump: 16 discs of 45 mm radius, all in the column at the start (150 mm) | 22.6° → 29.8° | "
       "22.5° → 29.4° | 26.9° → 26.2° | 0.47 / 0.52 / 0.01 | 7.6e7 |\n"
       "| the same, nothing removed | 21.1° → 28.2° | 21.0° → 27.1° | not run | 0.42 / 0.58 | 9.9e7 |\n"
       "| a tall column: 38 discs of 25 mm, all in the column (280 mm) | 11.7° → 18.4° | 12.0° → 19.2° | not run | "
       "0.54 / 0.46 | 7.0e7 |\n"
       "| a central stream: discs of 25 mm, 9 in the column, 29 appended at 60 mm | 23.0° → 38.3° | 29.7° → 34.3° "
       "| not run | 0.08 / 0.92 | 1.9e8 |\n"
       "| **a central stream: discs of 32 mm, 9 in the column, 14 appended at 60 mm (the quickstart)** | 24.7° → "
       "37.0° | 28.2° → 32.8° | 28.8° → 33.3° | 0.11 / 0.79 / 0.10 | 1.3e8 |\n"
       "| the same with `fill_height` 80 mm and `settle_speed` 0.05 | 22.7° → 33.1° | 22.6° → 30.8° | not run | "
       "0.38 / 0.62 | 1.2e8 |\n\n"
       "Particles that land as a sheet on the pedestal top stop on their particle-wall contacts; a stream onto the "
       "pile's top builds the cone by avalanches over particles, as the paper pours (discs of 20 mm on its 50 mm "
       "pedestal, one every sqrt(4 r_U/\\|g\\|)), and ranks μ_R,PP first as the larger piles of the paper's "
       "schedule do (at 2400 particles, 25.7° → 37.4° for μ_R,PP against 29.2° → 33.6° for μ_R,PW). The quickstart's "
       "own 20 samples (E in [1e7, 1e8] Pa) rank μ_R,PP first: S1 of the angle 0.63–0.70 (ST 0.68–0.71) against "
       "0.20–0.22 (ST 0.20–0.27) for μ_R,PW over its four metamodels, S1 of E at most 0.002. Its baseline at E = 1e7 "
       "Pa measured 30.9°, 31.5° and 31.9° with three packings (study seeds 20240501, 7 and 11; robust estimator "
       "33.0°, 33.3°, 33.9°); with 4800 particles 31.0° (robust 32.1°, unsettled at the cap); at E = 1e8 Pa 32.3° "
       "(robust 33.7°)."}};
}

void check_pile(const StudyConfig& config, const SectionCheck& at) {
  const PileSettings& p = settings(config);
  check_radii(p.radii, at);
  if (2 * p.radii.r_max > 2 * p.disc_radius)
    at.fail("disc_radius",
            fmt::format("{} m cannot hold a particle of radius r_max = {} m", p.disc_radius, p.radii.r_max));
  if (p.disc_radius + p.radii.r_max > p.domain_half_width || p.pedestal_radius >= p.domain_half_width)
    at.fail("domain_half_width",
            fmt::format("{} m must exceed the disc radius + r_max and the pedestal radius", p.domain_half_width));
  for (const double t : p.measure_times)
    if (t > p.settle_time * (1 + 1e-12))
      at.fail("measure_times",
              fmt::format("{} s lies beyond settle_time = {} s, the end of settling: raise settle_time "
                          "or measure earlier",
                          t, p.settle_time));
  if (p.history_interval > 0) {
    const double every = std::max(1.0, std::round(p.history_interval / p.settle_check_time));
    const double snapshots = std::ceil(p.settle_time / p.settle_check_time) / every + 1;
    if (snapshots > static_cast<double>(k_max_snapshots))
      at.fail("history_interval",
              fmt::format("{} s over settle_time = {} s is {:.0f} snapshots, more than {}: each is a dump of every "
                          "particle; take a longer interval",
                          p.history_interval, p.settle_time, snapshots, k_max_snapshots));
  }
  if (p.pedestal_top == PedestalTop::plane && !p.remove_fallen)
    at.fail("pedestal_top",
            "\"plane\" needs remove_fallen = true: the plane has no rim, so particles past the pedestal's radius "
            "stay on it unless they are deleted; use \"mesh\"");
  if (p.pedestal_top == PedestalTop::plane && p.base == PileBase::particles)
    at.fail("pedestal_top",
            "\"plane\" stands in for the pedestal's wall top, and base = \"particles\" has none (its pedestal is "
            "the side band under a frozen layer); use \"mesh\" or leave it out");
  if (p.base == PileBase::particles) {
    // The base layer's hexagonal lattice (build_base_layer) has about pi R^2 / (pitch^2 sqrt(3)/2) sites.
    const double pitch = k_base_pitch * p.radii.mean;
    const double sites =
        std::numbers::pi * p.pedestal_radius * p.pedestal_radius / (pitch * pitch * std::sqrt(3.0) / 2);
    if (sites > k_max_particles)
      at.fail(at.given("pedestal_radius") ? "pedestal_radius" : "base",
              fmt::format("a base layer of particles of mean radius {} m on a pedestal of radius {} m would hold about "
                          "{:.3g} particles, more than {:.0e}",
                          p.radii.mean, p.pedestal_radius, sites, k_max_particles));
  }
}

std::map<std::string, std::string> pile_retired_keys() {
  return {{"ke_stop",
           "it was replaced by `settle_speed` and `settle_window`: a pile is settled once the particles on the "
           "pedestal are slow, whatever rolls on the ground; remove `ke_stop`, see docs/reference/study-file.md"}};
}

}  // namespace demsa::experiments::pile
