#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/experiments/pile/case_angle.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/observables.hpp"
#include "orchestrator/study/setting_row.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/error.hpp"
#include "postprocess/stl.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

// The pile's descriptor: its measurement (paper §3.3), its observables, its report section and its ParaView
// surfaces. Its settings are in settings.cpp, its case in case.cpp.
namespace demsa::experiments::pile {

using namespace demsa::study;

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

// settings.cpp and case.cpp
std::vector<Setting> pile_settings();
std::vector<SettingSection> pile_sections();
void check_pile(const StudyConfig& config, const SectionCheck& at);
std::map<std::string, std::string> pile_retired_keys();
std::unique_ptr<CaseDraft> draft_case(const StudyConfig& config, std::uint64_t assembly_seed);

std::optional<PileSettling> read_settling(const fs::path& folder) {
  const fs::path file = folder / k_settling;
  std::ifstream in(file);
  if (!in) return std::nullopt;
  std::map<std::string, double> values;
  std::string line;
  long number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream words(line);
    std::string key;
    std::string value;
    std::string extra;
    if (!(words >> key)) continue;
    double v = 0;
    if (!(words >> value) || (words >> extra) || !(std::istringstream(value) >> v))
      throw pp::ParseError(file.string(), number, fmt::format("expected 'key number', got '{}'", line));
    values[key] = v;
  }
  const auto get = [&](const char* key) {
    const auto it = values.find(key);
    if (it == values.end()) throw pp::ParseError(file.string(), 0, fmt::format("no '{}' line", key));
    return it->second;
  };
  PileSettling s;
  s.criterion = get("criterion") > 0;
  s.settled = s.criterion && get("settled") > 0;
  s.end_step = static_cast<long>(get("end_step"));
  s.fastest = get("fastest_on_pedestal");
  s.speed_limit = get("speed_limit");
  s.on_pedestal = static_cast<long>(get("on_pedestal"));
  s.fast_on_pedestal = static_cast<long>(get("fast_on_pedestal"));
  s.removed = static_cast<long>(get("removed"));
  // Written since the pile in time; older cases have neither.
  if (values.count("start_step")) s.start_step = static_cast<long>(get("start_step"));
  if (values.count("check_steps")) s.check_steps = static_cast<long>(get("check_steps"));
  return s;
}

pp::PileAngleOptions angle_options(const PileSettings& pile) {
  pp::PileAngleOptions options;
  options.pedestal_radius = pile.pedestal_radius;
  options.pedestal_top = pile.pedestal_height;  // the ground is at z = 0
  options.directions = pile.directions;
  options.levels = pile.levels;
  options.target_angle = pile.target_angle;
  // [pile] angle_estimator holds one of postprocess::angle_estimator_names() (a choice of settings.cpp).
  options.estimator = pp::angle_estimator_from_string(pile.angle_estimator);
  return options;
}

CaseAngleSettings read_case_angle_settings(const nlohmann::json& doc, const fs::path& file) {
  // The ranges of the [pile] rows (settings.cpp): a length is positive and below a kilometre, a count fits its row.
  CaseAngleSettings s;
  s.pedestal_radius = case_number(doc, file, "pile.pedestal_radius_m", 1e-9, 1e3);
  s.pedestal_top = case_number(doc, file, "pile.pedestal_height_m", 0, 1e3);
  if (const auto n = case_integer(doc, file, "pile.angle_measurement.directions", 1, 100000))
    s.directions = static_cast<int>(*n);
  if (const auto n = case_integer(doc, file, "pile.angle_measurement.levels", 2, 100000))
    s.levels = static_cast<int>(*n);
  s.base_particles = case_integer(doc, file, "pile.base.particles", 0, static_cast<long>(k_max_particles));
  s.base_top = case_number(doc, file, "pile.base.top_m", 0, 1e3);
  if (const auto name = case_string(doc, file, "pile.angle_measurement.estimator")) {
    try {
      s.estimator = pp::angle_estimator_from_string(*name);
    } catch (const std::invalid_argument& e) {
      throw util::UserError(file.string(), 0, fmt::format("pile.angle_measurement.estimator: {}", e.what()));
    }
  }
  return s;
}

