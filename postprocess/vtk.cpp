#include "postprocess/vtk.hpp"

#include <fmt/core.h>

#include <cassert>
#include <cstdint>
#include <iterator>
#include <span>

namespace demsa::postprocess {

namespace {

// `{}` prints a double in its shortest form that reads back to the same bits: the file is exact.
constexpr const char* k_header =
    "<?xml version=\"1.0\"?>\n"
    "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
    "  <PolyData>\n";
constexpr const char* k_footer = "    </Piece>\n  </PolyData>\n</VTKFile>\n";

void open_array(std::string& out, const char* type, const char* name, int components) {
  out += fmt::format("        <DataArray type=\"{}\"", type);
  if (name[0] != '\0') out += fmt::format(" Name=\"{}\"", name);
  if (components > 1) out += fmt::format(" NumberOfComponents=\"{}\"", components);
  out += " format=\"ascii\">\n";
}

void close_array(std::string& out) { out += "        </DataArray>\n"; }

/// Cells as VTK XML writes them: every cell's point indices, then each cell's end offset.
void cells(std::string& out, const char* section, const std::vector<std::vector<std::size_t>>& polygons) {
  out += fmt::format("      <{}>\n", section);
  open_array(out, "Int64", "connectivity", 1);
  auto it = std::back_inserter(out);
  for (const std::vector<std::size_t>& p : polygons) {
    out += "         ";
    for (const std::size_t index : p) fmt::format_to(it, " {}", index);
    out += '\n';
  }
  close_array(out);
  open_array(out, "Int64", "offsets", 1);
  std::size_t end = 0;
  for (const std::vector<std::size_t>& p : polygons) {
    end += p.size();
    fmt::format_to(it, "          {}\n", end);
  }
  close_array(out);
  out += fmt::format("      </{}>\n", section);
}

}  // namespace

std::string particles_vtp(const DumpFrame& frame) {
  const Particles p = particles_from_frame(frame);
  const std::size_t n = p.size();
  const int velocity_columns = frame.has_column("vx") + frame.has_column("vy") + frame.has_column("vz");
  if (velocity_columns != 0 && velocity_columns != 3) {
    // read_last_frame knows the line of ITEM: ATOMS only when it counted the lines before it; the time step names
    // the frame either way.
    std::string have;
    for (const char* c : {"vx", "vy", "vz"})
      if (frame.has_column(c)) have += std::string(have.empty() ? "" : " ") + c;
    throw ParseError(frame.file, frame.atoms_line,
                     fmt::format("ITEM: ATOMS of time step {} has {} but not all of vx vy vz: the velocity needs all "
                                 "three (or none)",
                                 frame.timestep, have));
  }
  std::span<const double> v[3];
  if (velocity_columns == 3) {
    v[0] = frame.column("vx");
    v[1] = frame.column("vy");
    v[2] = frame.column("vz");
  }

  std::string out = k_header;
  out += fmt::format(
      "    <Piece NumberOfPoints=\"{0}\" NumberOfVerts=\"{0}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
      "NumberOfPolys=\"0\">\n",
      n);
  out += velocity_columns == 3 ? "      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n"
                               : "      <PointData Scalars=\"radius\">\n";
  auto it = std::back_inserter(out);
  open_array(out, "Int64", "id", 1);
  for (std::size_t i = 0; i < n; ++i) fmt::format_to(it, "          {}\n", p.id[i]);
  close_array(out);
  open_array(out, "Int32", "type", 1);
  for (std::size_t i = 0; i < n; ++i) fmt::format_to(it, "          {}\n", p.type[i]);
  close_array(out);
  open_array(out, "Float64", "radius", 1);
  for (std::size_t i = 0; i < n; ++i) fmt::format_to(it, "          {}\n", p.radius[i]);
  close_array(out);
  if (velocity_columns == 3) {
    // particles_from_frame keeps every row in file order (no type filter), so row i is particle i.
    open_array(out, "Float64", "velocity", 3);
    for (std::size_t i = 0; i < n; ++i) fmt::format_to(it, "          {} {} {}\n", v[0][i], v[1][i], v[2][i]);
    close_array(out);
  }
  out += "      </PointData>\n      <Points>\n";
  open_array(out, "Float64", "", 3);
  for (std::size_t i = 0; i < n; ++i) fmt::format_to(it, "          {} {} {}\n", p.x[i], p.y[i], p.z[i]);
  close_array(out);
  out += "      </Points>\n      <Verts>\n";
  open_array(out, "Int64", "connectivity", 1);
  for (std::size_t i = 0; i < n; ++i) fmt::format_to(it, "          {}\n", i);
  close_array(out);
  open_array(out, "Int64", "offsets", 1);
  for (std::size_t i = 0; i < n; ++i) fmt::format_to(it, "          {}\n", i + 1);
  close_array(out);
  out += "      </Verts>\n";
  out += k_footer;
  return out;
}

Surface mesh_surface(const TriangleMesh& mesh, double dz) {
  Surface s;
  s.points = mesh.points;
  for (std::array<double, 3>& p : s.points) p[2] += dz;
  for (const std::array<std::size_t, 3>& t : mesh.triangles) s.polygons.push_back({t[0], t[1], t[2]});
  return s;
}

std::string surface_vtp(const Surface& surface) {
  std::string out = k_header;
  out += fmt::format(
      "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
      "NumberOfPolys=\"{}\">\n",
      surface.points.size(), surface.polygons.size());
  out += "      <Points>\n";
  open_array(out, "Float64", "", 3);
  auto it = std::back_inserter(out);
  for (const std::array<double, 3>& q : surface.points) fmt::format_to(it, "          {} {} {}\n", q[0], q[1], q[2]);
  close_array(out);
  out += "      </Points>\n";
  for ([[maybe_unused]] const std::vector<std::size_t>& polygon : surface.polygons)
    for ([[maybe_unused]] const std::size_t index : polygon)
      assert(index < surface.points.size() && "polygon index outside the points");
  cells(out, "Polys", surface.polygons);
  out += k_footer;
  return out;
}

}  // namespace demsa::postprocess
