#include "orchestrator/experiments/drum/drum.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/setting_row.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/dump.hpp"
#include "postprocess/error.hpp"

#include <fmt/core.h>
#include <toml++/toml.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

// The drum's descriptor: its measurement (postprocess/drum.hpp), observables, report and ParaView wall, and the
// measurement of a laboratory photograph by the same code. Its settings are in settings.cpp, its case in case.cpp.
namespace demsa::experiments::drum {

using namespace demsa::study;

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

// settings.cpp and case.cpp
std::vector<Setting> drum_settings();
std::vector<SettingSection> drum_sections();
void check_drum(const StudyConfig& config, const SectionCheck& at);
std::unique_ptr<CaseDraft> draft_case(const StudyConfig& config, std::uint64_t assembly_seed);

namespace {

/// What a case.json records of the drum's measurement.
struct CaseRecord {
  double radius = 0;
  pp::DrumRotation rotation = pp::DrumRotation::clockwise;
  int image_size = 406;
  pp::DrumSurfaceOptions surface;
  double period = 0;
  long turning_steps = 0;  ///< spin-up and window
  double dt = 0;
  int wall_sides = 0;
  double depth = 0;
};

CaseRecord case_record(const nlohmann::json& doc, const fs::path& file) {
  const auto number = [&](const std::string& key, double low, double high) {
    const std::optional<double> v = case_number(doc, file, key, low, high);
    if (!v) throw util::UserError(file.string(), 0, fmt::format("records no {} (the drum's case)", key));
    return *v;
  };
  const auto integer = [&](const std::string& key, long low, long high) {
    const std::optional<long> v = case_integer(doc, file, key, low, high);
    if (!v) throw util::UserError(file.string(), 0, fmt::format("records no {} (the drum's case)", key));
    return *v;
  };
  CaseRecord r;
  r.radius = number("drum.radius_m", 1e-6, 100);
  r.depth = number("drum.depth_m", 1e-6, 100);
  const std::optional<std::string> rotation = case_string(doc, file, "drum.rotation");
  if (!rotation) throw util::UserError(file.string(), 0, "records no drum.rotation (the drum's case)");
  try {
    r.rotation = pp::drum_rotation_from_string(*rotation);
  } catch (const std::invalid_argument& e) {
    throw util::UserError(file.string(), 0, fmt::format("drum.rotation = \"{}\": {}", *rotation, e.what()));
  }
  r.image_size = static_cast<int>(integer("drum.measurement.image_size", 32, 4096));
  r.surface.judged_radius = number("drum.measurement.judged_radius", 0, 1);
  r.surface.angle_half_width = number("drum.measurement.angle_half_width", 0, 1);
  r.surface.threshold = number("drum.measurement.threshold", 0, 1);
  r.surface.stations.clear();
  const std::size_t n = case_list_size(doc, file, "drum.measurement.stations", 1000);
  for (std::size_t i = 0; i < n; ++i)
    r.surface.stations.push_back(number(fmt::format("drum.measurement.stations.{}", i), -1, 1));
  try {
    r.surface.validate();
  } catch (const std::invalid_argument& e) {
    throw util::UserError(file.string(), 0, fmt::format("drum.measurement: {}", e.what()));
  }
  r.period = number("drum.period_s", 1e-9, 1e9);
  r.turning_steps = integer("drum.spin_up_steps", 0, static_cast<long>(k_max_steps)) +
                    integer("drum.window_steps", 0, static_cast<long>(k_max_steps));
  r.dt = number("dt", 1e-15, 1);
  r.wall_sides = static_cast<int>(integer("drum.wall_sides", 3, 100000));
  return r;
}

/// The case's side view: every snapshot of drum_snapshots.dump projected onto the camera's picture (x → picture x,
/// z → picture up, the drum's centre at x = z = 0) and averaged.
pp::DrumOccupancy side_view(const fs::path& folder, const CaseRecord& r) {
  pp::DrumOccupancy occupancy(r.image_size, r.radius, r.rotation);
  pp::DumpReaderOptions options;
  options.required_columns = {"id", "type", "x", "z", "radius"};
  pp::DumpReader reader(folder / k_snapshots_dump, options);
  pp::DumpFrame frame;
  while (reader.next(frame)) {
    const pp::Particles p = pp::particles_from_frame(frame, 1);
    occupancy.add_snapshot(p.x, p.z, p.radius);
  }
  return occupancy;
}

struct CaseMeasurement {
  pp::DrumImage image;
  pp::DrumSurfaceResult surface;
  int snapshots = 0;
};

CaseMeasurement measure_case(const fs::path& folder, const CaseRecord& r) {
  CaseMeasurement m;
  const pp::DrumOccupancy occupancy = side_view(folder, r);
  m.image = occupancy.image();
  m.snapshots = occupancy.snapshots();
  m.surface = pp::measure_drum_surface(m.image, r.surface);
  pp::write_grey_png(folder / k_occupancy_png, m.image.material);
  pp::write_rgb_png(folder / k_surface_png, pp::drum_surface_overlay(m.image, m.surface, r.surface));
  return m;
}

std::map<std::string, double> measure(const fs::path& folder, const nlohmann::json& case_json) {
  const CaseRecord r = case_record(case_json, folder / k_case_json);
  const CaseMeasurement m = measure_case(folder, r);
  std::map<std::string, double> values = observable_values(m.surface);
  values[std::string(k_snapshots)] = m.snapshots;
  // An observable the study analyses must be measured.
  if (case_json.contains("drum") && case_json["drum"].contains("analysed"))
    for (const nlohmann::json& name : case_json["drum"]["analysed"])
      if (name.is_string() && !values.count(name.get<std::string>()))
        throw pp::InputError(fmt::format(
            "{}: {} not measured: the free surface does not reach its station within the judged circle (see {})",
            folder.string(), name.get<std::string>(), k_occupancy_png));
  return values;
}

std::optional<Observable> describe(std::string_view name);

std::vector<Observable> observables(const StudyConfig& config) {
  const DrumSettings& s = settings(config);
  std::vector<Observable> list{*describe(k_dynamic_angle)};
  for (std::size_t i = 0; i < s.stations.size(); ++i) {
    Observable o = *describe(fmt::format("{}{}", k_surface_prefix, i + 1));
    o.label = fmt::format("surface height at x = {:+.2f} R", s.stations[i]);
    list.push_back(o);
  }
  list.push_back(*describe(k_s_shape));
  list.push_back(*describe(k_fill_fraction));
  return list;
}

std::optional<Observable> describe(std::string_view name) {
  const std::string n(name);
  if (name == k_dynamic_angle) return Observable{n, "dynamic angle of the drum's surface", "°", 1.0, "°"};
  if (name == k_s_shape) return Observable{n, "S shape of the drum's surface", "mm", 1e3, "m"};
  if (name == k_fill_fraction) return Observable{n, "drum cross-section filled by the bed", "", 1.0, ""};
  if (name == k_angle_uncertainty) return Observable{n, "uncertainty of the dynamic angle", "°", 1.0, "°"};
  if (name == k_snapshots) return Observable{n, "snapshots of the drum averaged", "", 1.0, ""};
  if (name.starts_with(k_surface_prefix)) {
    const std::string_view rest = name.substr(k_surface_prefix.size());
    if (!rest.empty() && rest.size() < 5 && rest.find_first_not_of("0123456789") == std::string_view::npos &&
        rest[0] != '0')
      return Observable{n, fmt::format("surface height at station {}", rest), "mm", 1e3, "m"};
  }
  return std::nullopt;
}

std::vector<std::string> lab_observables(const StudyConfig& config) {
  // What a photograph gives: the angle and the surface's heights (a photograph's fill depends on how much was
  // poured, its S shape is a derived number of the same surface).
  std::vector<std::string> names{std::string(k_dynamic_angle)};
  for (std::size_t i = 0; i < settings(config).stations.size(); ++i)
    names.push_back(fmt::format("{}{}", k_surface_prefix, i + 1));
  return names;
}

std::vector<std::pair<std::string, double>> default_targets(const StudyConfig& config) {
  throw util::UserError(fmt::format(
      "{}: a drum study has no target of its own; measure the photograph (as `demsa measure IMAGE` does) and give "
      "its values, e.g. CalibrateOptions.targets dynamic_angle=38.2±0.5 CalibrateOptions.targets "
      "surface_1=0.0123±0.0005",
      config.file.string()));
}

ReportFocus report_focus(const StudyConfig&) { return {std::string(k_dynamic_angle), std::nullopt}; }

CaseReport case_report(const fs::path& folder, const std::string& relative, int sample, const StudyConfig&) {
  const nlohmann::json doc = read_case_json(folder);
  const CaseRecord record = case_record(doc, folder / k_case_json);
  const CaseMeasurement m = measure_case(folder, record);
  const pp::DrumSurfaceResult& r = m.surface;
  CaseReport report;
  report.heading = fmt::format("Sample {}: the rotating drum", sample);
  report.paragraphs.push_back(fmt::format(
      "Case `{}`: dynamic angle {:.2f}° ± {:.2f}°, S shape {:.2f} mm, {:.1f} % of the cross-section filled; the side "
      "view averages the snapshots of `{}` as the camera sees them through the end plate ({}).",
      relative, r.dynamic_angle, r.angle_uncertainty, r.s_shape * 1e3, 100 * r.fill_fraction, k_snapshots_dump,
      pp::to_string(record.rotation)));
  report.figures.push_back(
      {fmt::format("Sample {}: the time-averaged side view as the camera sees it ({} × {} pixels spanning the inner "
                   "diameter; material dark), its free surface (red) between the band's edges (yellow), the dynamic "
                   "angle's line (green), the stations (magenta) and the judged circle (cyan)",
                   sample, record.image_size, record.image_size),
       "drum_side_view", ImageFigure{(folder / k_surface_png).string()}});
  LinePlot plot;
  plot.title = fmt::format("sample {}: the free surface", sample);
  plot.x_label = "x [mm]";
  plot.y_label = "height [mm]";
  LinePlot::Series surface{"surface", {}, {}, "#1f77b4", false};
  LinePlot::Series low{"band", {}, {}, "#9ecae1", false}, high{"", {}, {}, "#9ecae1", false};
  for (const pp::SurfacePoint& p : r.surface) {
    surface.x.push_back(p.x * 1e3);
    surface.y.push_back(p.height * 1e3);
    low.x.push_back(p.x * 1e3);
    low.y.push_back((p.height - p.band / 2) * 1e3);
    high.x.push_back(p.x * 1e3);
    high.y.push_back((p.height + p.band / 2) * 1e3);
  }
  LinePlot::Series stations{"stations", {}, {}, "#d62728", true};
  for (const pp::SurfacePoint& p : r.stations) {
    stations.x.push_back(p.x * 1e3);
    stations.y.push_back(p.height * 1e3);
  }
  plot.series = {low, high, surface, stations};
  report.figures.push_back({fmt::format("Sample {}: the free surface within the judged radius, its band (fluctuation) "
                                        "and the stations",
                                        sample),
                            "drum_surface", plot});
  return report;
}

std::vector<CaseSurface> vtk_surfaces(const fs::path& folder, const nlohmann::json& case_json, const pp::DumpFrame&) {
  const CaseRecord r = case_record(case_json, folder / k_case_json);
  // The wall as it stands at the end: turned by 2π t / period about +y (right-hand rule; −y for counterclockwise).
  const double turns = static_cast<double>(r.turning_steps) * r.dt / r.period;
  const double angle = 2 * std::numbers::pi * turns * (r.rotation == pp::DrumRotation::clockwise ? 1.0 : -1.0);
  const double c = std::cos(angle), s = std::sin(angle);
  pp::Surface wall;
  for (const Triangle& t : drum_mesh(r.radius, r.depth, r.wall_sides)) {
    std::vector<std::size_t> polygon;
    for (const Vertex& v : t) {
      polygon.push_back(wall.points.size());
      wall.points.push_back({v[0] * c + v[2] * s, v[1], -v[0] * s + v[2] * c});
    }
    wall.polygons.push_back(std::move(polygon));
  }
  return {{"drum", wall}};
}

long particles(const StudyConfig& config) { return fill_count(settings(config)); }
double largest_radius(const StudyConfig& config) {
  const DrumSettings& s = settings(config);
  double r = s.radii.r_max;
  if (!s.diameters.empty()) r = *std::max_element(s.diameters.begin(), s.diameters.end()) / 2;
  return r * s.coarse_grain;
}

std::vector<std::string> limit_violations(const StudyConfig& config, const Material&, const TimestepChoice& ts) {
  const DrumSettings& s = settings(config);
  // The neighbour lists of a moving mesh stay valid while its nodes travel less than half the skin per step.
  const double travel = 2 * std::numbers::pi * s.rpm / 60.0 * polygon_vertex_radius(s.radius, s.wall_sides) * ts.dt;
  if (travel > config.timestep.skin / 2)
    return {
        fmt::format("the drum's wall travels {:.3g} m per time step, more than half the neighbour skin ({:.3g} m): "
                    "raise [timestep] skin or lower the time step",
                    travel, config.timestep.skin)};
  return {};
}

/// A run that ended cleanly without its snapshots (a window cut by hand, a disk full) has nothing to measure.
std::optional<OutputProblem> check_outputs(const fs::path& folder, const StudyConfig&) {
  std::error_code ec;
  const fs::path file = folder / k_snapshots_dump;
  if (!fs::is_regular_file(file, ec) || fs::file_size(file, ec) == 0 || ec)
    return OutputProblem{FailureClass::missing_dump,
                         fmt::format("{}: no snapshots of the turning drum to average", file.string())};
  return std::nullopt;
}

// ---------------------------------------------------------------- the photograph's geometry file

[[noreturn]] void fail_at(const fs::path& file, const toml::node& node, const std::string& message) {
  throw util::UserError(file.string(), static_cast<long>(node.source().begin.line), message);
}

}  // namespace

std::map<std::string, double> observable_values(const pp::DrumSurfaceResult& r) {
  std::map<std::string, double> values;
  values[std::string(k_dynamic_angle)] = r.dynamic_angle;
  values[std::string(k_angle_uncertainty)] = r.angle_uncertainty;
  // A station without a surface on both sides (a surface that leaves the judged circle there) has no height.
  for (std::size_t i = 0; i < r.stations.size(); ++i)
    if (std::isfinite(r.stations[i].height))
      values[fmt::format("{}{}", k_surface_prefix, i + 1)] = r.stations[i].height;
  values[std::string(k_s_shape)] = r.s_shape;
  values[std::string(k_fill_fraction)] = r.fill_fraction;
  return values;
}

std::optional<fs::path> photograph_geometry_file(const fs::path& image) {
  const fs::path beside = fs::path(image.string() + ".drum.toml");
  if (fs::is_regular_file(beside)) return beside;
  const fs::path folder = image.parent_path().empty() ? fs::path(".") : image.parent_path();
  if (fs::is_regular_file(folder / "drum.toml")) return folder / "drum.toml";
  return std::nullopt;
}

PhotographSettings read_photograph_settings(const fs::path& file) {
  toml::table root;
  try {
    root = toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    throw util::UserError(file.string(), static_cast<long>(e.source().begin.line), std::string(e.description()));
  }
  PhotographSettings s;
  s.surface.stations = DrumSettings{}.stations;
  bool radius_given = false, centre_given = false;
  const auto number = [&](const toml::node& node, const std::string& key, double low, double high) {
    const std::optional<double> v = node.value<double>();
    if (!v) fail_at(file, node, fmt::format("{}: expected a number", key));
    if (!(std::isfinite(*v) && *v >= low && *v <= high))
      fail_at(file, node, fmt::format("{} = {}: must lie in [{}, {}]", key, *v, low, high));
    return *v;
  };
  const auto boolean = [&](const toml::node& node, const std::string& key) {
    const std::optional<bool> v = node.value<bool>();
    if (!v) fail_at(file, node, fmt::format("{}: expected true or false", key));
    return *v;
  };
  for (const auto& [k, node] : root) {
    const std::string key(k.str());
    if (key == "preset") {
      const std::optional<std::string> v = node.value<std::string>();
      if (!v || *v != "granudrum")
        fail_at(file, node, fmt::format("preset = {}: unknown preset (valid: granudrum)", v ? *v : "?"));
      s.radius_m = 0.042;
      s.spans_diameter = true;
      radius_given = true;
    } else if (key == "radius") {
      s.radius_m = number(node, key, 1e-4, 100);
      radius_given = true;
    } else if (key == "spans_diameter") {
      s.spans_diameter = boolean(node, key);
    } else if (key == "centre_col") {
      s.centre_col = number(node, key, -1e6, 1e6), centre_given = true;
    } else if (key == "centre_row") {
      s.centre_row = number(node, key, -1e6, 1e6), centre_given = true;
    } else if (key == "radius_px") {
      s.radius_px = number(node, key, 1, 1e6), centre_given = true;
    } else if (key == "rotation") {
      const std::optional<std::string> v = node.value<std::string>();
      try {
        if (!v) throw std::invalid_argument("expected a string");
        s.rotation = pp::drum_rotation_from_string(*v);
      } catch (const std::invalid_argument& e) {
        fail_at(file, node, fmt::format("rotation = {}: {}", v ? *v : "?", e.what()));
      }
    } else if (key == "dark_material") {
      s.dark_material = boolean(node, key);
    } else if (key == "judged_radius") {
      s.surface.judged_radius = number(node, key, 1e-6, 1);
    } else if (key == "angle_half_width") {
      s.surface.angle_half_width = number(node, key, 1e-6, 1);
    } else if (key == "threshold") {
      s.surface.threshold = number(node, key, 1e-6, 1 - 1e-6);
    } else if (key == "stations") {
      const toml::array* list = node.as_array();
      if (!list || list->empty()) fail_at(file, node, "stations: expected a list of numbers");
      s.surface.stations.clear();
      for (const toml::node& x : *list) s.surface.stations.push_back(number(x, key, -1, 1));
    } else {
      fail_at(file, node,
              fmt::format("unknown key '{}' (valid: preset, radius, spans_diameter, centre_col, centre_row, "
                          "radius_px, rotation, dark_material, judged_radius, angle_half_width, stations, threshold)",
                          key));
    }
  }
  if (!radius_given)
    throw util::UserError(file.string(), 0, "give the drum's inner radius in metres (radius = 0.042) or a preset");
  // The centre and the radius in pixels together or not at all: one alone left the others at 0, a drum centred on the
  // picture's top left corner, measured with exit 0.
  const int placed = static_cast<int>(root.contains("centre_col")) + static_cast<int>(root.contains("centre_row")) +
                     static_cast<int>(root.contains("radius_px"));
  if (placed > 0 && placed < 3)
    throw util::UserError(file.string(), 0,
                          "centre_col, centre_row and radius_px (the drum's centre and inner radius in pixels) go "
                          "together: give all three, or none for a square picture that spans the drum's diameter");
  if (centre_given) {
    const toml::node* spans = root.get("spans_diameter");
    if (spans && spans->value<bool>().value_or(false))
      fail_at(file, *spans, "spans_diameter = true: the picture is placed by centre_col, centre_row and radius_px");
    s.spans_diameter = false;
  } else if (!s.spans_diameter) {
    throw util::UserError(file.string(), static_cast<long>(root.get("spans_diameter")->source().begin.line),
                          "spans_diameter = false: give the drum's centre and inner radius in pixels (centre_col, "
                          "centre_row, radius_px)");
  }
  try {
    s.surface.validate();
  } catch (const std::invalid_argument& e) {
    throw util::UserError(file.string(), 0, e.what());
  }
  return s;
}

namespace {

/// `what` (which reads or measures the photograph `image`), its InputErrors naming the file.
template <class F>
auto naming(const fs::path& image, F what) {
  try {
    return what();
  } catch (const pp::InputError& e) {
    throw pp::InputError(fmt::format("{}: {}", image.string(), e.what()));
  }
}

/// The photograph in the drum frame (its geometry from `s`).
pp::DrumImage photograph_image(const fs::path& image, const PhotographSettings& s, pp::DrumGeometry& geometry) {
  const pp::GreyImage photo = pp::read_grey_image(image);
  PhotographMeasurement m;
  if (s.spans_diameter) {
    if (photo.width != photo.height)
      throw util::UserError(
          fmt::format("{}: {} × {} pixels is not square: a picture that spans the drum's diameter "
                      "is; give centre_col, centre_row and radius_px instead",
                      image.string(), photo.width, photo.height));
    m.geometry = pp::DrumGeometry::spanning(photo.width, photo.height, s.radius_m, s.rotation);
  } else {
    m.geometry.centre_col = s.centre_col;
    m.geometry.centre_row = s.centre_row;
    m.geometry.radius_px = s.radius_px;
    m.geometry.radius_m = s.radius_m;
    m.geometry.rotation = s.rotation;
  }
  geometry = m.geometry;
  return naming(image, [&] { return pp::drum_image_from_photograph(photo, m.geometry, s.dark_material); });
}

/// The photograph `image`, already read into `drum` (its geometry `geometry`), measured.
PhotographMeasurement measured_photograph(const fs::path& image, const PhotographSettings& s, const pp::DrumImage& drum,
                                          const pp::DrumGeometry& geometry) {
  PhotographMeasurement m;
  m.geometry = geometry;
  m.surface = naming(image, [&] { return pp::measure_drum_surface(drum, s.surface); });
  // The angle is positive when the surface rises towards the wall that carries the powder up, which the rotation
  // names; a turning drum's surface always does. One that falls there by more than three times its uncertainty was
  // taken by a drum turning the other way (or a mirrored picture): measured as it is, it gave −40° with exit 0.
  if (m.surface.dynamic_angle < -3 * m.surface.angle_uncertainty)
    throw pp::InputError(fmt::format(
        "{}: the surface falls by {:.2f}° ± {:.2g}° towards the {} wall, which a drum turning {} (the geometry file's "
        "rotation) carries the powder up: the drum in this picture turns the other way, or the picture is mirrored; "
        "set rotation = \"{}\"",
        image.string(), -m.surface.dynamic_angle, m.surface.angle_uncertainty,
        s.rotation == pp::DrumRotation::clockwise ? "left" : "right", pp::to_string(s.rotation),
        s.rotation == pp::DrumRotation::clockwise ? "counterclockwise" : "clockwise"));
  m.values = observable_values(m.surface);
  return m;
}

}  // namespace

PhotographMeasurement measure_photograph(const fs::path& image, const PhotographSettings& s) {
  pp::DrumGeometry geometry;
  const pp::DrumImage drum = photograph_image(image, s, geometry);
  return measured_photograph(image, s, drum, geometry);
}

namespace {

PhotographSettings photograph_settings(const fs::path& image) {
  const std::optional<fs::path> file = photograph_geometry_file(image);
  if (!file)
    throw util::UserError(fmt::format(
        "{}: no geometry for this photograph: write {} (or drum.toml in its folder) with the drum's inner radius, e.g. "
        "`preset = \"granudrum\"` (a square picture spanning a 42 mm radius) and `rotation = \"clockwise\"` "
        "(docs/explanation/experiments.md)",
        image.string(), image.string() + ".drum.toml"));
  return read_photograph_settings(*file);
}

LabMeasurement measure_lab_file(const fs::path& image) {
  // photograph_settings refuses a photograph without a geometry file: only then is there one to name.
  const PhotographSettings s = photograph_settings(image);
  const fs::path file = *photograph_geometry_file(image);
  const PhotographMeasurement m = measure_photograph(image, s);
  LabMeasurement lab;
  const auto add = [&](std::string name, std::optional<double> uncertainty) {
    lab.values.push_back({name, m.values.at(name), uncertainty});
  };
  add(std::string(k_dynamic_angle), m.surface.angle_uncertainty);
  // A station's height is uncertain by half its band (the fluctuation of the surface and the blur of the average).
  for (std::size_t i = 0; i < m.surface.stations.size(); ++i)
    if (m.values.count(fmt::format("{}{}", k_surface_prefix, i + 1)))
      add(fmt::format("{}{}", k_surface_prefix, i + 1), m.surface.stations[i].band / 2);
  add(std::string(k_s_shape), std::nullopt);
  add(std::string(k_fill_fraction), std::nullopt);
  lab.notes.push_back(fmt::format("geometry from {}", file.string()));
  lab.notes.push_back(fmt::format(
      "drum centre at column {:.1f}, row {:.1f}; radius {:.1f} px = {:g} m ({:.4f} mm per pixel); {}; judged within "
      "{:g} R",
      m.geometry.centre_col, m.geometry.centre_row, m.geometry.radius_px, m.geometry.radius_m,
      m.geometry.pixel_m() * 1e3, pp::to_string(m.geometry.rotation), s.surface.judged_radius));
  std::string stations;
  for (std::size_t i = 0; i < m.surface.stations.size(); ++i)
    stations += fmt::format("{}surface_{} at x = {:+.2f} mm", i ? ", " : "", i + 1, m.surface.stations[i].x * 1e3);
  lab.notes.push_back(stations);
  return lab;
}

/// The case's side view against a photograph of the drum (Windows-Yule & Neveu 2022 compare drum images by the area
/// where they differ): the mismatch area within the case's judged radius, in the drum frame (the photograph's geometry
/// from its drum.toml), and the two superimposed.
LabComparison compare_with_lab_file(const fs::path& folder, const nlohmann::json& case_json, const fs::path& image,
                                    const fs::path& picture) {
  const CaseRecord r = case_record(case_json, folder / k_case_json);
  const pp::DrumImage simulated = side_view(folder, r).image();
  const PhotographSettings s = photograph_settings(image);
  if (std::abs(s.radius_m - r.radius) > 1e-6 * r.radius)
    throw util::UserError(fmt::format("{}: a drum of radius {:g} m, the case {} one of {:g} m: not the same drum",
                                      image.string(), s.radius_m, folder.string(), r.radius));
  pp::DrumGeometry geometry;
  const pp::DrumImage photo = photograph_image(image, s, geometry);
  LabComparison c;
  c.mismatch_m2 = pp::drum_mismatch_area(photo, simulated, r.surface.judged_radius, r.surface.threshold);
  c.region = fmt::format("within {:g} R", r.surface.judged_radius);
  pp::write_rgb_png(picture, pp::drum_overlay(photo, simulated, r.surface.judged_radius, r.surface.threshold));
  c.picture = picture;
  // The photograph measured on its own with its geometry file's settings, as `demsa measure IMAGE` reads it: its
  // surface, band, fitted line and stations drawn over it, so the reader sees what the comparison stands on.
  const PhotographMeasurement m = measured_photograph(image, s, photo, geometry);
  c.lab_picture = picture.parent_path() / (picture.stem().string() + "_photograph.png");
  pp::write_rgb_png(c.lab_picture, pp::drum_surface_overlay(photo, m.surface, s.surface));
  return c;
}

}  // namespace

const Experiment& experiment() {
  static const Experiment descriptor{
      .name = "drum",
      .summary = "dynamic angle and free surface of a rotating drum, as a camera sees it through the end plate",
      .sections = drum_sections,
      .settings = drum_settings,
      .check = check_drum,
      .draft = draft_case,
      .limit_violations = limit_violations,
      .particles = particles,
      .largest_radius = largest_radius,
      .final_dump = k_final_dump,
      .run_outputs =
          [] {
            return std::vector<std::string>{k_final_dump, k_snapshots_dump, k_occupancy_png, k_surface_png};
          },
      .measure = measure,
      .observables = observables,
      .describe = describe,
      .check_outputs = check_outputs,
      .default_targets = default_targets,
      .lab_observables = lab_observables,
      .report_focus = report_focus,
      .case_report = case_report,
      .vtk_surfaces = vtk_surfaces,
      .case_cost = case_cost,
      .lab_file_extensions = {".bmp", ".png"},
      .measure_lab_file = measure_lab_file,
      .compare_with_lab_file = compare_with_lab_file,
  };
  return descriptor;
}

}  // namespace demsa::experiments::drum
