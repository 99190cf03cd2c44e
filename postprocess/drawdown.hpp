#pragma once
// The draw-down test (Roessler, Richter, Katterfeld & Will 2019, Powder Technol. 343): a box of the material empties
// through a slot in its floor and leaves a static slope on each side of the slot. Measured here: the slope angle of
// the material left in the box, and the discharged mass and rate from the run's discharge record.
//
// Slope: the box is periodic along the slot (y); its depth is cut into `slices` planes across the slope. In each
// slice, the surface is the highest particle top (z + r) in x bins of `bin_width`; on each side of the slot the
// surface points between the slot edge + `edge_skip` and the wall − `wall_skip` get a Theil–Sen line (median of the
// pairwise slopes: Theil 1950, Sen 1968), robust against the odd particle sticking out; a side's angle is the median
// over the slices of atan |slope|, and the slope angle the mean of the two sides.
#include "postprocess/dump.hpp"

#include <filesystem>
#include <optional>
#include <vector>

namespace demsa::postprocess {

struct DrawdownSlopeOptions {
  double width = 0.102;  ///< inner width of the box, wall to wall, across the slot (x ∈ [−width/2, width/2]) [m]
  double slot_width = 0.03;  ///< the slot, centred on x = 0 [m]
  double y_low = 0.0;        ///< the periodic depth along the slot: y ∈ [y_low, y_low + depth) [m]
  double depth = 0.02;       ///< [m]
  double floor_z = 0.0;      ///< particles with centres below are not in the box [m]
  long skip_ids = 0;         ///< atoms 1..skip_ids (a frozen floor layer) are not material left in the box
  int slices = 5;            ///< planes across the slope; >= 1
  double bin_width = 3e-3;   ///< [m], > 0
  double edge_skip = 4e-3;   ///< surface points this close to the slot edge are not fitted [m]
  double wall_skip = 6e-3;   ///< ... nor this close to a wall [m]
  int min_points = 4;        ///< a slice with fewer surface points on a side gives that side no line; >= 2
  void validate() const;     ///< throws std::invalid_argument naming the field
};

struct DrawdownSlope {
  double angle = 0.0;                             ///< mean of the two sides [deg]
  double angle_left = 0.0, angle_right = 0.0;     ///< medians over the slices [deg]
  std::vector<double> slices_left, slices_right;  ///< each slice's angle [deg]
  std::vector<double> profile_x, profile_z;       ///< the surface points of every slice and side [m]
  long particles_left = 0;                        ///< particles of the material in the box
  double mass_left = 0.0;                         ///< their mass [kg] (with `density`)
};

/// Measures the slope of the particles left in the box. Throws InputError when a side has no slice with min_points
/// surface points (an empty box, a box still full), std::invalid_argument for invalid options.
DrawdownSlope measure_drawdown_slope(const Particles& particles, const DrawdownSlopeOptions& options, double density);

/// The discharge record: time since the slot opened [s] and the mass discharged by then [kg], in time order.
struct DischargeRecord {
  std::vector<double> time, mass;
};

/// Reads drawdown_discharge.txt: a `#` header, then rows `t_open discharged_kg atoms`. Throws ParseError (file, line)
/// on a malformed row, a time that goes back or a mass below zero.
DischargeRecord read_discharge(const std::filesystem::path& path);

/// The discharge rate [kg/s]: the least-squares slope of mass against time over the rows between 20 % and 80 % of
/// the final discharged mass (the steady flow, without its start and its end). Throws InputError with fewer than two
/// such rows (nothing, or too little, flowed).
double discharge_rate(const DischargeRecord& record);

}  // namespace demsa::postprocess
