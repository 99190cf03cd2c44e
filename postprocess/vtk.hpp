#pragma once
// VTK files that ParaView (and any VTK reader) opens directly: the particles of a dump frame and polygon surfaces
// (the pedestal, the box walls, the load plate).
//
// Format: VTK XML PolyData (.vtp), ASCII, for the particles (points with one vertex cell each) and the surfaces
// (polygons) alike. XML rather than legacy .vtk because its arrays carry explicit types and names (the ids as Int64,
// which legacy files before format 5.1 cannot name portably) and it is the format of ParaView's own writers. ASCII
// rather than base64 binary because it is exact with shortest round-trip numbers, needs no encoder, and stays readable
// in a text editor; it takes about 190 bytes per particle (23 kB for a pile of 120). Reference: "VTK File Formats", the
// VTK documentation (XML PolyData: Piece, PointData, Points, Verts, Polys; each cell's point indices in `connectivity`
// and its end in `offsets`).
#include "postprocess/dump.hpp"
#include "postprocess/stl.hpp"

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace demsa::postprocess {

/// A polygon surface: points and polygons (each a list of indices into points, counter-clockwise seen from the
/// outside where that side exists).
struct Surface {
  std::vector<std::array<double, 3>> points;
  std::vector<std::vector<std::size_t>> polygons;
};

/// The .vtp text of a dump frame's atoms: one point per atom at x y z (or xu/xs as particles_from_frame takes
/// them), a vertex cell each, and the point data `id` (Int64), `type` (Int32), `radius` (Float64) and, when the
/// frame has vx vy vz, `velocity` (Float64, 3 components). Throws ParseError (file, line) as particles_from_frame
/// does, and when the frame has only some of vx vy vz.
std::string particles_vtp(const DumpFrame& frame);

/// A triangle mesh (an STL file read) as a surface, shifted by `dz` in z (a mesh LIGGGHTS moved, such as a plate).
Surface mesh_surface(const TriangleMesh& mesh, double dz = 0.0);

/// The .vtp text of a surface (polygons, no point data). Asserts that every index lies inside points.
std::string surface_vtp(const Surface& surface);

}  // namespace demsa::postprocess
