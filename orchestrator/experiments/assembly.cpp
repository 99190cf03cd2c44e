#include "orchestrator/experiments/assembly.hpp"

#include "orchestrator/util/signals.hpp"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <tuple>

namespace demsa::experiments {

using namespace demsa::study;

std::vector<double> truncated_normal_radii(const RadiusDistribution& d, int count, std::uint64_t seed) {
  assert(d.r_min < d.r_max && d.sd > 0 && count >= 0);
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), &gsl_rng_free);
  gsl_rng_set(rng.get(), static_cast<unsigned long>(seed));
  std::vector<double> radii;
  radii.reserve(static_cast<std::size_t>(count));
  for (std::uint64_t draw = 1; static_cast<int>(radii.size()) < count; ++draw) {
    if (draw % 4096 == 0) util::throw_if_stop_raised();
    const double r = d.mean + gsl_ran_gaussian(rng.get(), d.sd);
    if (r >= d.r_min && r <= d.r_max) radii.push_back(r);
  }
  return radii;
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

}  // namespace demsa::experiments
