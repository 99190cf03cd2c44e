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

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace demsa::postprocess {

/// A grey image: `width` × `height` values in [0, 1], row 0 at the top, stored row by row.
struct GreyImage {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;  ///< pixels[row * width + col]
  float at(int col, int row) const { return pixels[static_cast<std::size_t>(row) * width + col]; }
  float& at(int col, int row) { return pixels[static_cast<std::size_t>(row) * width + col]; }
};

/// Reads a BMP or PNG (grey, palette or colour; 8 or 16 bits) through stb_image into its luminance (ITU-R BT.601
/// weights for colour) in [0, 1]. A file that is not a readable image, not a regular file, or larger than
/// `max_pixels` throws ParseError naming the file and the reason.
GreyImage read_grey_image(const std::filesystem::path& file, long max_pixels = 64L * 1024 * 1024);

/// Writes an 8-bit grey PNG through stb_image_write, atomically enough for a case folder (a temporary file renamed).
void write_grey_png(const std::filesystem::path& file, const GreyImage& image);

/// An 8-bit RGB image, for overlays in the report.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<unsigned char> pixels;  ///< 3 bytes per pixel, row 0 at the top
};
void write_rgb_png(const std::filesystem::path& file, const RgbImage& image);

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
  std::vector<SurfacePoint> stations;
  double bed_area = 0.0;     ///< area of the bed (material fraction ≥ threshold) within the whole drum [m²]
  double fill_fraction = 0.0;  ///< bed_area over the drum's cross-section π R²
  /// The S shape [m]: how far the surface departs from its fitted line, as the cubic term of a fit over the judged
  /// region (documented with the implementation; 0 for a straight surface, positive for the S of a fast drum).
  double s_shape = 0.0;
};

/// The free surface and the observables of a DrumImage. Throws InputError when the picture holds no free surface in
/// the judged region (an empty or a full drum).
DrumSurfaceResult measure_drum_surface(const DrumImage& image, const DrumSurfaceOptions& options = {});

/// The area [m²] within judged_radius·R where two pictures of the same drum disagree about material (thresholded at
/// `threshold`): the mismatch between a photograph and a simulation. The two are compared in the drum frame, so
/// their pixel grids may differ.
double drum_mismatch_area(const DrumImage& a, const DrumImage& b, double judged_radius = 0.77, double threshold = 0.5);

/// A picture for the report: `a` in grey, the thresholded material of `b` over it in colour, the judged circle drawn.
RgbImage drum_overlay(const DrumImage& a, const DrumImage& b, double judged_radius = 0.77, double threshold = 0.5);

}  // namespace demsa::postprocess
