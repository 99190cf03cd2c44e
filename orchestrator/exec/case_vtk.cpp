#include "orchestrator/exec/case_vtk.hpp"

#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "postprocess/dump.hpp"
#include "postprocess/oedometer.hpp"
#include "postprocess/stl.hpp"
#include "postprocess/vtk.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <exception>
#include <fstream>
#include <string>

namespace demsa::exec {

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

namespace {

// The meshes cases/case_writer.cpp writes into a case folder (and LIGGGHTS reads with fix mesh/surface).
constexpr const char* k_pedestal_stl = "pedestal.stl";
constexpr const char* k_plate_stl = "plate.stl";

nlohmann::json read_case_json(const fs::path& case_dir) {
  const fs::path file = case_dir / study::k_case_json;
  std::error_code ec;
  if (!fs::is_directory(case_dir, ec)) throw util::UserError(case_dir.string(), 0, "no such case folder");
  if (!fs::exists(file, ec))
    throw util::UserError(
        case_dir.string(), 0,
        fmt::format("not a case folder (no {}); give a dump file to convert its particles only", study::k_case_json));
  std::ifstream in(file);
  if (!in) throw util::UserError(file.string(), 0, "cannot be read");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw util::UserError(file.string(), 0, fmt::format("not valid JSON: {}", e.what()));
  }
  if (!doc.is_object()) throw util::UserError(file.string(), 0, "not a case description (a JSON object)");
  return doc;
}

/// The positive length at `section`.`key` of a case.json.
double case_length(const nlohmann::json& doc, const fs::path& file, const char* section, const char* key) {
  if (!doc.contains(section) || !doc[section].is_object() || !doc[section].contains(key))
    throw util::UserError(file.string(), 0, fmt::format("has no {}.{} (the case's geometry)", section, key));
  const nlohmann::json& v = doc[section][key];
  if (!v.is_number() || !(v.get<double>() > 0.0) || !std::isfinite(v.get<double>()))
    throw util::UserError(file.string(), 0, fmt::format("{}.{} = {}: not a length > 0", section, key, v.dump()));
  return v.get<double>();
}

pp::Surface surface_of(const pp::TriangleMesh& mesh, double dz) {
  pp::Surface s;
  s.points = mesh.points;
  for (std::array<double, 3>& p : s.points) p[2] += dz;
  for (const std::array<std::size_t, 3>& t : mesh.triangles) s.polygons.push_back({t[0], t[1], t[2]});
  return s;
}

/// A horizontal rectangle at height z, counter-clockwise seen from above.
pp::Surface rectangle(double x0, double x1, double y0, double y1, double z) {
  return {{{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}, {{0, 1, 2, 3}}};
}

/// The oedometer box (oedometer_box.liggghts: walls x, y = ±side/2, floor z = 0), drawn up to `height`: five quads,
/// counter-clockwise seen from inside.
pp::Surface open_box(double side, double height) {
  const double h = side / 2.0;
  pp::Surface s;
  s.points = {{-h, -h, 0.0},    {h, -h, 0.0},    {h, h, 0.0},    {-h, h, 0.0},
              {-h, -h, height}, {h, -h, height}, {h, h, height}, {-h, h, height}};
  s.polygons = {{0, 1, 2, 3}, {0, 4, 5, 1}, {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 4, 0}};
  return s;
}

void write(const fs::path& path, const std::string& text, std::vector<fs::path>& written) {
  util::write_file_atomically(path, text);
  written.push_back(path);
}

}  // namespace

std::vector<fs::path> write_case_vtk(const fs::path& case_dir, const fs::path& out_dir) {
  const nlohmann::json doc = read_case_json(case_dir);
  const fs::path file = case_dir / study::k_case_json;
  const nlohmann::json experiment = doc.contains("experiment") ? doc["experiment"] : nlohmann::json(nullptr);
  if (experiment != "pile" && experiment != "oedometer")
    throw util::UserError(file.string(), 0,
                          fmt::format("experiment = {}: expected \"pile\" or \"oedometer\"", experiment.dump()));
  const bool pile = experiment == "pile";
  const fs::path dump = case_dir / (pile ? study::k_pile_final_dump : study::k_oedometer_final_dump);
  std::error_code ec;
  if (!fs::exists(dump, ec))
    throw util::UserError(
        case_dir.string(), 0,
        fmt::format("the case has no {} (not run yet, or it did not finish)", dump.filename().string()));
  // Everything is read and checked before the first file is written.
  pp::DumpReaderOptions options;
  options.required_columns = {"id", "type", "radius"};
  const pp::DumpFrame frame = pp::read_last_frame(dump, options);
  const std::string particles = pp::particles_vtp(frame);
  std::vector<std::pair<const char*, std::string>> files{{k_vtk_particles, particles}};
  bool plate = false;
  if (pile) {
    files.emplace_back(k_vtk_pedestal, pp::surface_vtp(surface_of(pp::read_ascii_stl(case_dir / k_pedestal_stl), 0)));
    files.emplace_back(k_vtk_ground,
                       pp::surface_vtp(rectangle(frame.box[0], frame.box[1], frame.box[2], frame.box[3], 0.0)));
  } else {
    const double side = case_length(doc, file, "oedometer", "box_side_m");
    const double height = case_length(doc, file, "oedometer", "box_height_m");
    files.emplace_back(k_vtk_box, pp::surface_vtp(open_box(side, height)));
    const std::vector<pp::PlateState> states = pp::read_plate_states(case_dir / study::k_plate_states);
    if (states.empty()) {
      util::log::warn("{}: no load step in it yet, so no {} (the plate's height is not known)",
                      (case_dir / study::k_plate_states).string(), k_vtk_plate);
    } else {
      // plate.stl lies at z = 0; LIGGGHTS moves it to the plate height, and the last load state is where it stood
      // when the final dump was written.
      plate = true;
      files.emplace_back(k_vtk_plate, pp::surface_vtp(surface_of(pp::read_ascii_stl(case_dir / k_plate_stl),
                                                                 states.back().plate_z_m)));
    }
  }
  fs::create_directories(out_dir);
  std::vector<fs::path> written;
  for (const auto& [name, text] : files) write(out_dir / name, text, written);
  if (!pile && !plate) fs::remove(out_dir / k_vtk_plate, ec);  // not one of an earlier state
  return written;
}

void write_dump_vtk(const fs::path& dump, const fs::path& out) {
  pp::DumpReaderOptions options;
  options.required_columns = {"id", "type", "radius"};
  const std::string text = pp::particles_vtp(pp::read_last_frame(dump, options));
  if (!out.parent_path().empty()) fs::create_directories(out.parent_path());
  util::write_file_atomically(out, text);
}

void write_case_vtk_or_warn(const fs::path& case_dir) {
  try {
    write_case_vtk(case_dir, case_dir / study::k_case_vtk_folder);
  } catch (const std::exception& e) {
    util::log::warn("{}: the case was measured, but its ParaView files were not written: {}", case_dir.string(),
                    e.what());
  }
}

}  // namespace demsa::exec
