#pragma once
// The rotating drum seen through its end plate (GranuDrum-like testers): a time-averaged side view of the powder,
// its free surface, and the observables a calibration compares. A laboratory photograph and a simulated case are
// measured by the same code: both become a DrumImage (the material fraction seen in each pixel, with where the drum
// is in the picture), and measure_drum_surface() reads both alike.
//
// Image frame (as a viewer shows the picture): column c from the left, row r from the top; the drum frame: x to the
// right, y up (against gravity), origin at the drum's centre, in metres. A pixel's centre is at
// x = (c + 0.5 - centre_col) * pixel_m, y = (centre_row - r - 0.5) * pixel_m.
#include "postprocess/error.hpp"
#include "postprocess/image.hpp"  // GreyImage, RgbImage, read_grey_image, write_grey_png, write_rgb_png

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace demsa::postprocess {

/// Which way the drum turns as the picture shows it. Clockwise: the wall on the left carries the powder up, so the
/// free surface is high on the left (the GranuDrum images).
enum class DrumRotation { clockwise, counterclockwise };
/// "clockwise" / "counterclockwise"; throws std::invalid_argument listing the valid names.
DrumRotation drum_rotation_from_string(const std::string& name);
std::string to_string(DrumRotation rotation);

/// Where the drum is in a picture and how large.
struct DrumGeometry {
  double centre_col = 0.0;  ///< the drum's centre in pixels (fractional), column from the left
  double centre_row = 0.0;  ///< row from the top
  double radius_px = 0.0;   ///< the drum's inner radius in pixels (> 0)
  double radius_m = 0.0;    ///< the drum's inner radius [m] (> 0): sets the pixel size radius_m / radius_px
  DrumRotation rotation = DrumRotation::clockwise;
  double pixel_m() const { return radius_m / radius_px; }
  /// The geometry of a square picture that spans the drum's inner diameter (the GranuDrum's images).
  static DrumGeometry spanning(int width, int height, double radius_m, DrumRotation rotation);
};

/// What a picture holds: the fraction of the time each pixel showed material, in [0, 1] (1: always powder).
struct DrumImage {
  GreyImage material;
  DrumGeometry geometry;
};

/// A photograph as a DrumImage. The powder is dark and the empty drum light (`dark_material`, the GranuDrum's
/// images), or the reverse. The grey levels are mapped to material fractions between the levels of the empty and
/// the filled part of the drum (documented with the implementation: how the two levels are found and why).
DrumImage drum_image_from_photograph(const GreyImage& photograph, const DrumGeometry& geometry,
                                     bool dark_material = true);

/// The two grey levels of a photograph that drum_image_from_photograph maps to material fractions 0 and 1, found
/// among the pixels whose centres lie within `judged_radius`·R of the drum's centre: Otsu's threshold (Otsu 1979)
/// splits them into two classes, and each class's median is its level (docs/explanation/drum-images.md).
struct PhotographLevels {
  double empty = 0.0;         ///< grey level of the empty drum, in [0, 1] (material fraction 0)
  double material = 0.0;      ///< grey level of the bed, in [0, 1] (material fraction 1)
  double threshold = 0.0;     ///< Otsu's threshold between the two classes, in [0, 1]
  double separability = 0.0;  ///< Otsu's η = between-class over total variance, in [0, 1]
  long pixels = 0;            ///< pixels the levels were found among
};
/// The levels of a photograph (above). Throws InputError when the judged circle does not show two levels: Otsu's η
/// below k_min_separability (an empty or a full drum, or a picture without contrast).
PhotographLevels photograph_levels(const GreyImage& photograph, const DrumGeometry& geometry, bool dark_material = true,
                                   double judged_radius = 0.77);
/// The separability η below which a photograph is taken to show one level only. A grey level with Gaussian noise and
/// nothing else gives η = 2/π ≈ 0.64 (Otsu's split at its mean); a drum with a bed gives η > 0.9.
constexpr double k_min_separability = 0.8;

/// The time-averaged side view of a simulated drum: every snapshot adds each particle's projected disc (the camera
/// looks along the drum's axis, so a sphere covers the disc of its radius around its centre's (x, y)), clipped to
/// [0, 1] per snapshot (a pixel covered by two particles is covered once), then the snapshots are averaged.
/// Coordinates in the drum frame [m].
class DrumOccupancy {
 public:
  /// A picture of `size` × `size` pixels spanning the drum's inner diameter (radius `radius_m`), as the lab's images.
  DrumOccupancy(int size, double radius_m, DrumRotation rotation);
  /// Adds one snapshot; the spans have one entry per particle.
  void add_snapshot(std::span<const double> x, std::span<const double> y, std::span<const double> radius);
  int snapshots() const { return m_snapshots; }
  /// The average over the snapshots added (throws InputError when none was).
  DrumImage image() const;

 private:
  DrumGeometry m_geometry;
  GreyImage m_sum;
  int m_snapshots = 0;
};

struct DrumSurfaceOptions {
  /// Only the region within this fraction of the radius is judged: near the rim a photograph is least reliable
  /// (reflections, the rim's shadow); (0, 1].
  double judged_radius = 0.77;
  /// The dynamic angle's line is fitted over the free surface within this fraction of the radius of the centre, in x
  /// (the central part, away from the curled ends of an S); (0, judged_radius].
  double angle_half_width = 0.5;
  /// Positions across the drum at which the surface height is reported, as fractions of the radius in x
  /// (symmetric, left to right), each within judged_radius.
  std::vector<double> stations = {-0.6, -0.45, -0.3, -0.15, 0.0, 0.15, 0.3, 0.45, 0.6};
  /// The material fraction that counts as the free surface (0, 1).
  double threshold = 0.5;
  /// Throws std::invalid_argument naming the field, its value and the rule.
  void validate() const;
};

/// A photograph's rim (its dark line and shadow) lies beyond this fraction of the radius; bed_area reads the
/// material there from this radius inwards.
constexpr double k_rim_radius = 0.98;

/// The material fractions whose crossings bound the surface's band in a column: `band` is the height between the
/// crossings of k_band_low and of k_band_high nearest to the surface, above and below it (on a profile that rises
/// monotonically, their first crossings scanning the column from the top). The surface itself is the first crossing
/// of `threshold` from the top that the next 5 pixels keep (a dark speck above it is passed over).
constexpr double k_band_low = 0.25;
constexpr double k_band_high = 0.75;

/// The free surface at one position across the drum.
struct SurfacePoint {
  double x = 0.0;       ///< [m], drum frame
  double height = 0.0;  ///< y of the surface [m], drum frame
  double band = 0.0;    ///< the width of the surface's band in y (fluctuation and blur) [m]
};

struct DrumSurfaceResult {
  /// The free surface per pixel column within the judged region (columns where no surface was found are left out).
  std::vector<SurfacePoint> surface;
  /// Dynamic angle of repose [deg]: a robust line fit (documented with the implementation) to `surface` over
  /// |x| ≤ angle_half_width·R; positive when the surface rises towards the wall that carries the powder up (left for
  /// clockwise), so the same material gives the same sign in either direction.
  double dynamic_angle = 0.0;
  double angle_uncertainty = 0.0;  ///< [deg] from the surface's band (documented with the implementation)
  /// Surface heights at DrumSurfaceOptions::stations (same order) [m]; mirrored in x for counterclockwise drums, so
  /// station i is always on the side the powder is carried up to for negative fractions.
  /// Each point's x is where the station lies in the picture's drum frame; its height and band are linear between
  /// the two neighbouring columns, and NaN where the surface at the station lies outside the judged region (a steep
  /// surface can leave the judged circle before a station far from the centre).
  std::vector<SurfacePoint> stations;
  /// Area of the bed (material fraction ≥ threshold) within the whole drum [m²]; beyond k_rim_radius·R (a
  /// photograph's rim and its shadow) each pixel takes the material at k_rim_radius·R on its radius.
  double bed_area = 0.0;
  double fill_fraction = 0.0;  ///< bed_area over the drum's cross-section π R²
  /// The S shape [m]: how far the surface departs from its fitted line, as the cubic term of a fit over the judged
  /// region (documented with the implementation; 0 for a straight surface, positive for the S of a fast drum).
  double s_shape = 0.0;
  /// The dynamic angle's fitted line in the picture's drum frame: y = angle_line_height + angle_line_slope·x (not
  /// mirrored), for figures.
  double angle_line_height = 0.0;  ///< [m]
  double angle_line_slope = 0.0;   ///< dy/dx [-]
};

/// The free surface and the observables of a DrumImage. Throws InputError when the picture holds no free surface in
/// the judged region (an empty or a full drum).
DrumSurfaceResult measure_drum_surface(const DrumImage& image, const DrumSurfaceOptions& options = {});

/// A photograph file measured: read_grey_image, DrumGeometry::spanning (a square picture spanning the drum's inner
/// diameter of radius `radius_m`), drum_image_from_photograph and measure_drum_surface. An InputError names the file.
DrumSurfaceResult measure_drum_photograph(const std::filesystem::path& file, double radius_m, DrumRotation rotation,
                                          const DrumSurfaceOptions& options = {}, bool dark_material = true);

/// The area [m²] within judged_radius·R where two pictures of the same drum disagree about material (thresholded at
/// `threshold`): the mismatch between a photograph and a simulation. The two are compared in the drum frame, so
/// their pixel grids may differ; on a's grid, b read bilinearly and mirrored in x when the two drums turn opposite
/// ways (so both show the powder carried up on the same side). Drums of different radii throw InputError.
double drum_mismatch_area(const DrumImage& a, const DrumImage& b, double judged_radius = 0.77, double threshold = 0.5);

/// A picture for the report: `a` in grey, the thresholded material of `b` over it in colour, the judged circle drawn.
/// b is read as drum_mismatch_area reads it.
RgbImage drum_overlay(const DrumImage& a, const DrumImage& b, double judged_radius = 0.77, double threshold = 0.5);

/// A picture of a measurement: the picture's material in grey (material dark), the judged circle (cyan), the band's
/// edges (yellow: the crossings of k_band_low and k_band_high), the free surface (red), the dynamic angle's line over
/// |x| ≤ angle_half_width·R (green) and the stations (magenta crosses). `result` is measure_drum_surface(image,
/// options).
RgbImage drum_surface_overlay(const DrumImage& image, const DrumSurfaceResult& result,
                              const DrumSurfaceOptions& options = {});

}  // namespace demsa::postprocess
