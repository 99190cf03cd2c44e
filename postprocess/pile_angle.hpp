#pragma once
// The steepest angle of repose of a pile, measured as in the paper (§3.3, Fig. 4):
//  1. keep the particles on the pedestal: centre within the pedestal radius and at or above its top (§3.2 filter);
//  2. pile height h_P = highest particle top (z + r) above the pedestal top;
//  3. cylindrical coordinates with the origin at the centre of the pile's base (pedestal axis, pedestal top);
//  4. φ_N directions e_i = (cos φ_i, −sin φ_i), φ_i = 360°·i/φ_N (paper eq. 9);
//  5. equidistant levels between 0.2 h_P and 0.75 h_P; in each direction and level the particle reaching furthest
//     out is the boundary particle. A particle belongs to direction i and level k when its sphere meets the
//     vertical half-plane of e_i and the horizontal plane z_k (so every direction sees the pile's outline in its own
//     cross-section, however many particles there are);
//  6. one orthogonal (total least squares) line per direction through the boundary points in the (radial distance,
//     height) plane; its angle against the horizontal;
//  7. the mean angle over the directions is φ; E_φ = (φ̂ − φ)² against the target φ̂.
// AngleEstimator::robust replaces steps 5–6 by the outermost points of the pile's horizontal sections in a sector
// about each direction, at the exact level heights, and a Theil–Sen line, and step 7's mean by the median over the
// directions.
#include "postprocess/dump.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace demsa::postprocess {

/// Which point of a boundary particle enters the line fit.
enum class BoundaryPointKind {
  centre,   ///< the particle centre: radial distance of the centre along e_i and its height (paper §3.3; default)
  surface,  ///< the particle's outermost point in the direction's cross-section at the level height. The heights
            ///< are then exact and all roughness is radial, which the orthogonal fit (made for equal noise in both
            ///< coordinates) turns into a flatter line: about 1–2° low on rough piles, exact on smooth ones.
};
/// "surface" / "centre"; throws std::invalid_argument listing the valid names.
BoundaryPointKind boundary_point_kind_from_string(const std::string& name);
std::string to_string(BoundaryPointKind kind);

/// How the boundary points of a direction become its angle, and the directions the pile's angle.
enum class AngleEstimator {
  paper,   ///< §3.3 as published: the outermost particle per direction and level (its centre, or its surface with
           ///< `point`), one orthogonal (TLS) line per direction, the mean over the directions. Reads low on rough
           ///< flanks: the roughness is mostly radial, which an orthogonal fit turns into a flatter line, and one
           ///< particle sticking out at an end level tilts the line (synthetic cones with 1–2 mm of surface
           ///< jitter: 0.2–1 deg low on average, docs/explanation/benchmarks.md "Angle estimators").
  robust,  ///< the outermost point of the pile's horizontal section at each level's exact height, in a sector about
           ///< each direction whose width at the surface is one particle radius either side (`point` is ignored),
           ///< so all roughness is in the radial distance and as many particles compete for a level at the top of
           ///< the flank as at its foot (the paper's half-plane section lets more compete at the top, where a steep
           ///< rough flank then reads further out: +0.2 to +0.5 deg on cones with Gaussian normal jitter of
           ///< 1.5 mm); per direction a Theil–Sen line of radial distance on height
           ///< (median of the pairwise slopes: Theil 1950, Sen 1968), which a few levels caught on a particle sticking
           ///< out (or a gap) do not tilt; the median over the directions, which the directions that cross a mound
           ///< or a hole in the flank do not move (synthetic cones of nine kinds of surface: mean bias within
           ///< ±0.13 deg on each, where the mean over directions read up to 0.69 deg high on mounds;
           ///< docs/explanation/benchmarks.md "Angle estimators").
};
/// "paper" / "robust"; throws std::invalid_argument listing the valid names.
AngleEstimator angle_estimator_from_string(const std::string& name);
std::string to_string(AngleEstimator estimator);
/// The valid names, in the order the docs list them.
std::vector<std::string> angle_estimator_names();

