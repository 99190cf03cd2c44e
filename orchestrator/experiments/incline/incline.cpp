#include "orchestrator/experiments/incline/incline.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/setting_row.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/error.hpp"
#include "postprocess/incline.hpp"

#include <fmt/core.h>

#include <fstream>
#include <sstream>

// The incline's descriptor: its measurement (postprocess/incline.hpp), observables, report and ParaView plate. Its
// settings are in settings.cpp, its case in case.cpp.
namespace demsa::experiments::incline {

using namespace demsa::study;

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

// settings.cpp and case.cpp
std::vector<Setting> incline_settings();
std::vector<SettingSection> incline_sections();
void check_incline(const StudyConfig& config, const SectionCheck& at);
std::unique_ptr<CaseDraft> draft_case(const StudyConfig& config, std::uint64_t assembly_seed);

namespace {

/// The measurement options a case.json records.
pp::InclineOptions case_options(const nlohmann::json& doc, const fs::path& file) {
  const auto number = [&](const std::string& key, const auto&... range) {
    const std::optional<double> v = case_number(doc, file, key, range...);
    if (!v) throw util::UserError(file.string(), 0, fmt::format("records no {} (the incline's schedule)", key));
    return *v;
  };
  const auto integer = [&](const std::string& key, long low, long high) {
    const std::optional<long> v = case_integer(doc, file, key, low, high);
    if (!v) throw util::UserError(file.string(), 0, fmt::format("records no {} (the incline's schedule)", key));
    return *v;
  };
  pp::InclineOptions o;
  o.dt = number("dt", 1e-15, 1);
  o.tilt_rate = number("incline.tilt_rate_deg_s", 1e-9, 90);
  o.tilt_start_step = integer("incline.tilt_start_step", 0, static_cast<long>(k_max_steps));
  o.gravity = number("incline.gravity_m_s2", 1e-9, 1e4);
  o.onset_distance = number("incline.onset_distance_m", onset_distance_bounds());
  o.speed_angle = number("incline.speed_angle_deg", tilt_bounds());
  o.rolling_probes = integer("incline.rolling_probes", 1, 1000);
  o.max_tilt = case_number(doc, file, "incline.max_angle_deg", tilt_bounds()).value_or(90.0);
  return o;
}

std::map<std::string, double> measure(const fs::path& folder, const nlohmann::json& case_json) {
  const fs::path file = folder / k_case_json;
  const pp::InclineResult r = pp::measure_incline(folder / k_probes_dump, case_options(case_json, file));
  std::map<std::string, double> values;
  if (r.roll_angle) values[std::string(k_roll_angle)] = *r.roll_angle;
  if (r.slide_angle) values[std::string(k_slide_angle)] = *r.slide_angle;
  if (r.roll_speed) values[std::string(k_roll_speed)] = *r.roll_speed;
  values[std::string(k_probes_rolled)] = r.rolled;
  values[std::string(k_probes_slid)] = r.slid;
  // An observable the study analyses must be measured: a median of fewer than half the probes of its kind would not
  // be the material's.
  if (case_json.contains("incline") && case_json["incline"].contains("analysed"))
    for (const nlohmann::json& name : case_json["incline"]["analysed"]) {
      if (!name.is_string() || values.count(name.get<std::string>())) continue;
      throw pp::InputError(fmt::format(
          "{}: {} not measured: {} of {} free probes rolled and {} of {} locked probes slid before the tilt ended at "
          "{:.2f} deg (more than half are needed; raise [incline] max_angle, or see {})",
          folder.string(), name.get<std::string>(), r.rolled, r.rolling_probes, r.slid, r.sliding_probes, r.last_tilt,
          k_probes_dump));
    }
  return values;
}

std::optional<Observable> describe(std::string_view name);

std::vector<Observable> observables(const StudyConfig& config) {
  // The viscous model has no static rolling resistance: its free probes roll at once, and their speed at
  // speed_angle measures μ_R,PW instead of an onset angle.
  if (config.contact.rolling_model == RollingModel::viscous) return {*describe(k_roll_speed), *describe(k_slide_angle)};
  return {*describe(k_roll_angle), *describe(k_slide_angle)};
}

std::optional<Observable> describe(std::string_view name) {
  const std::string n(name);
  if (name == k_roll_angle) return Observable{n, "rolling angle of the incline", "°", 1.0, "°"};
  if (name == k_slide_angle) return Observable{n, "sliding angle of the incline", "°", 1.0, "°"};
  if (name == k_roll_speed) return Observable{n, "rolling speed on the incline", "mm/s", 1e3, "m/s"};
  if (name == k_probes_rolled) return Observable{n, "free probes that rolled", "", 1.0, ""};
  if (name == k_probes_slid) return Observable{n, "locked probes that slid", "", 1.0, ""};
  return std::nullopt;
}

/// incline_end.txt's `removed N`; 0 when the file is not there (the run did not end).
long removed_particles(const fs::path& folder) {
  const fs::path file = folder / k_end;
  std::ifstream in(file);
  std::string line;
  for (long number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string key;
    double value = 0;
    if (!(words >> key)) continue;
    if (!(words >> value))
      throw pp::ParseError(file.string(), number, fmt::format("expected 'key number', got '{}'", line));
    if (key == "removed") return static_cast<long>(value);
  }
  return 0;
}

std::vector<std::string> lab_observables(const StudyConfig& config) {
  std::vector<std::string> names;
  for (const Observable& o : observables(config)) names.push_back(o.name);
  return names;
}

std::vector<std::pair<std::string, double>> default_targets(const StudyConfig& config) {
  throw util::UserError(fmt::format(
      "{}: an incline study has no target of its own; give the measured angles, e.g. CalibrateOptions.targets "
      "roll_angle=12±0.5 CalibrateOptions.targets slide_angle=35±1",
      config.file.string()));
}

ReportFocus report_focus(const StudyConfig&) { return {std::string(k_slide_angle), std::nullopt}; }

CaseReport case_report(const fs::path& folder, const std::string& relative, int sample, const StudyConfig&) {
  const nlohmann::json doc = read_case_json(folder);
  const pp::InclineOptions options = case_options(doc, folder / k_case_json);
  const pp::InclineResult r = pp::measure_incline(folder / k_probes_dump, options);
  CaseReport report;
  report.heading = fmt::format("Sample {}: the incline", sample);
  const auto shown = [](const std::optional<double>& v, const char* format) {
    return v ? fmt::format(fmt::runtime(format), *v) : std::string("not measured");
  };
  report.paragraphs.push_back(fmt::format(
      "Case `{}`: {} of {} free probes rolled, median onset {}; {} of {} locked probes slid, median onset {}; the free "
      "probes' median speed at {:g}° was {}. Onsets: the tilt at which a probe had moved {:g} mm down the slope, less "
      "the lag of its start from rest at {:g} deg/s.",
      relative, r.rolled, r.rolling_probes, shown(r.roll_angle, "{:.2f}°"), r.slid, r.sliding_probes,
      shown(r.slide_angle, "{:.2f}°"), options.speed_angle, shown(r.roll_speed, "{:.4f} m/s"),
      options.onset_distance * 1e3, options.tilt_rate));
  LinePlot plot;
  plot.title = fmt::format("sample {}: probes down the slope", sample);
  plot.x_label = "tilt [deg]";
  plot.y_label = "down-slope displacement [mm]";
  bool rolling_named = false, sliding_named = false;
  for (const pp::InclineProbe& p : r.probes) {
    LinePlot::Series s;
    s.colour = p.rolling ? "#1f77b4" : "#d62728";
    if (p.rolling && !rolling_named) s.name = "free probes (roll)", rolling_named = true;
    if (!p.rolling && !sliding_named) s.name = "locked probes (slide)", sliding_named = true;
    for (std::size_t i = 0; i < p.tilt.size(); ++i) {
      // The curves up to a few onset distances: their start is what the onset reads.
      if (p.displacement[i] > 5 * options.onset_distance) break;
      s.x.push_back(p.tilt[i]);
      s.y.push_back(p.displacement[i] * 1e3);
    }
    plot.series.push_back(std::move(s));
  }
  plot.y_reference = options.onset_distance * 1e3;
  plot.y_reference_label = "onset distance";
  report.figures.push_back({fmt::format("The probes of sample {}: displacement down the slope against the tilt; "
                                        "blue the free probes, red the rotation-locked ones",
                                        sample),
                            "incline_probes", plot});
  return report;
}

std::vector<CaseSurface> vtk_surfaces(const fs::path&, const nlohmann::json&, const pp::DumpFrame& frame) {
  // The plate z = 0 over the box, in the plate's frame (gravity turned, the plate level).
  const pp::Surface plate{{{frame.box[0], frame.box[2], 0.0},
                           {frame.box[1], frame.box[2], 0.0},
                           {frame.box[1], frame.box[3], 0.0},
                           {frame.box[0], frame.box[3], 0.0}},
                          {{0, 1, 2, 3}}};
  return {{"plate", plate}};
}

long particles(const StudyConfig& config) { return settings(config).rolling_probes + settings(config).sliding_probes; }
double largest_radius(const StudyConfig& config) { return settings(config).radii.r_max; }

}  // namespace

const Experiment& experiment() {
  static const Experiment descriptor{
      .name = "incline",
      .summary = "rolling and sliding angles on a tilting plate of the wall material",
      .sections = incline_sections,
      .settings = incline_settings,
      .check = check_incline,
      .draft = draft_case,
      .particles = particles,
      .largest_radius = largest_radius,
      .final_dump = k_final_dump,
      .run_outputs =
          [] {
            return std::vector<std::string>{k_final_dump, k_probes_dump, k_end};
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

}  // namespace demsa::experiments::incline
