#pragma once
// Comparing two particle states (a dump against a reference dump): particles matched by id; common, missing and
// extra ids; maximum and RMS displacement; radius mismatches; for piles also the angle of repose and h_P.
#include "postprocess/dump.hpp"
#include "postprocess/pile_angle.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace demsa::postprocess {

struct CompareOptions {
  double position_tolerance = 1e-6;  ///< largest accepted displacement of a common particle, and |Δh_P| [m]; ≥ 0
  double radius_tolerance = 1e-9;    ///< |r_A − r_B| above this is a radius mismatch [m]; ≥ 0
  double angle_tolerance = 0.5;      ///< largest accepted |Δφ| for piles [deg]; ≥ 0
  bool pile = false;                 ///< also measure and compare the angle of repose and h_P of both
  PileAngleOptions pile_options;     ///< how the pile angles are measured (of A, and of B without pile_options_b)
  /// How B's pile is measured when it stood on another pedestal (each case folder's own, from its case.json)
  std::optional<PileAngleOptions> pile_options_b;
  std::size_t max_listed = 20;  ///< at most this many ids in each list of the result

  /// Throws std::invalid_argument naming the field, its value and the rule.
  void validate() const;
};

struct PileDifference {
  double angle_a = 0, angle_b = 0;    ///< φ of A and B [deg]
  double angle_difference = 0;        ///< φ_B − φ_A [deg]
  double height_a = 0, height_b = 0;  ///< h_P of A and B [m]
  double height_difference = 0;       ///< h_P,B − h_P,A [m]
};

struct DumpComparison {
  CompareOptions options;  ///< echo
  std::size_t particles_a = 0, particles_b = 0;
  std::size_t common = 0;                         ///< ids in both
  std::size_t missing = 0;                        ///< ids in A but not in B
  std::size_t extra = 0;                          ///< ids in B but not in A
  std::vector<std::int64_t> missing_ids;          ///< the first max_listed of them, ascending
  std::vector<std::int64_t> extra_ids;            ///< the first max_listed of them, ascending
  double max_displacement = 0;                    ///< max |x_B − x_A| over common ids [m]
  std::int64_t max_displacement_id = 0;           ///< the id where it occurs (0 when nothing is common)
  double rms_displacement = 0;                    ///< sqrt(mean |x_B − x_A|²) over common ids [m]
  std::size_t radius_mismatches = 0;              ///< common ids with |r_B − r_A| > radius_tolerance
  double max_radius_difference = 0;               ///< [m]
  std::vector<std::int64_t> radius_mismatch_ids;  ///< the first max_listed of them, ascending
  std::optional<PileDifference> pile;             ///< when options.pile
  std::vector<std::string> violations;            ///< why it is beyond tolerance, one sentence each; empty = within
  bool within_tolerance() const { return violations.empty(); }
};

/// Compares B against A. `name_a` / `name_b` name them in error messages (duplicate ids are an InputError).
DumpComparison compare_particles(const Particles& a, const Particles& b, const CompareOptions& options = {},
                                 const std::string& name_a = "A", const std::string& name_b = "B");

/// Compares the last frames of two dump files.
DumpComparison compare_dumps(const std::filesystem::path& a, const std::filesystem::path& b,
                             const CompareOptions& options = {});

}  // namespace demsa::postprocess