/// The band of levels the robust estimator uses unless told otherwise: 0.25–0.80 h_P instead of the paper's
/// 0.20–0.75. At 0.2 h_P the cross-section still cuts the flank's lowest particles, which rest on the pedestal's edge
/// and reach less far out than the flank above them; a regression of radial distance on height (unlike the paper's
/// orthogonal fit) turns that into a flatter line. On synthetic cones (bench/angle_estimators.cpp, 20 seeds per
/// angle from 22° to 41°) the largest mean error over the angles went from −0.42° / −0.55° / +0.45° (smooth / 1 mm /
/// 2 mm of jitter) at 0.20–0.75 to −0.30° / −0.23° / +0.47° at 0.25–0.80 (docs/explanation/benchmarks.md).
constexpr double k_robust_level_low = 0.25;
constexpr double k_robust_level_high = 0.80;
/// Unless level_low is given, the robust estimator's lowest level is also at least this many of the largest particle
/// radius above the pedestal top (1.5 r_max: 5.25 mm for particle set 1, above 0.25 h_P on piles lower than 21 mm,
/// i.e. flanks below about 25°). Particles resting on the pedestal's edge reach up to 2 r_max and crowd the foot of a
/// shallow flank; the outermost of them reads further out than the flank above, and the line flatter. On synthetic
/// 22° cones of set 1 (bench/angle_estimators.cpp, 20 seeds) the sector sections read −0.50° / −0.42° / −0.41° on
/// average (±1 mm, ±2 mm of jitter, sticking out) from 0.25 h_P, and −0.35° / −0.18° / −0.27° with this floor
/// (docs/explanation/benchmarks.md).
constexpr double k_robust_floor_radii = 1.5;
/// The paper's band of levels (§3.3: 0.2 h_P to 0.75 h_P), which the paper's estimator uses unless told otherwise.
constexpr double k_paper_level_low = 0.20;
constexpr double k_paper_level_high = 0.75;

struct PileAngleOptions {
  double pedestal_radius = 0.050;  ///< r_cy: particles with centre further from the axis are dropped [m] (> 0)
  double pedestal_top = 0.005;     ///< z of the pedestal top (= its height on a ground at 0): lower centres are
                                   ///< dropped, and h_P and the levels are measured from it [m]
  double axis_x = 0.0;             ///< pile axis (origin of the cylindrical coordinates) [m]
  double axis_y = 0.0;             ///< [m]
  int particle_type = 1;           ///< atom type of the particles (demsa: 1); 0 = every atom counts
  int directions = 180;            ///< φ_N, number of directions (paper: 180); ≥ 1
  int levels = 10;                 ///< number of equidistant height levels; ≥ 2
  /// Lowest level as a fraction of h_P, in (0, level_high); unset: the estimator's band (k_paper_level_low for
  /// `paper`, k_robust_level_low for `robust`).
  std::optional<double> level_low;
  /// Highest level as a fraction of h_P, in (level_low, 1); unset: the estimator's band (k_paper_level_high,
  /// k_robust_level_high).
  std::optional<double> level_high;
  int min_points = 3;                                   ///< a direction with fewer boundary points is skipped; ≥ 2
  BoundaryPointKind point = BoundaryPointKind::centre;  ///< which point of a boundary particle is fitted (paper)
  AngleEstimator estimator = AngleEstimator::paper;     ///< line fit and averaging (see AngleEstimator)
  double target_angle = 33.5;  ///< φ̂ for E_φ [deg] (paper: mean of the measured 32° and 35°)

  /// The levels measured: level_low / level_high when set, else the estimator's band.
  double low_level() const;
  double high_level() const;

  /// Throws std::invalid_argument naming the field, its value and the rule.
  void validate() const;
};