namespace {

/// `chosen`'s options with what the case records in place of those the caller did not choose.
pp::PileAngleOptions recorded_angle_options(const CaseAngleSettings& s, const ChosenAngleOptions& chosen) {
  pp::PileAngleOptions options = chosen.options;
  if (s.pedestal_radius && !chosen.pedestal_radius) options.pedestal_radius = *s.pedestal_radius;
  if (s.pedestal_top && !chosen.pedestal_top) options.pedestal_top = *s.pedestal_top;
  if (s.directions && !chosen.directions) options.directions = *s.directions;
  if (s.levels && !chosen.levels) options.levels = *s.levels;
  if (s.estimator && !chosen.estimator) options.estimator = *s.estimator;
  // A pile on a base layer stands on the layer: heights and levels start at its mean top.
  if (s.base_top && !chosen.pedestal_top) options.pedestal_top = *s.base_top;
  return options;
}

}  // namespace

pp::PileAngleOptions case_angle_options(const nlohmann::json& doc, const fs::path& file) {
  const CaseAngleSettings s = read_case_angle_settings(doc, file);
  for (const auto& [value, key] :
       {std::pair{s.pedestal_radius, "pile.pedestal_radius_m"}, std::pair{s.pedestal_top, "pile.pedestal_height_m"}})
    if (!value) throw util::UserError(file.string(), 0, fmt::format("records no {} (the pile's pedestal)", key));
  return recorded_angle_options(s, ChosenAngleOptions{});
}

CaseAngle case_angle(const nlohmann::json& doc, const fs::path& file, const ChosenAngleOptions& chosen) {
  if (const std::optional<std::string> name = case_string(doc, file, "experiment"); name && *name != experiment().name)
    throw util::UserError(file.string(), 0,
                          fmt::format("experiment = \"{}\": not a pile case; `demsa measure {}` measures it", *name,
                                      file.parent_path().string()));
  const CaseAngleSettings recorded = read_case_angle_settings(doc, file);
  for (const auto& [value, key, given] :
       {std::tuple{recorded.pedestal_radius, "pile.pedestal_radius_m", chosen.pedestal_radius},
        std::tuple{recorded.pedestal_top, "pile.pedestal_height_m", chosen.pedestal_top}}) {
    if (!value && !given)
      throw util::UserError(file.string(), 0,
                            fmt::format("records no {} (a case written by an older demsa): give the pile's pedestal "
                                        "as PileAngleOptions.pedestal_radius and PileAngleOptions.pedestal_top",
                                        key));
  }
  CaseAngle angle;
  angle.options = recorded_angle_options(recorded, chosen);
  angle.base_particles = recorded.base_particles.value_or(0);
  return angle;
}

namespace {

/// The pile of one state (its particles without the base layer) measured by both estimators; NaN angles when it holds
/// no pile to measure (a snapshot taken while the last disc still falls onto an empty pedestal).
PileMoment measure_moment(const pp::Particles& particles, pp::PileAngleOptions options) {
  PileMoment m;
  const pp::AngleEstimator study = options.estimator;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const pp::AngleEstimator estimator : {pp::AngleEstimator::paper, pp::AngleEstimator::robust}) {
    options.estimator = estimator;
    double angle = nan;
    try {
      const pp::PileAngleResult r = pp::measure_pile_angle(particles, options);
      angle = r.angle;
      if (estimator == study) {
        m.height = r.pile_height;
        m.on_pedestal = static_cast<long>(r.particles_on_pedestal);
      }
    } catch (const pp::InputError&) {
      if (estimator == study) m.on_pedestal = static_cast<long>(pp::pedestal_particles(particles, options).size());
    }
    (estimator == pp::AngleEstimator::paper ? m.angle_paper : m.angle_robust) = angle;
    if (estimator == study) m.angle = angle;
  }
  return m;
}

