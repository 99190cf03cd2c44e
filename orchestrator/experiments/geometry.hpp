#pragma once
// Geometry files written by demsa into a case: the pile's pedestal (a closed-top cylinder as a compact triangle
// mesh) and the oedometer's load plate, as ASCII STL that LIGGGHTS reads with `fix mesh/surface`.
#include <array>
#include <string>
#include <vector>

namespace demsa::experiments {

using Vertex = std::array<double, 3>;
using Triangle = std::array<Vertex, 3>;

/// The pedestal cylinder (paper §3.2: r_cy, h_cy) standing on z = 0, axis x = y = 0: the top disc triangulated
/// ring by ring with rings `element` apart and about `element` long edges, and the side band split to the same
/// edge length. Compact (near-equilateral) triangles keep the mesh-wall neighbour search cheap: the reference
/// measurements found them about 20 % faster than a fan of long thin triangles. Without `with_top`, the side band
/// only: a pedestal whose top is covered by a frozen layer of particles ([pile] base = "particles"), whose contacts
/// with a top mesh would cost 2.5 to 3.5 times the CPU of the pile on a wall and change nothing.
std::vector<Triangle> pedestal_mesh(double radius, double height, double element, bool with_top = true);

/// The oedometer load plate: a side × side square in the plane z = 0 centred on x = y = 0, two triangles.
std::vector<Triangle> plate_mesh(double side);

/// ASCII STL with fixed formatting (byte-identical for identical triangles); normals from the vertex order.
std::string to_ascii_stl(const std::vector<Triangle>& triangles, const std::string& solid_name);

}  // namespace demsa::experiments
