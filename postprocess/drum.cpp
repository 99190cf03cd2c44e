#include "postprocess/drum.hpp"

#include "postprocess/pile_angle.hpp"  // fit_theil_sen_line

#include <fmt/core.h>
#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <stdexcept>

namespace demsa::postprocess {

namespace {

constexpr double k_rad_to_deg = 180.0 / std::numbers::pi;

double median_of(std::vector<double> v) {
  assert(!v.empty());
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  if (v.size() % 2 == 1) return v[mid];
  const double upper = v[mid];
  return 0.5 * (*std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)) + upper);
}

void check_geometry(const DrumGeometry& g) {
  if (!(g.radius_px > 0.0) || !std::isfinite(g.radius_px))
    throw std::invalid_argument(fmt::format("DrumGeometry.radius_px = {}: must be positive", g.radius_px));
  if (!(g.radius_m > 0.0) || !std::isfinite(g.radius_m))
    throw std::invalid_argument(fmt::format("DrumGeometry.radius_m = {}: must be positive", g.radius_m));
  if (!std::isfinite(g.centre_col) || !std::isfinite(g.centre_row))
    throw std::invalid_argument(
        fmt::format("DrumGeometry centre ({}, {}): must be finite", g.centre_col, g.centre_row));
}

void check_image(const GreyImage& image, const char* what) {
  if (image.width <= 0 || image.height <= 0)
    throw InputError(fmt::format("{} has no pixels ({} × {})", what, image.width, image.height));
  assert(image.pixels.size() == static_cast<std::size_t>(image.width) * image.height);
}

/// The pixel's centre in the drum frame, in pixels (x right, y up).
double x_px_of(const DrumGeometry& g, int col) { return col + 0.5 - g.centre_col; }
double y_px_of(const DrumGeometry& g, int row) { return g.centre_row - row - 0.5; }

/// The material fraction of `image` at a point of the drum frame [m], bilinear between pixel centres (the nearest
/// edge pixel beyond the picture).
double sample(const DrumImage& image, double x_m, double y_m) {
  const DrumGeometry& g = image.geometry;
  const GreyImage& m = image.material;
  const double u = std::clamp(x_m / g.pixel_m() + g.centre_col - 0.5, 0.0, static_cast<double>(m.width - 1));
  const double v = std::clamp(g.centre_row - y_m / g.pixel_m() - 0.5, 0.0, static_cast<double>(m.height - 1));
  const int c0 = std::min(static_cast<int>(u), m.width - 1), r0 = std::min(static_cast<int>(v), m.height - 1);
  const int c1 = std::min(c0 + 1, m.width - 1), r1 = std::min(r0 + 1, m.height - 1);
  const double fu = u - c0, fv = v - r0;
  return (1 - fv) * ((1 - fu) * m.at(c0, r0) + fu * m.at(c1, r0)) + fv * ((1 - fu) * m.at(c0, r1) + fu * m.at(c1, r1));
}

// ------------------------------------------------------------------------------------------------ column scan

/// One pixel column's free surface: the heights [px, drum frame] of the surface and of its band's edges.
struct ColumnCrossing {
  int col = 0;
  double x_px = 0.0;
  double upper = 0.0;    ///< the crossing of k_band_low next above the surface (the band's top)
  double surface = 0.0;  ///< the first lasting crossing of the threshold, from the top
  double lower = 0.0;    ///< the crossing of k_band_high next below the surface (the band's bottom)
};

/// A surface crossing counts when this many pixels from it down (fewer at the bottom of the judged circle) all reach
/// the threshold: a dark speck above the surface shorter than that (dust on the end plate, a clump in flight; 1 mm on
/// the GranuDrum's images) is passed over, since the surface is the first crossing into material that stays.
constexpr int k_persist_px = 5;

/// Where `level` lies between rows row − 1 and row (f(row − 1) < level ≤ f(row)), linearly between their centres.
double crossing_height(const DrumImage& image, int col, int row, double level) {
  const double f0 = image.material.at(col, row - 1), f1 = image.material.at(col, row);
  return y_px_of(image.geometry, row - 1) - (level - f0) / (f1 - f0);
}

