#pragma once
// Initial particle assemblies, identical for every sample of a study (paper §3: "the initial position of each
// particle must be identical for each simulation"): they depend only on the experiment settings and the seed.
#include "orchestrator/study/config.hpp"

#include <cstdint>
#include <vector>

namespace demsa::cases {

struct Particle {
  double x = 0, y = 0, z = 0;  ///< centre [m]
  double radius = 0;           ///< [m]
};

/// `count` radii from N(mean, sd) truncated to [r_min, r_max] by rejection (paper Table 2), drawn with GSL's
/// MT19937 seeded with `seed`. The same seed gives the same radii on every machine.
std::vector<double> truncated_normal_radii(const study::RadiusDistribution& distribution, int count,
                                           std::uint64_t seed);

/// One horizontal disc of the pile: particle centres in the plane z = 0 (the height is set by the schedule).
using Disc = std::vector<Particle>;

/// Fills one disc of radius `disc_radius` by concentric annuli (paper §3.1, Fig. 1a): ring k has radius 2 r_U k
/// (k = 0 is the centre particle) and is used while 2 r_U k + r_U ≤ disc_radius; along a ring, consecutive
/// particles are spaced by the chord r_a + r_b + gap, and a ring closes when the next particle would overlap its
/// first. Consumes radii from `radii` starting at `next`, advancing it; returns an empty disc when none are left.
Disc fill_disc(const std::vector<double>& radii, std::size_t& next, double r_upper, double disc_radius, double gap);

/// The pile's initial column and its appended discs (paper §3.1–3.2).
struct PileAssembly {
  std::vector<Disc> discs;       ///< every disc in order; particle z is its height at insertion
  int column_discs = 0;          ///< discs 0..column_discs-1 are present at the start
  double append_height = 0.0;    ///< z of every later disc: pedestal top + h_fu [m]
  double r_upper = 0.0;          ///< r_U: the upper radius bound [m]
  std::vector<double> radii;     ///< all radii in insertion order
  int particles() const;         ///< total count
  int column_particles() const;  ///< particles present at the start
};

/// Disc k of the column sits at z = pedestal_height + r_U + 2 r_U k while that is ≤ pedestal_height + h_fu; the
/// rest are appended at pedestal_height + h_fu, one every sqrt(4 r_U/|g|) (heights from the pedestal top: a disc
/// at r_U above the ground would cut the pedestal).
PileAssembly build_pile_assembly(const study::PileSettings& settings, std::uint64_t seed);

/// The oedometer's loose initial packing: a square lattice of cells of side 2 r_max + gap filling the box's base,
/// layer on layer from the floor, each particle shifted inside its cell by a deterministic golden-angle offset of
/// length r_max − r so that the packing is not a perfect lattice and poured it settles into a random packing.
struct OedometerAssembly {
  std::vector<Particle> particles;
  int per_layer = 0;  ///< particles per lattice layer
  int layers = 0;
  double top = 0.0;           ///< highest particle top [m]
  double solid_volume = 0.0;  ///< Σ 4/3 π r³ [m³]
};

OedometerAssembly build_oedometer_assembly(const study::OedometerSettings& settings, std::uint64_t seed);

/// The smallest surface gap |c_i − c_j| − r_i − r_j over all pairs (negative: an overlap), by a cell list.
/// +infinity when no two particles are closer than 2 r_max centre to centre (then no pair touches).
double min_pair_gap(const std::vector<Particle>& particles);

}  // namespace demsa::cases
