#pragma once
// Synthetic piles for comparing angle estimators: polydisperse spheres (radii from a normal distribution of mean
// 2 mm, sd 0.5 mm truncated to [1, 3.5] mm, paper Table 2 set 1) filling a cone of known flank angle θ that stands
// on the pedestal top, its apex rounded by a spherical cap tangent to the flank (the shape of the paper's Fig. 1b).
// The cone is filled by random sequential addition (Feder 1980, J. Theor. Biol. 87, 237; Widom 1966): spheres
// at random positions are kept when they overlap no earlier sphere and lie inside the outline, until `attempts`
// positions have been tried. Surface roughness, each kind on its own or together: every shell sphere moved along the
// outline's normal by its own offset, uniform in [-jitter, +jitter] (or Gaussian of sd jitter_sd); one-sided,
// sticking out by uniform [0, outward]; holes, a share `missing` of the shell's spheres left out; mounds, `bumps`
// raised patches of the flank a few particle sizes across. jitter = outward = missing = bumps = 0 gives a smooth cone.
// A few particles lie on the ground beside the pedestal.
#include "postprocess/dump.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

namespace demsa::test {

struct SyntheticConeOptions {
  double angle_deg = 33.0;        ///< flank angle θ [deg]
  double base_radius = 0.045;     ///< the flank meets the pedestal top at this distance from the axis [m]
  double pedestal_top = 0.005;    ///< z of the pedestal top [m]
  double pedestal_radius = 0.05;  ///< particles on the ground lie beyond it [m]
  double cap_radius = 0.006;      ///< radius of the rounded apex [m]
  double jitter = 0.0;            ///< shell spheres move along the outline's normal by uniform [-jitter, +jitter] [m]
  /// Held-out roughness (not used when the robust estimator was designed; test_angle_estimators.cpp): shell spheres
  /// move along the outline's normal by a Gaussian offset of this standard deviation, unbounded either way [m].
  double jitter_sd = 0.0;
  /// Other kinds of roughness (bench/angle_estimators.cpp compares the estimators on each):
  double outward = 0.0;  ///< shell spheres stick out of the outline by uniform [0, outward] (one-sided) [m]
  double missing = 0.0;  ///< share of the shell's spheres left out (holes in the surface layer), in [0, 1)
  int bumps = 0;         ///< mounds on the flank: the outline raised by bump_height cos²(π d / (2 bump_radius))
  double bump_radius = 0.008, bump_height = 0.003;  ///< of each mound, d the distance from its centre [m]
  double r_mean = 2.0e-3, r_sd = 0.5e-3, r_min = 1.0e-3, r_max = 3.5e-3;  ///< radius distribution [m]
  double spacing = 2.5e-3;  ///< least distance between the tangent points of the surface shell spheres [m]
  int attempts = 100000;    ///< random positions tried inside the shell
  int fallen = 20;          ///< particles on the ground outside the pedestal
  unsigned seed = 1;
};

/// Depth of a point (rho, z above the pedestal top) inside the rounded cone: its distance to the outline, negative
/// outside. The rounded cone is convex (hull of the cap sphere and the base circle), so the depth is the least over
/// its supporting half-spaces: the pedestal top, the flank plane, and the cap's tangent planes tilted less than θ.
inline double synthetic_cone_depth(const SyntheticConeOptions& o, double rho, double z) {
  const double t = o.angle_deg * std::numbers::pi / 180.0;
  const double flank = (o.base_radius - rho) * std::sin(t) - z * std::cos(t);
  const double zc = (o.base_radius * std::sin(t) - o.cap_radius) / std::cos(t);  // cap centre on the axis
  double depth = std::min(z, flank);
  const double dz = z - zc;
  if (dz > 0.0 && rho <= dz * std::tan(t)) depth = std::min(depth, o.cap_radius - std::hypot(rho, dz));
  return depth;
}

inline postprocess::Particles make_synthetic_cone(const SyntheticConeOptions& o) {
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> radius_dist(o.r_mean, o.r_sd);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  auto radius = [&] {
    for (;;) {
      const double r = radius_dist(rng);
      if (r >= o.r_min && r <= o.r_max) return r;
    }
  };
  const double t = o.angle_deg * std::numbers::pi / 180.0;
  const double rough = o.jitter + o.outward + (o.bumps > 0 ? o.bump_height : 0.0);
  const double height = o.base_radius * std::tan(t) + rough;
  const double reach = o.base_radius + rough;

  postprocess::Particles p;
  // Overlap search on a cell grid of side 2 r_max: a sphere can only touch spheres in its own and adjacent cells.
  const double cell = 2.0 * o.r_max;
  auto key = [&](double x, double y, double z) {
    const auto i = static_cast<std::int64_t>(std::floor((x + reach) / cell));
    const auto j = static_cast<std::int64_t>(std::floor((y + reach) / cell));
    const auto k = static_cast<std::int64_t>(std::floor(z / cell));
    return (i * 1024 + j) * 1024 + k;
  };
  std::unordered_map<std::int64_t, std::vector<std::size_t>> grid;
  std::int64_t next_id = 1;
  auto add = [&](double x, double y, double z, double r) {
    p.id.push_back(next_id++);
    p.type.push_back(1);
    p.x.push_back(x);
    p.y.push_back(y);
    p.z.push_back(z);
    p.radius.push_back(r);
  };
  // Overlap test against the spheres kept so far (the shell's own spheres may overlap each other).
  auto overlaps = [&](double x, double y, double z, double r) {
    const auto i0 = static_cast<std::int64_t>(std::floor((x + reach) / cell));
    const auto j0 = static_cast<std::int64_t>(std::floor((y + reach) / cell));
    const auto k0 = static_cast<std::int64_t>(std::floor(z / cell));
    for (std::int64_t i = i0 - 1; i <= i0 + 1; ++i)
      for (std::int64_t j = j0 - 1; j <= j0 + 1; ++j)
        for (std::int64_t k = k0 - 1; k <= k0 + 1; ++k) {
          const auto it = grid.find((i * 1024 + j) * 1024 + k);
          if (it == grid.end()) continue;
          for (std::size_t m : it->second) {
            const double dx = p.x[m] - x, dy = p.y[m] - y, dz = p.z[m] - o.pedestal_top - z;
            const double dmin = p.radius[m] + r;
            if (dx * dx + dy * dy + dz * dz < dmin * dmin) return true;
          }
        }
    return false;
  };
  auto keep = [&](double x, double y, double z, double r) {
    grid[key(x, y, z)].push_back(p.size());
    add(x, y, o.pedestal_top + z, r);
  };

  // The shell: spheres touching the outline from inside at random tangent points, placed by random sequential
  // addition of the tangent points on the outline (area-uniform, at least `spacing` apart; the spheres themselves
  // may overlap), so the surface is dense but has no rows that levels could alias with. Each sphere is moved along
  // the outline's normal by its own roughness offset, uniform in [-jitter, +jitter]; one that would reach into the
  // pedestal rests on it instead, as far below the flank.
  const double zc = (o.base_radius * std::sin(t) - o.cap_radius) / std::cos(t);
  const double rho_t = o.cap_radius * std::sin(t);
  const double flank_length = (o.base_radius - rho_t) / std::cos(t);
  const double outline_length = flank_length + o.cap_radius * (std::numbers::pi / 2.0 - t);
  std::vector<std::array<double, 3>> tangents;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> tangent_grid;
  auto tkey = [&](double x, double y, double z) {
    return (static_cast<std::int64_t>(std::floor((x + reach) / o.spacing)) * 4096 +
            static_cast<std::int64_t>(std::floor((y + reach) / o.spacing))) *
               4096 +
           static_cast<std::int64_t>(std::floor(z / o.spacing));
  };
  const int shell_attempts = static_cast<int>(40.0 * 2.0 * o.base_radius * outline_length / (o.spacing * o.spacing));
  // The mounds' centres: points of the flank between 20 % and 80 % of its length, at random azimuths.
  std::vector<std::array<double, 3>> bump_centres;
  for (int b = 0; b < o.bumps; ++b) {
    const double s = flank_length * (0.2 + 0.6 * unit(rng));
    const double az = 2.0 * std::numbers::pi * unit(rng);
    const double rho = o.base_radius - s * std::cos(t);
    bump_centres.push_back({rho * std::cos(az), rho * std::sin(az), s * std::sin(t)});
  }
  for (int attempt = 0; attempt < shell_attempts; ++attempt) {
    const double s = outline_length * unit(rng);
    double rho = 0, z = 0, nr = 0, nz = 0;  // point of the outline and its outward unit normal
    if (s < flank_length) {
      rho = o.base_radius - s * std::cos(t);
      z = s * std::sin(t);
      nr = std::sin(t);
      nz = std::cos(t);
    } else {
      const double tilt = std::max(0.0, t - (s - flank_length) / o.cap_radius);
      nr = std::sin(tilt);
      nz = std::cos(tilt);
      rho = o.cap_radius * nr;
      z = zc + o.cap_radius * nz;
    }
    if (unit(rng) * o.base_radius > rho) continue;  // area-uniform: the ring at rho has length 2π rho
    const double az = 2.0 * std::numbers::pi * unit(rng);
    const double tx = rho * std::cos(az), ty = rho * std::sin(az);
    bool near = false;
    const std::int64_t k0 = tkey(tx, ty, z);
    for (std::int64_t di = -1; di <= 1 && !near; ++di)
      for (std::int64_t dj = -1; dj <= 1 && !near; ++dj)
        for (std::int64_t dk = -1; dk <= 1 && !near; ++dk) {
          const auto it = tangent_grid.find(k0 + (di * 4096 + dj) * 4096 + dk);
          if (it == tangent_grid.end()) continue;
          for (std::size_t m : it->second) {
            const auto& q = tangents[m];
            const double dx = q[0] - tx, dy = q[1] - ty, dz = q[2] - z;
            if (dx * dx + dy * dy + dz * dz < o.spacing * o.spacing) {
              near = true;
              break;
            }
          }
        }
    if (near) continue;
    tangent_grid[k0].push_back(tangents.size());
    tangents.push_back({tx, ty, z});
    const double r = radius();
    double raise = o.jitter * (2.0 * unit(rng) - 1.0) + o.outward * unit(rng);
    if (o.jitter_sd > 0.0) raise += o.jitter_sd * gauss(rng);  // drawn only then: the other kinds keep their cones
    for (const auto& c : bump_centres) {
      const double d = std::hypot(c[0] - tx, c[1] - ty, c[2] - z);
      if (d < o.bump_radius)
        raise += o.bump_height * std::pow(std::cos(std::numbers::pi * d / (2.0 * o.bump_radius)), 2);
    }
    if (o.missing > 0.0 && unit(rng) < o.missing) continue;  // a hole: the tangent point stays taken
    const double depth = r - raise;
    double cr = rho - depth * nr;
    double cz = z - depth * nz;
    if (cz < r) {  // rests on the pedestal top, at the same depth below the flank
      cz = r;
      cr = o.base_radius - (depth + r * std::cos(t)) / std::sin(t);
    }
    keep(cr * std::cos(az), cr * std::sin(az), cz, r);
  }
  // The inside: random sequential addition of spheres that lie wholly inside the outline.
  for (int attempt = 0; attempt < o.attempts; ++attempt) {
    const double r = radius();
    const double x = o.base_radius * (2.0 * unit(rng) - 1.0);
    const double y = o.base_radius * (2.0 * unit(rng) - 1.0);
    const double z = height * unit(rng);
    // Under a hole or a mound the inside reaches no further than under the plain outline.
    if (synthetic_cone_depth(o, std::hypot(x, y), z) < r) continue;
    if (!overlaps(x, y, z, r)) keep(x, y, z, r);
  }
  // Particles that rolled off: on the ground beside the pedestal; the pedestal filter drops them.
  for (int m = 0; m < o.fallen; ++m) {
    const double az = 2.0 * std::numbers::pi * unit(rng);
    const double r = radius();
    const double rho = o.pedestal_radius + 0.005 + 0.04 * unit(rng);
    add(rho * std::cos(az), rho * std::sin(az), r, r);
  }
  return p;
}

/// The particles as a LIGGGHTS `write_dump ... custom id type x y z radius vx vy vz` snapshot (at rest).
inline std::string synthetic_dump_text(const postprocess::Particles& p) {
  std::string text = fmt::format(
      "ITEM: TIMESTEP\n1000\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS ff ff ff\n-0.15 0.15\n-0.15 0.15\n-0.01 "
      "0.2\nITEM: ATOMS id type x y z radius vx vy vz\n",
      p.size());
  for (std::size_t j = 0; j < p.size(); ++j)
    text += fmt::format("{} {} {:.9g} {:.9g} {:.9g} {:.9g} 0 0 0\n", p.id[j], p.type[j], p.x[j], p.y[j], p.z[j],
                        p.radius[j]);
  return text;
}

}  // namespace demsa::test
