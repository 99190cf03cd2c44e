#pragma once
// Geometry files written by demsa into a case: the pile's pedestal (a closed-top cylinder as a compact triangle
// mesh) and the oedometer's load plate, as ASCII STL that LIGGGHTS reads with `fix mesh/surface`.
#include <array>
#include <string>
#include <vector>

namespace demsa::experiments {

using Vertex = std::array<double, 3>;
using Triangle = std::array<Vertex, 3>;

/// The pedestal cylinder (paper §3.2: r_cy, h_cy) standing on z = 0, axis x = y = 0. The top disc is triangulated
/// ring by ring, rings `top_element` apart with points about `top_element` apart along them, except the rim: the
/// circle's polygon, whose points are `rim_element` apart (it is where particles roll off); the side band is split to
/// edges of about `rim_element`. The cost of LIGGGHTS's mesh wall grows with the triangles within reach of each
/// particle (every pair is checked every step): coarse triangles inside a fine rim halve it against triangles of the
/// rim's size everywhere, and long thin ones (a fan from the centre) raise it (docs/explanation/benchmarks.md, "The
/// pedestal mesh"). `top_element` = `rim_element` gives compact triangles of one size. Without `with_top`, the side
/// band only: a pedestal whose top is covered by a frozen layer of particles ([pile] base = "particles"), whose
/// contacts with a top mesh would cost 2.5 to 3.5 times the CPU of the pile on a wall and change nothing.
std::vector<Triangle> pedestal_mesh(double radius, double height, double rim_element, double top_element,
                                    bool with_top = true);

/// The oedometer load plate: a side × side square in the plane z = 0 centred on x = y = 0, two triangles.
std::vector<Triangle> plate_mesh(double side);

/// ASCII STL with fixed formatting (byte-identical for identical triangles); normals from the vertex order.
std::string to_ascii_stl(const std::vector<Triangle>& triangles, const std::string& solid_name);

}  // namespace demsa::experiments