/// The pile in time of a finished case: measured on its snapshots when they are there (written to pile_history.csv,
/// the snapshots then removed unless kept), read back from pile_history.csv when they are not; empty for a case
/// without snapshots. The final dump is the last moment when it lies after the last snapshot.
std::vector<PileMoment> case_history(const fs::path& folder, const nlohmann::json& doc,
                                     const pp::PileAngleOptions& options, long base, const PileSettling& settling,
                                     const PileMoment& final_moment) {
  const fs::path file = folder / k_case_json;
  const std::size_t n = case_list_size(doc, file, "pile.history.snapshot_checks", k_max_snapshots + 1);
  if (n == 0 || !settling.start_step) return {};
  const long check_steps = case_integer(doc, file, "pile.history.check_steps", 1, 1L << 50).value_or(0);
  const double dt = case_number(doc, file, "dt", 1e-15, 1e3).value_or(0);
  if (check_steps == 0 || dt == 0)
    throw util::UserError(file.string(), 0, "records snapshots but no pile.history.check_steps or dt");
  // Snapshots after the end of settling are of an earlier, longer attempt.
  const long end_check = (settling.end_step - *settling.start_step) / check_steps;
  std::vector<long> checks;
  for (std::size_t i = 0; i < n; ++i) {
    const long k = *case_integer(doc, file, fmt::format("pile.history.snapshot_checks.{}", i), 0, 1L << 50);
    if (k <= end_check) checks.push_back(k);
  }
  std::error_code ec;
  const bool any =
      std::any_of(checks.begin(), checks.end(), [&](long k) { return fs::exists(folder / snapshot_file(k), ec); });
  std::vector<PileMoment> moments;
  if (!any && fs::exists(folder / k_history_csv, ec)) return read_history(folder);
  for (const long k : checks) {
    const fs::path dump = folder / snapshot_file(k);
    if (!fs::exists(dump, ec))
      throw pp::InputError(
          fmt::format("{}: missing: the case wrote a snapshot at every check of "
                      "pile.history.snapshot_checks up to the end of settling (check {})",
                      dump.string(), end_check));
    PileMoment m = measure_moment(without_base(pp::read_particles(dump, 1), base), options);
    m.check = k;
    m.time = static_cast<double>(k * check_steps) * dt;
    moments.push_back(m);
  }
  if (moments.empty() || final_moment.time > moments.back().time + 0.5 * dt) moments.push_back(final_moment);
  write_history(folder, moments);
  const bool keep = doc["pile"]["history"].value("keep_snapshots", false);
  if (!keep)
    for (const long k : checks) fs::remove(folder / snapshot_file(k), ec);
  return moments;
}

/// `t` rounded to 9 significant digits: 5 × 0.01 s reads 0.05 s, not 0.05000000000000000278.
double round_time(double t) { return std::stod(fmt::format("{:.9g}", t)); }

