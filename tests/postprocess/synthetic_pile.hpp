#pragma once
// Synthetic piles of known flank angle for the angle-of-repose tests: a cone of flank angle θ on the pedestal whose
// top is rounded by a spherical cap tangent to the flank (the shape of the paper's Fig. 1b), built from polydisperse
// spheres (radii from a normal distribution truncated to [1, 3.5] mm, paper Table 2 set 1). The outer layer touches
// the cone from inside with some random depth noise; inner layers fill it; a few particles lie off the pedestal.
#include "postprocess/dump.hpp"

#include <cmath>
#include <numbers>
#include <random>

namespace demsa::test {

struct SyntheticPileOptions {
  double angle_deg = 33.5;      ///< flank angle θ
  double base_radius = 0.050;   ///< flank meets the pedestal top at this radius [m]
  double pedestal_top = 0.005;  ///< [m]
  double cap_radius = 0.015;    ///< radius of the rounded top [m]
  double noise = 0.3e-3;        ///< depth noise of the outer layer, uniform in ±noise [m]
  int layers = 3;               ///< layers of spheres below the surface
  double spacing = 3.5e-3;      ///< distance between neighbouring surface spheres [m]
  double layer_depth = 2.5e-3;  ///< depth between layers (a layer sits in the hollows of the one above) [m]
  unsigned seed = 1;
};

/// Height of the pile's outline above the pedestal top at radial distance rho (0 beyond the base).
inline double synthetic_pile_profile(const SyntheticPileOptions& o, double rho) {
  const double t = o.angle_deg * std::numbers::pi / 180.0;
  const double zc = (o.base_radius * std::sin(t) - o.cap_radius) / std::cos(t);  // cap centre on the axis
  const double rho_t = o.cap_radius * std::sin(t);                               // tangent point
  if (rho <= rho_t) return zc + std::sqrt(o.cap_radius * o.cap_radius - rho * rho);
  return std::max(0.0, (o.base_radius - rho) * std::tan(t));
}

inline postprocess::Particles make_synthetic_pile(const SyntheticPileOptions& o) {
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> radius_dist(2.0e-3, 0.5e-3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto radius = [&] {
    for (;;) {
      const double r = radius_dist(rng);
      if (r >= 1.0e-3 && r <= 3.5e-3) return r;
    }
  };
  const double t = o.angle_deg * std::numbers::pi / 180.0;
  const double zc = (o.base_radius * std::sin(t) - o.cap_radius) / std::cos(t);
  const double rho_t = o.cap_radius * std::sin(t);
  const double flank_length = (o.base_radius - rho_t) / std::cos(t);
  const double cap_length = o.cap_radius * (std::numbers::pi / 2.0 - t);  // arc from the tangent point to the top

  postprocess::Particles p;
  std::int64_t next_id = 1;
  auto add = [&](double x, double y, double z, double r) {
    p.id.push_back(next_id++);
    p.type.push_back(1);
    p.x.push_back(x);
    p.y.push_back(y);
    p.z.push_back(z);
    p.radius.push_back(r);
  };
  // Walk the outline by arc length from the base edge to the top; each point has a unit outward normal (nr, nz).
  for (int layer = 0; layer < o.layers; ++layer) {
    const double depth0 = layer * o.layer_depth;
    for (double s = 0.5 * o.spacing; s < flank_length + cap_length; s += o.spacing * (0.8 + 0.4 * unit(rng))) {
      double rho = 0, z = 0, nr = 0, nz = 0;
      if (s < flank_length) {
        rho = o.base_radius - s * std::cos(t);
        z = s * std::sin(t);
        nr = std::sin(t);
        nz = std::cos(t);
      } else {
        // on the cap the normal turns from the flank normal (tilt θ from the vertical) to the vertical
        const double tilt = t - (s - flank_length) / o.cap_radius;
        nr = std::sin(std::max(0.0, tilt));
        nz = std::cos(std::max(0.0, tilt));
        rho = o.cap_radius * nr;
        z = zc + o.cap_radius * nz;
      }
      const double circumference = 2.0 * std::numbers::pi * std::max(rho, 0.5 * o.spacing);
      const int count = std::max(1, static_cast<int>(circumference / o.spacing));
      const double offset = unit(rng) * 2.0 * std::numbers::pi;
      for (int m = 0; m < count; ++m) {
        const double az = offset + 2.0 * std::numbers::pi * (m + 0.3 * (unit(rng) - 0.5)) / count;
        const double r = radius();
        const double depth = depth0 + r + (layer == 0 ? o.noise * (2.0 * unit(rng) - 1.0) : 0.0);
        const double cr = rho - depth * nr;
        const double cz = z - depth * nz;
        if (cz < r) continue;  // would be inside the pedestal
        add(cr * std::cos(az), cr * std::sin(az), o.pedestal_top + cz, r);
      }
    }
  }
  // Particles that rolled off: on the ground beside the pedestal; they must be filtered out.
  for (int m = 0; m < 40; ++m) {
    const double az = 2.0 * std::numbers::pi * unit(rng);
    const double r = radius();
    const double rho = 0.055 + 0.05 * unit(rng);
    add(rho * std::cos(az), rho * std::sin(az), r, r);
  }
  return p;
}

}  // namespace demsa::test