/// One column's surface and band between rows top..bottom (inclusive), or none. The surface is the first lasting
/// crossing of the threshold scanning down from the top; none when the column starts in lasting material (the surface
/// lies above the judged circle, or the column is full) or never reaches it for good (the column is empty). The band's
/// edges are the crossings of k_band_low and k_band_high nearest to the surface, above and below it (on a monotone
/// profile, their first crossings from the top); none when one lies outside the judged circle. Searched from the
/// surface rather than from the top, so that a speck the surface passed over does not widen the band, and without
/// the surface's persistence, which on a slowly rising profile would push the band's lower edge down by one grey
/// level's wiggle.
std::optional<ColumnCrossing> scan_column(const DrumImage& image, int col, int top, int bottom, double threshold) {
  const GreyImage& m = image.material;
  const auto lasts = [&](int row) {
    for (int r = row; r <= std::min(bottom, row + k_persist_px - 1); ++r)
      if (m.at(col, r) < threshold) return false;
    return true;
  };
  int row = top;
  while (row <= bottom && (m.at(col, row) < threshold || !lasts(row))) ++row;
  if (row > bottom || row == top) return std::nullopt;
  // Here f(row − 1) < threshold: had the row above reached it, its run would have lasted too and been taken.
  ColumnCrossing c;
  c.col = col;
  c.x_px = x_px_of(image.geometry, col);
  c.surface = crossing_height(image, col, row, threshold);
  // The nearest crossing of a level: upwards from the surface row for a level at or below the threshold, downwards
  // for one above it.
  const auto nearest = [&](double level) -> std::optional<double> {
    if (level <= threshold) {
      for (int r = row; r > top; --r)
        if (m.at(col, r - 1) < level && m.at(col, r) >= level) return crossing_height(image, col, r, level);
    } else {
      for (int r = row; r <= bottom; ++r)
        if (m.at(col, r - 1) < level && m.at(col, r) >= level) return crossing_height(image, col, r, level);
    }
    return std::nullopt;
  };
  const std::optional<double> upper = nearest(k_band_low), lower = nearest(k_band_high);
  if (!upper || !lower) return std::nullopt;
  c.upper = *upper;
  c.lower = *lower;
  return c;
}

/// Every column of the judged circle with a surface and a band inside it. The rim, its shadow and reflections lie
/// outside the judged circle, so no scan ever starts on them.
std::vector<ColumnCrossing> scan_columns(const DrumImage& image, double judged_radius, double threshold) {
  const DrumGeometry& g = image.geometry;
  const GreyImage& m = image.material;
  const double judged_px = judged_radius * g.radius_px;
  std::vector<ColumnCrossing> columns;
  for (int col = 0; col < m.width; ++col) {
    const double x = x_px_of(g, col);
    if (std::abs(x) >= judged_px) continue;
    const double half = std::sqrt(judged_px * judged_px - x * x);
    const int top = std::max(0, static_cast<int>(std::ceil(g.centre_row - 0.5 - half)));
    const int bottom = std::min(m.height - 1, static_cast<int>(std::floor(g.centre_row - 0.5 + half)));
    if (bottom <= top) continue;
    if (const std::optional<ColumnCrossing> c = scan_column(image, col, top, bottom, threshold)) columns.push_back(*c);
  }
  return columns;
}

// ------------------------------------------------------------------------------------------------ drawing

struct Rgb {
  unsigned char r, g, b;
};
constexpr Rgb k_cyan{0, 200, 230};
constexpr Rgb k_red{230, 30, 30};
constexpr Rgb k_yellow{250, 210, 0};
constexpr Rgb k_green{0, 200, 60};
constexpr Rgb k_magenta{220, 0, 220};

void put(RgbImage& image, int col, int row, Rgb colour) {
  if (col < 0 || row < 0 || col >= image.width || row >= image.height) return;
  unsigned char* p = &image.pixels[(static_cast<std::size_t>(row) * image.width + col) * 3];
  p[0] = colour.r, p[1] = colour.g, p[2] = colour.b;
}

/// The pixel holding a point of the drum frame given in pixels.
void put_px(RgbImage& image, const DrumGeometry& g, double x_px, double y_px, Rgb colour) {
  put(image, static_cast<int>(std::floor(x_px + g.centre_col)), static_cast<int>(std::floor(g.centre_row - y_px)),
      colour);
}

