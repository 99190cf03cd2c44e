#include "orchestrator/experiments/drawdown/drawdown.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/observables.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/drawdown.hpp"
#include "postprocess/error.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

// The draw-down's descriptor: its measurement (postprocess/drawdown.hpp), observables, report and ParaView walls. Its
// settings are in settings.cpp, its case in case.cpp.
namespace demsa::experiments::drawdown {

using namespace demsa::study;

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

// settings.cpp and case.cpp
std::vector<Setting> drawdown_settings();
std::vector<SettingSection> drawdown_sections();
void check_drawdown(const StudyConfig& config, const SectionCheck& at);
std::unique_ptr<CaseDraft> draft_case(const StudyConfig& config, std::uint64_t assembly_seed);

namespace {

/// drawdown_end.txt: `key number` lines.
std::map<std::string, double> read_end(const fs::path& folder) {
  const fs::path file = folder / k_end;
  std::ifstream in(file);
  if (!in) throw pp::ParseError(file.string(), 0, "missing: the run did not end");
  std::map<std::string, double> values;
  std::string line;
  for (long number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string key;
    double value = 0;
    if (!(words >> key)) continue;
    if (!(words >> value))
      throw pp::ParseError(file.string(), number, fmt::format("expected 'key number', got '{}'", line));
    values[key] = value;
  }
  for (const char* key : {"stopped", "fill_mass", "discharged", "removed"})
    if (!values.count(key)) throw pp::ParseError(file.string(), 0, fmt::format("no '{}' line", key));
  return values;
}

struct CaseGeometry {
  pp::DrawdownSlopeOptions slope;
  double density = 2500;
  double fill_mass = 0;
};

CaseGeometry case_geometry(const nlohmann::json& doc, const fs::path& file) {
  const auto number = [&](const std::string& key, const auto&... range) {
    const std::optional<double> v = case_number(doc, file, key, range...);
    if (!v) throw util::UserError(file.string(), 0, fmt::format("records no {} (the draw-down's geometry)", key));
    return *v;
  };
  CaseGeometry g;
  g.slope.width = number("drawdown.width_m", 1e-9, 100);
  g.slope.slot_width = number("drawdown.slot_width_m", 1e-9, 100);
  g.slope.depth = number("drawdown.depth_m", 1e-9, 100);
  g.slope.skip_ids = case_integer(doc, file, "drawdown.floor_particles", 0, 100000000).value_or(0);
  g.slope.slices = static_cast<int>(case_integer(doc, file, "drawdown.measurement.slices", 1, 1000).value_or(5));
  g.slope.bin_width = number("drawdown.measurement.bin_width_m", bin_width_bounds());
  g.slope.edge_skip = number("drawdown.measurement.edge_skip_m", 0, 1);
  g.slope.wall_skip = number("drawdown.measurement.wall_skip_m", 0, 1);
  g.density = number("drawdown.density", 1e-9, 1e6);
  g.fill_mass = number("drawdown.fill_mass_kg", 0, 1e9);
  return g;
}

std::map<std::string, double> measure(const fs::path& folder, const nlohmann::json& case_json) {
  const CaseGeometry g = case_geometry(case_json, folder / k_case_json);
  const std::map<std::string, double> end = read_end(folder);
  const pp::DrawdownSlope slope =
      pp::measure_drawdown_slope(pp::read_particles(folder / k_final_dump, 1), g.slope, g.density);
  const pp::DischargeRecord record = pp::read_discharge(folder / k_discharge);
  std::map<std::string, double> values;
  values[std::string(k_slope_angle)] = slope.angle;
  values["slope_angle_left"] = slope.angle_left;
  values["slope_angle_right"] = slope.angle_right;
  values[std::string(k_discharged_mass)] = end.at("discharged");
  values[std::string(k_discharge_rate)] = pp::discharge_rate(record);
  values[std::string(k_retained_fraction)] = end.at("fill_mass") > 0 ? slope.mass_left / end.at("fill_mass") : 0.0;
  values[std::string(k_settled)] = end.at("stopped") > 0 ? 1.0 : 0.0;
  return values;
}

std::optional<Observable> describe(std::string_view name) {
  const std::string n(name);
  if (name == k_slope_angle) return Observable{n, "draw-down slope angle", "°", 1.0, "°"};
  if (name == "slope_angle_left") return Observable{n, "draw-down slope angle, left side", "°", 1.0, "°"};
  if (name == "slope_angle_right") return Observable{n, "draw-down slope angle, right side", "°", 1.0, "°"};
  if (name == k_discharged_mass) return Observable{n, "discharged mass", "g", 1e3, "kg"};
  if (name == k_discharge_rate) return Observable{n, "discharge rate", "g/s", 1e3, "kg/s"};
  if (name == k_retained_fraction) return Observable{n, "share of the fill left in the box", "", 1.0, ""};
  return std::nullopt;
}

std::vector<Observable> observables(const StudyConfig&) {
  return {*describe(k_slope_angle), *describe(k_discharged_mass), *describe(k_discharge_rate)};
}

long removed_particles(const fs::path& folder) {
  if (!fs::exists(folder / k_end)) return 0;
  return static_cast<long>(read_end(folder).at("removed"));
}

/// The slope left in the box and the mass that ran out (a discharge rate needs a load cell under the outlet).
std::vector<std::string> lab_observables(const StudyConfig&) {
  return {std::string(k_slope_angle), std::string(k_discharged_mass)};
}

std::vector<std::pair<std::string, double>> default_targets(const StudyConfig& config) {
  throw util::UserError(fmt::format(
      "{}: a draw-down study has no target of its own; give the measured values, e.g. CalibrateOptions.targets "
      "slope_angle=38±2 CalibrateOptions.targets discharged_mass=0.06±0.002",
      config.file.string()));
}

ReportFocus report_focus(const StudyConfig&) { return {std::string(k_slope_angle), std::nullopt}; }

CaseReport case_report(const fs::path& folder, const std::string& relative, int sample, const StudyConfig&) {
  const nlohmann::json doc = read_case_json(folder);
  const CaseGeometry g = case_geometry(doc, folder / k_case_json);
  const std::map<std::string, double> values = measure(folder, doc);
  const pp::DrawdownSlope slope =
      pp::measure_drawdown_slope(pp::read_particles(folder / k_final_dump, 1), g.slope, g.density);
  const pp::DischargeRecord record = pp::read_discharge(folder / k_discharge);
  CaseReport report;
  report.heading = fmt::format("Sample {}: the draw-down", sample);
  report.paragraphs.push_back(fmt::format(
      "Case `{}`: slope angle {:.2f}° (left {:.2f}°, right {:.2f}°; medians over {} slices), {:.1f} g discharged "
      "({:.1f} % of the fill left in the box) at {:.1f} g/s between 20 % and 80 % of it{}.",
      relative, slope.angle, slope.angle_left, slope.angle_right, g.slope.slices, values.at("discharged_mass") * 1e3,
      100 * values.at("retained_fraction"), values.at("discharge_rate") * 1e3,
      values.at("settled") > 0 ? "" : "; the flow had not stopped at the time cap"));
  LinePlot profile;
  profile.title = fmt::format("sample {}: the surface left in the box", sample);
  profile.x_label = "x across the slot [mm]";
  profile.y_label = "surface height [mm]";
  LinePlot::Series points{"surface points (every slice)", {}, {}, "#1f77b4", true};
  for (std::size_t i = 0; i < slope.profile_x.size(); ++i) {
    points.x.push_back(slope.profile_x[i] * 1e3);
    points.y.push_back(slope.profile_z[i] * 1e3);
  }
  profile.series.push_back(points);
  // Each side's measured angle drawn through the median of the points it fits (a check by eye of the fit).
  const double inner = g.slope.slot_width / 2 + g.slope.edge_skip, outer = g.slope.width / 2 - g.slope.wall_skip;
  for (const int side : {-1, 1}) {
    std::vector<double> xs, zs;
    for (std::size_t i = 0; i < slope.profile_x.size(); ++i) {
      const double along = side * slope.profile_x[i];
      if (along >= inner && along <= outer) xs.push_back(slope.profile_x[i]), zs.push_back(slope.profile_z[i]);
    }
    if (xs.empty()) continue;
    const auto median = [](std::vector<double> v) {
      std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
      return v[v.size() / 2];
    };
    const double x0 = median(xs), z0 = median(zs);
    const double tangent = std::tan((side < 0 ? slope.angle_left : slope.angle_right) * std::numbers::pi / 180.0);
    LinePlot::Series line{side < 0 ? "measured angle, left" : "measured angle, right", {}, {}, "#d62728"};
    for (const double x : {side * inner, side * outer}) {
      line.x.push_back(x * 1e3);
      line.y.push_back((z0 + side * (x - x0) * tangent) * 1e3);
    }
    profile.series.push_back(std::move(line));
  }
  report.figures.push_back({fmt::format("The surface of the material left in the box of sample {}: the highest "
                                        "particle top per bin of every slice across the slope",
                                        sample),
                            "drawdown_surface", profile});
  LinePlot flow;
  flow.title = fmt::format("sample {}: discharge", sample);
  flow.x_label = "time since the slot opened [s]";
  flow.y_label = "discharged mass [g]";
  LinePlot::Series mass{"discharged", record.time, {}, "#d62728"};
  for (const double m : record.mass) mass.y.push_back(m * 1e3);
  flow.series.push_back(std::move(mass));
  report.figures.push_back(
      {fmt::format("The mass discharged from the box of sample {} against time", sample), "drawdown_discharge", flow});
  return report;
}

std::vector<CaseSurface> vtk_surfaces(const fs::path& folder, const nlohmann::json& case_json, const pp::DumpFrame&) {
  const CaseGeometry g = case_geometry(case_json, folder / k_case_json);
  const double h = g.slope.width / 2, s = g.slope.slot_width / 2, d = g.slope.depth, top = 0.1;
  const auto quad = [](std::array<double, 3> a, std::array<double, 3> b, std::array<double, 3> c,
                       std::array<double, 3> e) {
    return pp::Surface{{a, b, c, e}, {{0, 1, 2, 3}}};
  };
  return {{"floor_left", quad({-h, 0, 0}, {-s, 0, 0}, {-s, d, 0}, {-h, d, 0})},
          {"floor_right", quad({s, 0, 0}, {h, 0, 0}, {h, d, 0}, {s, d, 0})},
          {"wall_left", quad({-h, 0, 0}, {-h, d, 0}, {-h, d, top}, {-h, 0, top})},
          {"wall_right", quad({h, 0, 0}, {h, 0, top}, {h, d, top}, {h, d, 0})}};
}

long particles(const StudyConfig& config) {
  // The fill; a floor layer's count is known once its case is drawn (the runner takes the case's own count).
  return settings(config).particles;
}
double largest_radius(const StudyConfig& config) { return settings(config).radii.r_max; }

}  // namespace

const Experiment& experiment() {
  static const Experiment descriptor{
      .name = "drawdown",
      .summary = "slope angle and discharge of a box emptying through a floor slot",
      .sections = drawdown_sections,
      .settings = drawdown_settings,
      .check = check_drawdown,
      .draft = draft_case,
      .particles = particles,
      .largest_radius = largest_radius,
      .final_dump = k_final_dump,
      .run_outputs =
          [] {
            return std::vector<std::string>{k_final_dump, k_discharge, k_end};
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
  };
  return descriptor;
}

}  // namespace demsa::experiments::drawdown