/// The outermost particle of one direction at one level (a coloured particle of the paper's Fig. 4a).
struct BoundaryParticle {
  int direction = 0;                       ///< i_φ
  int level = 0;                           ///< k, 0 = lowest level
  std::size_t index = 0;                   ///< row in the Particles given to measure_pile_angle
  std::int64_t id = 0;                     ///< atom id
  double x = 0, y = 0, z = 0, radius = 0;  ///< the particle [m]
  double radial = 0;                       ///< fitted point: distance from the axis along e_i [m]
  double height = 0;                       ///< fitted point: height above the pedestal top [m]
};

/// The fitted line of one direction (a line element of the paper's Fig. 4b).
struct DirectionLine {
  int direction = 0;        ///< i_φ
  double phi = 0;           ///< φ_i [deg]
  double ex = 1, ey = 0;    ///< e_i = (cos φ_i, −sin φ_i)
  int points = 0;           ///< boundary points fitted
  bool used = false;        ///< false: fewer than min_points boundary points (or all at one spot): not counted
  double angle = 0;         ///< angle of repose of this direction [deg]; positive when the flank falls outwards
  double rms_distance = 0;  ///< RMS orthogonal distance of the points from the line [m]
  /// Line segment between the lowest and the highest level, in the (radial, height above pedestal top) plane [m].
  double radial_low = 0, height_low = 0, radial_high = 0, height_high = 0;
};

struct PileAngleResult {
  PileAngleOptions options;         ///< echo of the options used (robust: point = surface, the points it fits;
                                    ///< level_low and level_high set to the band measured)
  std::size_t particles_total = 0;  ///< atoms given (of particle_type)
  std::size_t particles_on_pedestal = 0;
  double pile_height = 0;                  ///< h_P above the pedestal top [m]
  std::vector<double> level_heights;       ///< z_k above the pedestal top [m]
  std::vector<BoundaryParticle> boundary;  ///< ordered by direction, then level
  std::vector<DirectionLine> lines;        ///< one per direction, used or not
  int directions_used = 0;
  /// φ, the pile's angle: the mean over the used directions (paper), their median (robust) [deg]
  double angle = 0;
  double angle_sd = 0;                  ///< sample standard deviation over the used directions [deg]
  double angle_min = 0, angle_max = 0;  ///< range over the used directions [deg]
  double angle_error = 0;               ///< E_φ = (φ̂ − φ)² [deg²]
};

/// Indices of the particles kept on the pedestal (step 1 above).
std::vector<std::size_t> pedestal_particles(const Particles& particles, const PileAngleOptions& options);

/// Measures the angle of repose. Throws InputError when no particle is on the pedestal or no direction has
/// min_points boundary points; std::invalid_argument for invalid options.
PileAngleResult measure_pile_angle(const Particles& particles, const PileAngleOptions& options = {});

/// Theil–Sen line u = intercept + slope·v through points (u_j, v_j) (Theil 1950, Sen 1968): the slope is the median
/// of the pairwise slopes (u_k − u_j)/(v_k − v_j) over the pairs with v_j ≠ v_k, the intercept the median of
/// u_j − slope·v_j. Unaffected by up to about 29 % of the points lying anywhere. Requires two distinct v.
struct TheilSenLine {
  double intercept = 0, slope = 0;
};
TheilSenLine fit_theil_sen_line(const std::vector<double>& u, const std::vector<double>& v);

/// Orthogonal (total least squares) line through points (u_j, v_j): the line through their centroid along the
/// principal axis of their scatter (Golub & Van Loan, §12.3 on TLS; SVD of the centred points). Returns the unit
/// direction (du, dv) with du ≥ 0 and the centroid. Requires at least 2 points.
struct TlsLine {
  double u0 = 0, v0 = 0;  ///< centroid
  double du = 1, dv = 0;  ///< unit direction
  double rms_distance = 0;
};
TlsLine fit_tls_line(const std::vector<double>& u, const std::vector<double>& v);

}  // namespace demsa::postprocess