/// The material in grey, dark where the drum held material (as the photographs show it).
RgbImage grey_background(const DrumImage& image) {
  const GreyImage& m = image.material;
  RgbImage out{m.width, m.height, std::vector<unsigned char>(m.pixels.size() * 3)};
  for (std::size_t i = 0; i < m.pixels.size(); ++i) {
    const auto grey = static_cast<unsigned char>(std::lround(255.0 * (1.0 - std::clamp(m.pixels[i], 0.0f, 1.0f))));
    out.pixels[3 * i] = out.pixels[3 * i + 1] = out.pixels[3 * i + 2] = grey;
  }
  return out;
}

void draw_circle(RgbImage& out, const DrumGeometry& g, double radius_px, Rgb colour) {
  const int steps = std::max(64, static_cast<int>(std::ceil(2 * std::numbers::pi * radius_px * 4)));
  for (int k = 0; k < steps; ++k) {
    const double phi = 2 * std::numbers::pi * k / steps;
    put_px(out, g, radius_px * std::cos(phi), radius_px * std::sin(phi), colour);
  }
}

void check_same_drum(const DrumImage& a, const DrumImage& b) {
  if (std::abs(a.geometry.radius_m - b.geometry.radius_m) > 1e-6 * a.geometry.radius_m)
    throw InputError(fmt::format("the two pictures show drums of radius {} m and {} m, not the same drum",
                                 a.geometry.radius_m, b.geometry.radius_m));
}

}  // namespace

// ------------------------------------------------------------------------------------------------ names, geometry

DrumRotation drum_rotation_from_string(const std::string& name) {
  if (name == "clockwise") return DrumRotation::clockwise;
  if (name == "counterclockwise") return DrumRotation::counterclockwise;
  throw std::invalid_argument(fmt::format("unknown drum rotation '{}' (valid: clockwise, counterclockwise)", name));
}

std::string to_string(DrumRotation rotation) {
  switch (rotation) {
    case DrumRotation::clockwise:
      return "clockwise";
    case DrumRotation::counterclockwise:
      return "counterclockwise";
  }
  assert(false && "unknown DrumRotation");
  return {};
}

DrumGeometry DrumGeometry::spanning(int width, int height, double radius_m, DrumRotation rotation) {
  if (width <= 0 || height <= 0 || width != height)
    throw InputError(fmt::format(
        "a picture of {} × {} pixels: a picture that spans the drum's inner diameter must be square", width, height));
  if (!(radius_m > 0.0) || !std::isfinite(radius_m))
    throw std::invalid_argument(fmt::format("drum radius {} m: must be positive", radius_m));
  DrumGeometry g;
  g.centre_col = width / 2.0;
  g.centre_row = height / 2.0;
  g.radius_px = width / 2.0;
  g.radius_m = radius_m;
  g.rotation = rotation;
  return g;
}

// ------------------------------------------------------------------------------------------------ photographs

