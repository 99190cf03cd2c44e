#include "orchestrator/experiments/geometry.hpp"

#include "orchestrator/util/signals.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

namespace demsa::experiments {

std::vector<Triangle> pedestal_mesh(double radius, double height, double rim_element, double top_element,
                                    bool with_top) {
  assert(radius > 0 && height > 0 && rim_element > 0 && top_element >= rim_element);
  using Point = std::array<double, 2>;
  const double two_pi = 2.0 * std::numbers::pi;
  const int ring_count = std::max(1, static_cast<int>(std::lround(radius / top_element)));
  std::vector<std::vector<Point>> rings{{Point{0.0, 0.0}}};
  for (int k = 1; k <= ring_count; ++k) {
    util::throw_if_stop_raised();
    const double r = radius * k / ring_count;
    // The rim is the circle's polygon: its points rim_element apart whatever the top's triangles.
    const double element = k == ring_count ? rim_element : top_element;
    const int n = std::max(6, static_cast<int>(std::lround(two_pi * r / element)));
    std::vector<Point> ring;
    for (int i = 0; i < n; ++i) ring.push_back({r * std::cos(two_pi * i / n), r * std::sin(two_pi * i / n)});
    rings.push_back(std::move(ring));
  }
  std::vector<Triangle> tris;
  const auto top = [height](const Point& p) { return Vertex{p[0], p[1], height}; };
  for (std::size_t k = 1; with_top && k < rings.size(); ++k) {
    const std::vector<Point>& a = rings[k - 1];
    const std::vector<Point>& b = rings[k];
    const std::size_t na = a.size(), nb = b.size();
    if (na == 1) {
      for (std::size_t j = 0; j < nb; ++j) tris.push_back({top(a[0]), top(b[j]), top(b[(j + 1) % nb])});
      continue;
    }
    // Stitch two rings by advancing along whichever ring is behind in angle.
    std::size_t i = 0, j = 0;
    while (i < na || j < nb) {
      const double ta = static_cast<double>(i + 1) / na, tb = static_cast<double>(j + 1) / nb;
      if (j < nb && (i >= na || tb <= ta)) {
        tris.push_back({top(a[i % na]), top(b[j % nb]), top(b[(j + 1) % nb])});
        ++j;
      } else {
        tris.push_back({top(a[i % na]), top(b[j % nb]), top(a[(i + 1) % na])});
        ++i;
      }
    }
  }
  const std::vector<Point>& outer = rings.back();
  const std::size_t n = outer.size();
  const int bands = std::max(1, static_cast<int>(std::lround(height / rim_element)));
  for (std::size_t i = 0; i < n; ++i) {
    const Point& p = outer[i];
    const Point& q = outer[(i + 1) % n];
    for (int k = 0; k < bands; ++k) {
      const double z0 = height * k / bands, z1 = height * (k + 1) / bands;
      tris.push_back({Vertex{p[0], p[1], z0}, Vertex{q[0], q[1], z0}, Vertex{q[0], q[1], z1}});
      tris.push_back({Vertex{p[0], p[1], z0}, Vertex{q[0], q[1], z1}, Vertex{p[0], p[1], z1}});
    }
  }
  return tris;
}

std::vector<Triangle> plate_mesh(double side) {
  const double h = side / 2.0;
  return {Triangle{Vertex{-h, -h, 0.0}, Vertex{h, -h, 0.0}, Vertex{h, h, 0.0}},
          Triangle{Vertex{-h, -h, 0.0}, Vertex{h, h, 0.0}, Vertex{-h, h, 0.0}}};
}

std::string to_ascii_stl(const std::vector<Triangle>& triangles, const std::string& solid_name) {
  std::string out = "solid " + solid_name + "\n";
  for (std::size_t k = 0; k < triangles.size(); ++k) {
    if (k % 4096 == 0) util::throw_if_stop_raised();
    const Triangle& t = triangles[k];
    const Vertex u{t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]};
    const Vertex v{t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]};
    Vertex nrm{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    assert(len > 0 && "degenerate triangle");
    for (double& c : nrm) c = c / len + 0.0;  // + 0.0 turns -0 into 0
    out += fmt::format(" facet normal {:.6e} {:.6e} {:.6e}\n  outer loop\n", nrm[0], nrm[1], nrm[2]);
    for (const Vertex& p : t)
      out += fmt::format("   vertex {:.9e} {:.9e} {:.9e}\n", p[0] + 0.0, p[1] + 0.0, p[2] + 0.0);
    out += "  endloop\n endfacet\n";
  }
  out += "endsolid " + solid_name + "\n";
  return out;
}

}  // namespace demsa::experiments
