#include "orchestrator/experiments/pile/pile.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/observables.hpp"
#include "orchestrator/study/setting_row.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/error.hpp"
#include "postprocess/stl.hpp"

#include <fmt/core.h>

#include <fstream>
#include <map>
#include <sstream>

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

pp::PileAngleOptions case_angle_options(const nlohmann::json& doc, const fs::path& file) {
  const CaseAngleSettings s = read_case_angle_settings(doc, file);
  for (const auto& [value, key] :
       {std::pair{s.pedestal_radius, "pile.pedestal_radius_m"}, std::pair{s.pedestal_top, "pile.pedestal_height_m"}})
    if (!value) throw util::UserError(file.string(), 0, fmt::format("records no {} (the pile's pedestal)", key));
  pp::PileAngleOptions options;
  options.pedestal_radius = *s.pedestal_radius;
  options.pedestal_top = *s.pedestal_top;
  if (s.directions) options.directions = *s.directions;
  if (s.levels) options.levels = *s.levels;
  if (s.estimator) options.estimator = *s.estimator;
  // A pile on a base layer stands on the layer: heights and levels start at its mean top.
  if (s.base_top) options.pedestal_top = *s.base_top;
  return options;
}

pp::Particles without_base(const pp::Particles& particles, long base_particles) {
  if (base_particles <= 0) return particles;
  pp::Particles pile;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.id[i] <= base_particles) continue;
    pile.id.push_back(particles.id[i]);
    pile.type.push_back(particles.type[i]);
    pile.x.push_back(particles.x[i]);
    pile.y.push_back(particles.y[i]);
    pile.z.push_back(particles.z[i]);
    pile.radius.push_back(particles.radius[i]);
  }
  return pile;
}

namespace {

std::map<std::string, double> measure(const fs::path& folder, const nlohmann::json& case_json) {
  const pp::PileAngleOptions options = case_angle_options(case_json, folder / k_case_json);
  const std::optional<long> base = read_case_angle_settings(case_json, folder / k_case_json).base_particles;
  const pp::Particles particles = without_base(pp::read_particles(folder / k_final_dump, 1), base.value_or(0));
  const pp::PileAngleResult result = pp::measure_pile_angle(particles, options);
  std::map<std::string, double> values;
  values[std::string(k_angle)] = result.angle;
  values[std::string(k_pile_height)] = result.pile_height;
  values[std::string(k_angle_sd)] = result.angle_sd;
  values[std::string(k_particles_on_pedestal)] = static_cast<double>(result.particles_on_pedestal);
  if (const std::optional<PileSettling> settling = read_settling(folder)) {
    if (settling->criterion) values[std::string(k_settled)] = settling->settled ? 1.0 : 0.0;
    values[std::string(k_removed_off_pedestal)] = static_cast<double>(settling->removed);
  }
  return values;
}

std::optional<Observable> describe(std::string_view name);

std::vector<Observable> observables(const StudyConfig&) { return {*describe(k_angle), *describe(k_pile_height)}; }

std::optional<Observable> describe(std::string_view name) {
  const std::string n(name);
  if (name == k_angle) return Observable{n, "angle of repose", "°", 1.0, "°"};
  if (name == k_angle_sd) return Observable{n, "spread of the angle over directions", "°", 1.0, "°"};
  if (name == k_pile_height) return Observable{n, "pile height", "mm", 1e3, "m"};
  if (name == k_particles_on_pedestal) return Observable{n, "particles on the pedestal", "", 1.0, ""};
  if (name == k_removed_off_pedestal) return Observable{n, "particles removed off the pedestal", "", 1.0, ""};
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
std::string driver_command(const StudyConfig&) { return {}; }

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
      .limit_violations = nullptr,
      .driver_command = driver_command,
      .drivers = [] { return std::vector<Driver>{}; },
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
      .check_outputs = nullptr,
      .default_targets = default_targets,
      .lab_observables = lab_observables,
      .report_focus = report_focus,
      .case_report = case_report,
      .vtk_surfaces = vtk_surfaces,
      .case_cost = case_cost,
  };
  return descriptor;
}

}  // namespace demsa::experiments::pile