PhotographLevels photograph_levels(const GreyImage& photograph, const DrumGeometry& geometry, bool dark_material,
                                   double judged_radius) {
  check_geometry(geometry);
  check_image(photograph, "the photograph");
  if (!(judged_radius > 0.0 && judged_radius <= 1.0))
    throw std::invalid_argument(fmt::format("judged_radius = {}: must be in (0, 1]", judged_radius));
  const double judged_px = judged_radius * geometry.radius_px;
  std::vector<double> values;
  values.reserve(photograph.pixels.size());
  for (int row = 0; row < photograph.height; ++row)
    for (int col = 0; col < photograph.width; ++col)
      if (std::hypot(x_px_of(geometry, col), y_px_of(geometry, row)) <= judged_px)
        values.push_back(std::clamp(static_cast<double>(photograph.at(col, row)), 0.0, 1.0));
  if (values.size() < 2)
    throw InputError(fmt::format("the photograph ({} × {} pixels) has no pixels within {} of the drum's radius",
                                 photograph.width, photograph.height, judged_radius));

  // Otsu (1979), "A threshold selection method from gray-level histograms", IEEE Trans. SMC 9(1): over a 256-bin
  // histogram the threshold k maximises the between-class variance σ_B²(k) = [μ_T ω(k) − μ(k)]² / [ω(k)(1 − ω(k))];
  // η = σ_B²(k*) / σ_T² (his separability measure) says how well two classes are there at all. Where σ_B² is flat
  // (bins with no pixels between the two modes) the middle of the flat run is taken.
  constexpr int k_bins = 256;
  std::array<double, k_bins> p{};
  for (double v : values) p[std::min(k_bins - 1, static_cast<int>(v * k_bins))] += 1.0;
  const auto n = static_cast<double>(values.size());
  double mu_total = 0.0;
  for (int i = 0; i < k_bins; ++i) p[i] /= n, mu_total += i * p[i];
  double var_total = 0.0;
  for (int i = 0; i < k_bins; ++i) var_total += (i - mu_total) * (i - mu_total) * p[i];
  double omega = 0.0, mu = 0.0, best = -1.0;
  int first_best = 0, last_best = 0;
  for (int k = 0; k < k_bins - 1; ++k) {
    omega += p[k], mu += k * p[k];
    if (omega <= 0.0 || omega >= 1.0) continue;
    const double between = (mu_total * omega - mu) * (mu_total * omega - mu) / (omega * (1.0 - omega));
    if (between > best * (1.0 + 1e-12)) {
      best = between, first_best = last_best = k;
    } else if (between >= best * (1.0 - 1e-12)) {
      last_best = k;
    }
  }
  PhotographLevels levels;
  levels.pixels = static_cast<long>(values.size());
  levels.separability = var_total > 0.0 && best > 0.0 ? best / var_total : 0.0;
  if (levels.separability < k_min_separability)
    throw InputError(fmt::format(
        "the photograph shows one grey level within {} of the drum's radius (Otsu's separability {:.3f} < {}): an "
        "empty or a full drum, or no contrast between powder and drum",
        judged_radius, levels.separability, k_min_separability));
  const int k_star = (first_best + last_best) / 2;
  levels.threshold = (k_star + 1.0) / k_bins;  // class 0: bins 0..k*, values below the bin's upper edge
  std::vector<double> dark, light;
  for (double v : values) (v < levels.threshold ? dark : light).push_back(v);
  assert(!dark.empty() && !light.empty());
  // The medians, not the means, of the classes: the band's blurred pixels and the odd reflection or shadow pull a
  // class's mean towards the other class, but hardly its median.
  const double dark_level = median_of(std::move(dark)), light_level = median_of(std::move(light));
  levels.material = dark_material ? dark_level : light_level;
  levels.empty = dark_material ? light_level : dark_level;
  return levels;
}

DrumImage drum_image_from_photograph(const GreyImage& photograph, const DrumGeometry& geometry, bool dark_material) {
  // The material fraction of a pixel of a time-averaged photograph is where its grey lies between the empty drum's
  // level and the bed's: a pixel that showed powder a fraction f of the time averages to
  // empty + f·(material − empty). Both levels come from the picture itself (photograph_levels), so neither the
  // lighting nor the camera's exposure enters the observables.
  check_geometry(geometry);
  check_image(photograph, "the photograph");
  // The whole drum in the picture, to half a pixel: beyond its edges a surface's columns, its stations and the bed's
  // area are cut off, and the scan from the top of the judged circle would start on the picture's first row, taking
  // the edge for the surface (a drum of 400 px in a 406 px picture measured a fill of 0.13 for 0.50).
  const double left = geometry.centre_col - geometry.radius_px, right = geometry.centre_col + geometry.radius_px;
  const double top = geometry.centre_row - geometry.radius_px, bottom = geometry.centre_row + geometry.radius_px;
  if (left < -0.5 || top < -0.5 || right > photograph.width + 0.5 || bottom > photograph.height + 0.5)
    throw InputError(fmt::format(
        "the drum (centre at column {:g}, row {:g}, radius {:g} px) reaches beyond the picture's {} × {} pixels "
        "(columns {:g} to {:g}, rows {:g} to {:g}): the whole drum must be in the picture",
        geometry.centre_col, geometry.centre_row, geometry.radius_px, photograph.width, photograph.height, left, right,
        top, bottom));
  const PhotographLevels levels = photograph_levels(photograph, geometry, dark_material);
  DrumImage image;
  image.geometry = geometry;
  image.material.width = photograph.width;
  image.material.height = photograph.height;
  image.material.pixels.resize(photograph.pixels.size());
  const double span = levels.material - levels.empty;
  for (std::size_t i = 0; i < photograph.pixels.size(); ++i)
    image.material.pixels[i] = static_cast<float>(std::clamp((photograph.pixels[i] - levels.empty) / span, 0.0, 1.0));
  return image;
}

// ------------------------------------------------------------------------------------------------ simulations

