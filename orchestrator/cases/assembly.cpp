#include "orchestrator/cases/assembly.hpp"

#include "orchestrator/cases/physics.hpp"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <tuple>

namespace demsa::cases {

using namespace demsa::study;

std::vector<double> truncated_normal_radii(const RadiusDistribution& d, int count, std::uint64_t seed) {
  assert(d.r_min < d.r_max && d.sd > 0 && count >= 0);
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), &gsl_rng_free);
  gsl_rng_set(rng.get(), static_cast<unsigned long>(seed));
  std::vector<double> radii;
  radii.reserve(static_cast<std::size_t>(count));
  while (static_cast<int>(radii.size()) < count) {
    const double r = d.mean + gsl_ran_gaussian(rng.get(), d.sd);
    if (r >= d.r_min && r <= d.r_max) radii.push_back(r);
  }
  return radii;
}

Disc fill_disc(const std::vector<double>& radii, std::size_t& next, double r_upper, double disc_radius, double gap) {
  Disc disc;
  const double two_pi = 2.0 * std::numbers::pi;
  for (int k = 0;; ++k) {
    const double ring = 2.0 * r_upper * k;
    if (ring + r_upper > disc_radius * (1.0 + 1e-12)) break;
    if (next >= radii.size()) break;
    if (k == 0) {
      disc.push_back({0.0, 0.0, 0.0, radii[next++]});
      continue;
    }
    // Angle subtended by a chord of length c on the ring.
    const auto angle = [ring](double chord) { return 2.0 * std::asin(std::min(1.0, chord / (2.0 * ring))); };
    const double first_r = radii[next];
    double theta = 0.0;
    disc.push_back({ring, 0.0, 0.0, radii[next++]});
    double prev_r = first_r;
    while (next < radii.size()) {
      const double r = radii[next];
      const double t = theta + angle(prev_r + r + gap);
      if (t + angle(first_r + r + gap) > two_pi) break;  // would touch the ring's first particle
      theta = t;
      disc.push_back({ring * std::cos(theta), ring * std::sin(theta), 0.0, r});
      ++next;
      prev_r = r;
    }
  }
  return disc;
}

int PileAssembly::particles() const {
  int n = 0;
  for (const Disc& d : discs) n += static_cast<int>(d.size());
  return n;
}

int PileAssembly::column_particles() const {
  int n = 0;
  for (int i = 0; i < column_discs; ++i) n += static_cast<int>(discs[static_cast<std::size_t>(i)].size());
  return n;
}

PileAssembly build_pile_assembly(const PileSettings& s, std::uint64_t seed) {
  PileAssembly a;
  a.r_upper = s.radii.r_max;
  a.radii = truncated_normal_radii(s.radii, s.particles, seed);
  // Placement gap along a ring: 1 % of the smallest radius keeps neighbours apart without loosening the disc.
  const double gap = 0.01 * s.radii.r_min;
  const double base = s.pedestal_height;
  a.append_height = base + s.fill_height;
  std::size_t next = 0;
  bool in_column = true;
  for (int k = 0; next < a.radii.size(); ++k) {
    Disc disc = fill_disc(a.radii, next, a.r_upper, s.disc_radius, gap);
    assert(!disc.empty());
    const double z_column = base + a.r_upper + 2.0 * a.r_upper * k;
    in_column = in_column && z_column <= a.append_height * (1.0 + 1e-12);
    const double z = in_column ? z_column : a.append_height;
    for (Particle& p : disc) p.z = z;
    if (in_column) ++a.column_discs;
    a.discs.push_back(std::move(disc));
  }
  return a;
}

OedometerAssembly build_oedometer_assembly(const OedometerSettings& s, std::uint64_t seed) {
  OedometerAssembly a;
  const std::vector<double> radii = truncated_normal_radii(s.radii, s.particles, seed);
  // Cell gap: 10 % of r_max, so that neighbouring particles never touch before they are poured.
  const double gap = 0.1 * s.radii.r_max;
  const double cell = 2.0 * s.radii.r_max + gap;
  const int n = static_cast<int>(std::floor((s.box_side - gap) / cell));
  assert(n >= 1);
  a.per_layer = n * n;
  const double offset = -s.box_side / 2.0 + (s.box_side - n * cell) / 2.0 + cell / 2.0;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));  // golden angle [rad]
  for (std::size_t i = 0; i < radii.size(); ++i) {
    const int index = static_cast<int>(i);
    const int layer = index / a.per_layer, k = index % a.per_layer;
    const int ix = k / n, iy = k % n;
    const double r = radii[i];
    const double shift = s.radii.r_max - r;
    Particle p;
    p.radius = r;
    p.x = offset + ix * cell + shift * std::cos(golden * index);
    p.y = offset + iy * cell + shift * std::sin(golden * index);
    p.z = cell / 2.0 + layer * cell;
    a.top = std::max(a.top, p.z + r);
    a.solid_volume += 4.0 / 3.0 * std::numbers::pi * r * r * r;
    a.layers = layer + 1;
    a.particles.push_back(p);
  }
  return a;
}

double min_pair_gap(const std::vector<Particle>& particles) {
  double gap = std::numeric_limits<double>::infinity();
  if (particles.size() < 2) return gap;
  double r_max = 0;
  for (const Particle& p : particles) r_max = std::max(r_max, p.radius);
  const double h = 2.0 * r_max;  // pairs that can overlap or touch are at most 2 r_max apart
  std::map<std::tuple<long, long, long>, std::vector<std::size_t>> cells;
  const auto key = [h](const Particle& p) {
    return std::make_tuple(std::lround(std::floor(p.x / h)), std::lround(std::floor(p.y / h)),
                           std::lround(std::floor(p.z / h)));
  };
  for (std::size_t i = 0; i < particles.size(); ++i) cells[key(particles[i])].push_back(i);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Particle& a = particles[i];
    const auto [cx, cy, cz] = key(a);
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find({cx + dx, cy + dy, cz + dz});
          if (it == cells.end()) continue;
          for (const std::size_t j : it->second) {
            if (j <= i) continue;
            const Particle& b = particles[j];
            const double d =
                std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z));
            gap = std::min(gap, d - a.radius - b.radius);
          }
        }
  }
  return gap;
}

}  // namespace demsa::cases
