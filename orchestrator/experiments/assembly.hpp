#pragma once
// What every experiment's initial assembly is made of: particles, radii drawn from a particle set, and the check that
// no two overlap. An experiment's assembly (experiments/NAME/) is identical for every sample of a study (paper §3:
// "the initial position of each particle must be identical for each simulation"): it depends only on the settings
// and the seed.
#include "orchestrator/study/config.hpp"

#include <cstdint>
#include <vector>

namespace demsa::experiments {

struct Particle {
  double x = 0, y = 0, z = 0;  ///< centre [m]
  double radius = 0;           ///< [m]
};

/// `count` radii from N(mean, sd) truncated to [r_min, r_max] by rejection (paper Table 2), drawn with GSL's
/// MT19937 seeded with `seed`. The same seed gives the same radii on every machine.
std::vector<double> truncated_normal_radii(const study::RadiusDistribution& distribution, int count,
                                           std::uint64_t seed);

/// The smallest surface gap |c_i − c_j| − r_i − r_j over all pairs (negative: an overlap), by a cell list.
/// +infinity when no two particles are closer than 2 r_max centre to centre (then no pair touches).
double min_pair_gap(const std::vector<Particle>& particles);

}  // namespace demsa::experiments