DrumOccupancy::DrumOccupancy(int size, double radius_m, DrumRotation rotation)
    : m_geometry(DrumGeometry::spanning(size, size, radius_m, rotation)) {
  m_sum.width = m_sum.height = size;
  m_sum.pixels.assign(static_cast<std::size_t>(size) * size, 0.0f);
}

void DrumOccupancy::add_snapshot(std::span<const double> x, std::span<const double> y, std::span<const double> radius) {
  if (x.size() != y.size() || x.size() != radius.size())
    throw std::invalid_argument(
        fmt::format("DrumOccupancy::add_snapshot: {} x, {} y and {} radii", x.size(), y.size(), radius.size()));
  // Anti-aliased coverage with the union of the discs exact at the sampling resolution: each pixel has 4 × 4 sample
  // points (a 16-bit mask); a disc sets the samples it covers (every sample of a pixel wholly inside it), the masks of
  // the snapshot's discs are OR-ed, and a pixel's coverage is its count of set samples over 16. A pixel covered by two
  // discs is so covered once, and a pixel half covered counts ½ (to 1/16) rather than 0 or 1 by its centre.
  constexpr int k_sub = 4;
  const int size = m_sum.width;
  const double pixel = m_geometry.pixel_m();
  std::vector<std::uint16_t> mask(m_sum.pixels.size(), 0);
  for (std::size_t j = 0; j < x.size(); ++j) {
    if (!std::isfinite(x[j]) || !std::isfinite(y[j]) || !std::isfinite(radius[j]) || radius[j] <= 0.0)
      throw InputError(
          fmt::format("particle {} of the snapshot: position ({}, {}) m, radius {} m", j, x[j], y[j], radius[j]));
    const double cu = x[j] / pixel + m_geometry.centre_col;  // continuous column: pixel c spans [c, c + 1)
    const double cv = m_geometry.centre_row - y[j] / pixel;  // continuous row
    const double rp = radius[j] / pixel;
    const int c0 = std::max(0, static_cast<int>(std::floor(cu - rp)));
    const int c1 = std::min(size - 1, static_cast<int>(std::floor(cu + rp)));
    const int r0 = std::max(0, static_cast<int>(std::floor(cv - rp)));
    const int r1 = std::min(size - 1, static_cast<int>(std::floor(cv + rp)));
    for (int row = r0; row <= r1; ++row)
      for (int col = c0; col <= c1; ++col) {
        std::uint16_t& bits = mask[static_cast<std::size_t>(row) * size + col];
        if (bits == 0xFFFF) continue;
        const double d = std::hypot(col + 0.5 - cu, row + 0.5 - cv);
        if (d + std::numbers::sqrt2 / 2 <= rp) {
          bits = 0xFFFF;
          continue;
        }
        if (d - std::numbers::sqrt2 / 2 >= rp) continue;
        for (int i = 0; i < k_sub; ++i)
          for (int k = 0; k < k_sub; ++k) {
            const double su = col + (i + 0.5) / k_sub - cu, sv = row + (k + 0.5) / k_sub - cv;
            if (su * su + sv * sv <= rp * rp) bits = static_cast<std::uint16_t>(bits | (1u << (k * k_sub + i)));
          }
      }
  }
  for (std::size_t i = 0; i < mask.size(); ++i)
    m_sum.pixels[i] += static_cast<float>(std::popcount(mask[i])) / (k_sub * k_sub);
  ++m_snapshots;
}

DrumImage DrumOccupancy::image() const {
  if (m_snapshots == 0) throw InputError("the drum's occupancy has no snapshot");
  DrumImage image{m_sum, m_geometry};
  for (float& v : image.material.pixels) v /= static_cast<float>(m_snapshots);
  return image;
}

// ------------------------------------------------------------------------------------------------ measurement

void DrumSurfaceOptions::validate() const {
  if (!(judged_radius > 0.0 && judged_radius <= 1.0))
    throw std::invalid_argument(fmt::format("DrumSurfaceOptions.judged_radius = {}: must be in (0, 1]", judged_radius));
  if (!(angle_half_width > 0.0 && angle_half_width <= judged_radius))
    throw std::invalid_argument(
        fmt::format("DrumSurfaceOptions.angle_half_width = {}: must be in (0, judged_radius = {}]", angle_half_width,
                    judged_radius));
  for (double s : stations)
    if (!(std::abs(s) <= judged_radius))
      throw std::invalid_argument(fmt::format(
          "DrumSurfaceOptions.stations holds {}: every station must be within ±judged_radius = {}", s, judged_radius));
  if (!(threshold > 0.0 && threshold < 1.0))
    throw std::invalid_argument(fmt::format("DrumSurfaceOptions.threshold = {}: must be in (0, 1)", threshold));
}