std::map<std::string, double> measure(const fs::path& folder, const nlohmann::json& case_json) {
  const fs::path file = folder / k_case_json;
  const pp::PileAngleOptions options = case_angle_options(case_json, file);
  const long base = read_case_angle_settings(case_json, file).base_particles.value_or(0);
  const pp::Particles particles = without_base(pp::read_particles(folder / k_final_dump, 1), base);
  const pp::PileAngleResult result = pp::measure_pile_angle(particles, options);
  std::map<std::string, double> values;
  values[std::string(k_angle)] = result.angle;
  values[std::string(k_pile_height)] = result.pile_height;
  values[std::string(k_angle_sd)] = result.angle_sd;
  values[std::string(k_particles_on_pedestal)] = static_cast<double>(result.particles_on_pedestal);
  const std::optional<PileSettling> settling = read_settling(folder);
  if (!settling) return values;
  std::optional<bool> settled;
  if (settling->criterion) settled = settling->settled;
  values[std::string(k_removed_off_pedestal)] = static_cast<double>(settling->removed);

  // The pile in time (settling snapshots): the series, the angle at the measure times, the drift.
  if (settling->start_step) {
    const double dt = case_number(case_json, file, "dt", 1e-15, 1e3).value_or(0);
    PileMoment last = measure_moment(particles, options);
    last.time = static_cast<double>(settling->end_step - *settling->start_step) * dt;
    const std::vector<PileMoment> moments = case_history(folder, case_json, options, base, *settling, last);
    // The series is stored by the nominal time of each check, k × settle_check_time (the measured time in
    // pile_history.csv differs by the rounding of a check to whole steps).
    const double check_time = case_number(case_json, file, "pile.history.check_time_s", 1e-15, 1e4).value_or(0);
    for (const PileMoment& m : moments)
      if (m.check >= 0 && std::isfinite(m.angle) && check_time > 0)
        values[timed_observable(k_angle_series, round_time(static_cast<double>(m.check) * check_time))] = m.angle;
    const std::size_t n = case_list_size(case_json, file, "pile.history.measure_checks", 100);
    if (case_list_size(case_json, file, "pile.history.measure_times_s", 100) != n)
      throw util::UserError(file.string(), 0,
                            "pile.history.measure_times_s and pile.history.measure_checks differ in length");
    for (std::size_t i = 0; i < n; ++i) {
      const long k = *case_integer(case_json, file, fmt::format("pile.history.measure_checks.{}", i), 0, 1L << 50);
      const double t = *case_number(case_json, file, fmt::format("pile.history.measure_times_s.{}", i), 0, 1e4);
      const auto at = std::find_if(moments.begin(), moments.end(), [k](const PileMoment& m) { return m.check == k; });
      if (at == moments.end())
        throw pp::InputError(fmt::format("{}: no snapshot at check {} (measure time {} s): settling ended before it",
                                         folder.string(), k, t));
      if (std::isfinite(at->angle)) values[timed_observable(k_angle_at, t)] = at->angle;
    }
    const double window =
        case_number(case_json, file, "pile.angle_measurement.drift_window_s", drift_window_bounds()).value_or(0.2);
    const double limit =
        case_number(case_json, file, "pile.angle_measurement.drift_limit_deg_s", drift_limit_bounds()).value_or(1.0);
    const double drift = angle_drift(moments, window);
    if (std::isfinite(drift)) {
      values[std::string(k_angle_drift)] = drift;
      settled = settled.value_or(true) && std::abs(drift) <= limit;
    }
  }
  if (settled) values[std::string(k_settled)] = *settled ? 1.0 : 0.0;
  return values;
}

std::optional<Observable> describe(std::string_view name);

std::vector<Observable> observables(const StudyConfig& config) {
  std::vector<Observable> list{*describe(k_angle), *describe(k_pile_height)};
  for (const double t : settings(config).measure_times) list.push_back(*describe(timed_observable(k_angle_at, t)));
  return list;
}

std::optional<Observable> describe(std::string_view name) {
  const std::string n(name);
  if (name == k_angle) return Observable{n, "angle of repose", "°", 1.0, "°"};
  if (name == k_angle_sd) return Observable{n, "spread of the angle over directions", "°", 1.0, "°"};
  if (name == k_pile_height) return Observable{n, "pile height", "mm", 1e3, "m"};
  if (name == k_particles_on_pedestal) return Observable{n, "particles on the pedestal", "", 1.0, ""};
  if (name == k_removed_off_pedestal) return Observable{n, "particles removed off the pedestal", "", 1.0, ""};
  if (name == k_angle_drift) return Observable{n, "drift of the angle at the end of settling", "°/s", 1.0, "°/s"};
  if (const std::optional<TimedName> timed = timed_name(name)) {
    for (const auto& [prefix, label] : {std::pair{k_angle_at, "angle of repose"}, std::pair{k_angle_series, "angle"}})
      if (timed->family + "@" == prefix)
        return Observable{n, fmt::format("{} {} s after the last disc", label, timed->text), "°", 1.0, "°"};
  }
  return std::nullopt;
}