DrumSurfaceResult measure_drum_surface(const DrumImage& image, const DrumSurfaceOptions& options) {
  options.validate();
  const DrumGeometry& g = image.geometry;
  check_geometry(g);
  check_image(image.material, "the drum's picture");
  const double pixel = g.pixel_m();
  const double radius = g.radius_m;
  const bool clockwise = g.rotation == DrumRotation::clockwise;

  DrumSurfaceResult result;
  const std::vector<ColumnCrossing> columns = scan_columns(image, options.judged_radius, options.threshold);
  if (columns.empty()) {
    long judged = 0, material = 0;
    const double judged_px = options.judged_radius * g.radius_px;
    for (int row = 0; row < image.material.height; ++row)
      for (int col = 0; col < image.material.width; ++col)
        if (std::hypot(x_px_of(g, col), y_px_of(g, row)) <= judged_px) {
          ++judged;
          if (image.material.at(col, row) >= options.threshold) ++material;
        }
    throw InputError(fmt::format(
        "no free surface within {} of the drum's radius: {} of its {} pixels hold material (fraction ≥ {}){}",
        options.judged_radius, material, judged, options.threshold,
        material == 0        ? " — an empty drum"
        : material == judged ? " — a full drum"
                             : ""));
  }
  result.surface.reserve(columns.size());
  for (const ColumnCrossing& c : columns)
    result.surface.push_back({c.x_px * pixel, c.surface * pixel, (c.upper - c.lower) * pixel});

  // The dynamic angle: a Theil–Sen line (Theil 1950, Sen 1968: the median of the pairwise slopes, then the median
  // intercept) of height on x through the central columns. The median ignores the few columns a reflection, a stuck
  // clump or the start of an S bends, where a least-squares line would tilt towards them.
  std::vector<double> xs, heights, sds;
  for (const SurfacePoint& p : result.surface)
    if (std::abs(p.x) <= options.angle_half_width * radius + 1e-12 * radius)
      xs.push_back(p.x), heights.push_back(p.height), sds.push_back(0.5 * p.band);
  if (xs.size() < 2 || *std::max_element(xs.begin(), xs.end()) == *std::min_element(xs.begin(), xs.end()))
    throw InputError(fmt::format(
        "the free surface is found in {} column(s) within {} of the drum's radius of its centre: too few for its "
        "angle (of {} columns with a surface in the judged region)",
        xs.size(), options.angle_half_width, result.surface.size()));
  const TheilSenLine line = fit_theil_sen_line(heights, xs);
  result.angle_line_slope = line.slope;
  result.angle_line_height = line.intercept;
  const double angle = std::atan(line.slope) * k_rad_to_deg;  // rising to the right: positive
  result.dynamic_angle = (clockwise ? -angle : angle) + 0.0;  // + 0.0: a level surface is 0°, not −0°

  // Its uncertainty: each column's height taken as uncertain by half its band (the surface's fluctuation and blur,
  // as one standard deviation) and propagated through the slope of a line fitted by least squares,
  // var(b) = Σ (x_i − x̄)² s_i² / [Σ (x_i − x̄)²]², then through atan. The columns are taken as independent; the
  // surface's fluctuations reach over a few particle diameters (several columns), so this is a lower bound of the
  // angle's uncertainty in one picture.
  const double x_mean = std::accumulate(xs.begin(), xs.end(), 0.0) / static_cast<double>(xs.size());
  double sxx = 0.0, var_num = 0.0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const double dx = xs[i] - x_mean;
    sxx += dx * dx;
    var_num += dx * dx * sds[i] * sds[i];
  }
  result.angle_uncertainty = std::sqrt(var_num) / sxx / (1.0 + line.slope * line.slope) * k_rad_to_deg;

  // Stations: the height between the two columns on either side, linearly; the fractions mirrored in x for a drum
  // that turns counterclockwise. A station must fall between two neighbouring columns with a surface, else its height
  // and band are NaN.
  for (double s : options.stations) {
    const double x = (clockwise ? s : -s) * radius;
    const auto after = std::lower_bound(result.surface.begin(), result.surface.end(), x,
                                        [](const SurfacePoint& p, double v) { return p.x < v; });
    std::optional<SurfacePoint> found;
    if (after != result.surface.end() && std::abs(after->x - x) <= 1e-9 * pixel) {
      found = *after;
    } else if (after != result.surface.begin() && after != result.surface.end() &&
               after->x - std::prev(after)->x <= 1.5 * pixel) {
      const SurfacePoint& a = *std::prev(after);
      const double t = (x - a.x) / (after->x - a.x);
      found = SurfacePoint{x, a.height + t * (after->height - a.height), a.band + t * (after->band - a.band)};
    }
    constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();
    if (!found) found = SurfacePoint{x, k_nan, k_nan};  // the surface there is outside the judged region
    found->x = x;
    result.stations.push_back(*found);
  }

  // The bed: the pixels of the whole drum (centre within R) that hold material at the threshold. The outermost ring,
  // beyond k_rim_radius·R, takes the material at k_rim_radius·R on its own radius: in a photograph it holds the
  // rim's dark line and its shadow (dark as powder where the drum is empty: they would add 0.1–0.2% of the
  // drum's area to the fill of the GranuDrum's images), in a simulation the gaps between the wall and the spheres
  // against it.
  long bed = 0;
  for (int row = 0; row < image.material.height; ++row)
    for (int col = 0; col < image.material.width; ++col) {
      const double xp = x_px_of(g, col), yp = y_px_of(g, row), r = std::hypot(xp, yp);
      if (r > g.radius_px) continue;
      const double rim = k_rim_radius * g.radius_px;
      const double f =
          r <= rim ? image.material.at(col, row) : sample(image, xp * rim / r * pixel, yp * rim / r * pixel);
      if (f >= options.threshold) ++bed;
    }
  result.bed_area = static_cast<double>(bed) * pixel * pixel;
  result.fill_fraction = result.bed_area / (std::numbers::pi * radius * radius);

  // The S shape: the cubic term of the least-squares cubic y = a + b u + c u² + d u³ through every surface point of
  // the judged region, with u = x / (judged_radius·R) so that d = d_x·(judged_radius·R)³ is in metres (the cubic
  // part's height at the edge of the judged region). Solved by column-pivoted Householder
  // QR on the Vandermonde matrix (not the normal equations). A clockwise drum's fast S (steep in the middle, flat at
  // both ends, falling to the right) has d > 0; mirrored for counterclockwise, so the S of either direction is
  // positive.
  if (result.surface.size() < 4)
    throw InputError(
        fmt::format("the free surface is found in {} column(s) of the judged region: too few for its S "
                    "shape (a cubic needs 4)",
                    result.surface.size()));
  const double half_width = options.judged_radius * radius;
  Eigen::MatrixXd basis(static_cast<Eigen::Index>(result.surface.size()), 4);
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(result.surface.size()));
  for (std::size_t i = 0; i < result.surface.size(); ++i) {
    const double u = result.surface[i].x / half_width;
    const auto r = static_cast<Eigen::Index>(i);
    basis(r, 0) = 1.0, basis(r, 1) = u, basis(r, 2) = u * u, basis(r, 3) = u * u * u;
    rhs(r) = result.surface[i].height;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(basis);
  if (qr.rank() < 4)
    throw InputError(fmt::format("the free surface's {} columns do not determine a cubic", result.surface.size()));
  const Eigen::VectorXd coefficients = qr.solve(rhs);
  result.s_shape = clockwise ? coefficients(3) : -coefficients(3);
  return result;
}