long removed_particles(const fs::path& folder) {
  const std::optional<PileSettling> settling = read_settling(folder);
  return settling ? settling->removed : 0;
}

std::vector<std::string> lab_observables(const StudyConfig&) { return {std::string(k_angle)}; }

std::vector<std::pair<std::string, double>> default_targets(const StudyConfig& config) {
  return {{std::string(k_angle), settings(config).target_angle}};
}

ReportFocus report_focus(const StudyConfig& config) { return {std::string(k_angle), settings(config).target_angle}; }

CaseReport case_report(const fs::path& folder, const std::string& relative, int sample, const StudyConfig& config) {
  CaseReport report;
  report.heading = fmt::format("Sample {}: the pile (paper Fig. 4)", sample);
  // As the study measured it (its case.json; a folder without one: the study's [pile] settings), so that the figure
  // shows the stored angle, against [pile]'s target.
  pp::PileAngleOptions options = angle_options(settings(config));
  std::optional<long> base;
  std::error_code ec;
  if (fs::exists(folder / k_case_json, ec)) {
    const nlohmann::json case_json = read_case_json(folder);
    options = case_angle_options(case_json, folder / k_case_json);
    options.target_angle = settings(config).target_angle;
    base = read_case_angle_settings(case_json, folder / k_case_json).base_particles;
  }
  const pp::Particles particles = without_base(pp::read_particles(folder / k_final_dump, 1), base.value_or(0));
  const pp::PileAngleResult r = pp::measure_pile_angle(particles, options);
  PileSideView view;
  view.title = fmt::format("sample {}", sample);
  view.directions = options.directions;
  view.angle_deg = r.angle;
  view.height = r.pile_height;
  view.pedestal_radius = options.pedestal_radius;
  view.pedestal_height = options.pedestal_top;
  std::vector<int> direction(particles.size(), -1);
  for (const pp::BoundaryParticle& b : r.boundary) direction[b.index] = b.direction;
  for (size_t i : pp::pedestal_particles(particles, options))
    view.particles.push_back({particles.x[i], particles.y[i], particles.z[i], particles.radius[i], direction[i]});
  // The fitted lines live in the (radial, height above the pedestal top) plane; the plot wants z.
  for (const pp::DirectionLine& l : r.lines) {
    if (!l.used) continue;
    view.lines.push_back({l.direction, l.phi, l.angle, l.radial_low, l.height_low + options.pedestal_top, l.radial_high,
                          l.height_high + options.pedestal_top});
  }
  report.paragraphs.push_back(fmt::format(
      "Case `{}`: {} particles on the pedestal, pile height h_P = {:.1f} mm, angle of repose φ = {:.2f}° "
      "(standard deviation {:.2f}° over {} of {} directions, range {:.2f}°–{:.2f}°; {}), E_φ = {:.3g} deg² "
      "against φ̂ = {:g}°.",
      relative, r.particles_on_pedestal, r.pile_height * 1e3, r.angle, r.angle_sd, r.directions_used,
      options.directions, r.angle_min, r.angle_max,
      options.estimator == pp::AngleEstimator::robust ? "robust estimator: Theil–Sen lines through the surface points"
                                                      : "the paper's estimator, §3.3",
      r.angle_error, options.target_angle));
  report.figures.push_back({fmt::format("The pile of sample {} from the side: a cross section with its boundary "
                                        "particles (coloured by direction) and fitted lines, and every "
                                        "direction's boundary particles and line unrolled onto one plane",
                                        sample),
                            "pile_side", view});
  // The pile in time, when the case measured snapshots of its settling.
  if (fs::exists(folder / k_history_csv, ec)) {
    const std::vector<PileMoment> moments = read_history(folder);
    LinePlot plot;
    plot.title = fmt::format("sample {}: the angle during settling", sample);
    plot.x_label = "time after the last disc [s]";
    plot.y_label = "angle of repose [°]";
    plot.series = {{"paper's estimator (§3.3)", {}, {}, "#1f77b4", false},
                   {"robust estimator", {}, {}, "#ff7f0e", false}};
    for (const PileMoment& m : moments) {
      if (std::isfinite(m.angle_paper)) {
        plot.series[0].x.push_back(m.time);
        plot.series[0].y.push_back(m.angle_paper);
      }
      if (std::isfinite(m.angle_robust)) {
        plot.series[1].x.push_back(m.time);
        plot.series[1].y.push_back(m.angle_robust);
      }
    }
    plot.y_reference = settings(config).target_angle;
    plot.y_reference_label = "target φ̂";
    const nlohmann::json case_json = read_case_json(folder);
    const double window =
        case_number(case_json, folder / k_case_json, "pile.angle_measurement.drift_window_s", drift_window_bounds())
            .value_or(0.2);
    report.paragraphs.push_back(fmt::format(
        "Measured at {} moments of its settling (`{}`): from {:.2f}° to {:.2f}° (the study's estimator); drift over "
        "the last {:g} s: {:+.3g}°/s.",
        moments.size(), k_history_csv, moments.front().angle, moments.back().angle, window,
        angle_drift(moments, window)));
    report.figures.push_back(
        {fmt::format("The angle of sample {} during settling, by both estimators (snapshots every [pile] "
                     "history_interval; t = 0 is the end of the last disc, which is still falling then)",
                     sample),
         "pile_history", plot});
  }
  return report;
}

/// A horizontal rectangle at height z, counter-clockwise seen from above.
pp::Surface rectangle(double x0, double x1, double y0, double y1, double z) {
  return {{{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}, {{0, 1, 2, 3}}};
}

std::vector<CaseSurface> vtk_surfaces(const fs::path& folder, const nlohmann::json&, const pp::DumpFrame& frame) {
  // The pedestal mesh LIGGGHTS used, and the ground plane z = 0 over the box.
  return {{"pedestal", pp::mesh_surface(pp::read_ascii_stl(folder / k_pedestal_stl), 0.0)},
          {"ground", rectangle(frame.box[0], frame.box[1], frame.box[2], frame.box[3], 0.0)}};
}

long particles(const StudyConfig& config) { return settings(config).particles; }
double largest_radius(const StudyConfig& config) { return settings(config).radii.r_max; }

}  // namespace

const Experiment& experiment() {
  static const Experiment descriptor{
      .name = "pile",
      .summary = "angle of repose, paper §3",
      .sections = pile_sections,
      .settings = pile_settings,
      .check = check_pile,
      .retired_keys = pile_retired_keys,
      .draft = draft_case,
      .particles = particles,
      .largest_radius = largest_radius,
      .final_dump = k_final_dump,
      .run_outputs =
          [] {
            return std::vector<std::string>{k_final_dump, k_settling};
          },
      .measure = measure,
      .observables = observables,
      .describe = describe,
      .removed_particles = removed_particles,
      .default_targets = default_targets,
      .lab_observables = lab_observables,
      .report_focus = report_focus,
      .case_report = case_report,
      .vtk_surfaces = vtk_surfaces,
      .case_cost = case_cost,
      .case_angle = pile::case_angle,
      .case_tool = {"Angle of repose and pile height of a pile dump (paper §3.3)", make_case_tool},
  };
  return descriptor;
}

}  // namespace demsa::experiments::pile