DrumSurfaceResult measure_drum_photograph(const std::filesystem::path& file, double radius_m, DrumRotation rotation,
                                          const DrumSurfaceOptions& options, bool dark_material) {
  const GreyImage photograph = read_grey_image(file);
  try {
    const DrumGeometry geometry = DrumGeometry::spanning(photograph.width, photograph.height, radius_m, rotation);
    return measure_drum_surface(drum_image_from_photograph(photograph, geometry, dark_material), options);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", file.string(), e.what()));
  }
}

// ------------------------------------------------------------------------------------------------ comparison

double drum_mismatch_area(const DrumImage& a, const DrumImage& b, double judged_radius, double threshold) {
  check_geometry(a.geometry);
  check_geometry(b.geometry);
  check_image(a.material, "the first picture");
  check_image(b.material, "the second picture");
  if (!(judged_radius > 0.0 && judged_radius <= 1.0))
    throw std::invalid_argument(fmt::format("judged_radius = {}: must be in (0, 1]", judged_radius));
  if (!(threshold > 0.0 && threshold < 1.0))
    throw std::invalid_argument(fmt::format("threshold = {}: must be in (0, 1)", threshold));
  check_same_drum(a, b);
  // On a's pixel grid: each of a's pixels within the judged circle against b at the same point of the drum frame
  // (bilinear), b mirrored in x when the two drums turn opposite ways, so that both show the powder carried up on
  // the same side.
  const bool mirror = a.geometry.rotation != b.geometry.rotation;
  const double pixel = a.geometry.pixel_m();
  const double judged_px = judged_radius * a.geometry.radius_px;
  long differ = 0;
  for (int row = 0; row < a.material.height; ++row)
    for (int col = 0; col < a.material.width; ++col) {
      const double xp = x_px_of(a.geometry, col), yp = y_px_of(a.geometry, row);
      if (std::hypot(xp, yp) > judged_px) continue;
      const bool in_a = a.material.at(col, row) >= threshold;
      const bool in_b = sample(b, (mirror ? -xp : xp) * pixel, yp * pixel) >= threshold;
      if (in_a != in_b) ++differ;
    }
  return static_cast<double>(differ) * pixel * pixel;
}

RgbImage drum_overlay(const DrumImage& a, const DrumImage& b, double judged_radius, double threshold) {
  check_geometry(a.geometry);
  check_geometry(b.geometry);
  check_image(a.material, "the first picture");
  check_image(b.material, "the second picture");
  check_same_drum(a, b);
  RgbImage out = grey_background(a);
  const bool mirror = a.geometry.rotation != b.geometry.rotation;
  const double pixel = a.geometry.pixel_m();
  // b's material (thresholded) as a translucent blue over a's grey, within the drum.
  constexpr double k_alpha = 0.45;
  constexpr std::array<double, 3> k_tint = {30, 110, 255};
  for (int row = 0; row < out.height; ++row)
    for (int col = 0; col < out.width; ++col) {
      const double xp = x_px_of(a.geometry, col), yp = y_px_of(a.geometry, row);
      if (std::hypot(xp, yp) > a.geometry.radius_px) continue;
      if (sample(b, (mirror ? -xp : xp) * pixel, yp * pixel) < threshold) continue;
      unsigned char* p = &out.pixels[(static_cast<std::size_t>(row) * out.width + col) * 3];
      for (int k = 0; k < 3; ++k)
        p[k] = static_cast<unsigned char>(std::lround((1 - k_alpha) * p[k] + k_alpha * k_tint[k]));
    }
  draw_circle(out, a.geometry, judged_radius * a.geometry.radius_px, k_cyan);
  return out;
}

RgbImage drum_surface_overlay(const DrumImage& image, const DrumSurfaceResult& result,
                              const DrumSurfaceOptions& options) {
  options.validate();
  check_geometry(image.geometry);
  check_image(image.material, "the drum's picture");
  const DrumGeometry& g = image.geometry;
  const double pixel = g.pixel_m();
  RgbImage out = grey_background(image);
  draw_circle(out, g, options.judged_radius * g.radius_px, k_cyan);
  for (const ColumnCrossing& c : scan_columns(image, options.judged_radius, options.threshold)) {
    put_px(out, g, c.x_px, c.upper, k_yellow);
    put_px(out, g, c.x_px, c.lower, k_yellow);
  }
  for (const SurfacePoint& p : result.surface) put_px(out, g, p.x / pixel, p.height / pixel, k_red);
  const double half = options.angle_half_width * g.radius_px;
  for (double x = -half; x <= half; x += 0.25) {
    const double y = (result.angle_line_height + result.angle_line_slope * x * pixel) / pixel;
    put_px(out, g, x, y, k_green);
  }
  for (const SurfacePoint& s : result.stations)
    for (int k = -3; k <= 3; ++k) {
      put_px(out, g, s.x / pixel + k, s.height / pixel, k_magenta);
      put_px(out, g, s.x / pixel, s.height / pixel + k, k_magenta);
    }
  return out;
}

}  // namespace demsa::postprocess
