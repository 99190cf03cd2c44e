// The rotating drum's side view (postprocess/drum.hpp): photographs drawn from known surfaces (lines at known angles,
// an S of known cubic term; blurred, noisy, 8-bit, as PNG and BMP) and the occupancy of particles under a known line
// measured to those surfaces; and the pictures that hold no surface refused.
#include "postprocess/drum.hpp"
#include "postprocess/error.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace demsa::drum_test_files {
// Defined in test_image.cpp: an 8-bit palette BMP with a grey palette, as the GranuDrum writes its images.
std::string grey_bmp(const postprocess::GreyImage& image);
}  // namespace demsa::drum_test_files

namespace demsa {
namespace {

using postprocess::DrumGeometry;
using postprocess::DrumImage;
using postprocess::DrumRotation;
using postprocess::DrumSurfaceOptions;
using postprocess::DrumSurfaceResult;
using postprocess::GreyImage;
using postprocess::InputError;

constexpr double k_deg = std::numbers::pi / 180.0;
constexpr double k_radius = 0.042;  // the GranuDrum's inner radius [m]
constexpr int k_size = 406;         // its pictures' side [px]
constexpr float k_light = 0.94f;    // the empty drum's grey
constexpr float k_dark = 0.11f;     // the powder's grey
/// The S shape of a drawn photograph within 0.06 mm (0.3 px) of its cubic term; the lab's images measure 2–21 mm.
constexpr double k_s_tolerance = 0.06e-3;

/// A surface y(x) in units of R, in the drum frame (x right, y up).
using Surface = std::function<double(double)>;

/// A line at `angle` degrees through (0, offset·R), rising towards the wall that carries the powder up.
Surface line(double angle, double offset, DrumRotation rotation) {
  const double slope = std::tan(angle * k_deg) * (rotation == DrumRotation::clockwise ? -1.0 : 1.0);
  return [=](double x) { return offset + slope * x; };
}

/// A GranuDrum-like photograph, `size` px square spanning the drum: the empty drum light above the surface, the
/// powder dark below it, white outside the drum and the rim a dark line 1.5 px wide inside R; 4 × 4 samples per pixel,
/// then a Gaussian blur of sd `blur_px` (the surface's fluctuation in a time average), Gaussian noise of sd `noise`
/// and 8-bit levels.
GreyImage draw_photograph(const Surface& surface, double blur_px, double noise, unsigned seed, int size = k_size) {
  const double half = size / 2.0;
  GreyImage image{size, size, std::vector<float>(static_cast<std::size_t>(size) * size)};
  for (int row = 0; row < size; ++row)
    for (int col = 0; col < size; ++col) {
      const double xc = (col + 0.5 - half) / half, yc = (half - row - 0.5) / half, rc = std::hypot(xc, yc);
      if (std::abs(yc - surface(xc)) > 2.0 / half && std::abs(rc - 1.0) > 3.0 / half) {  // wholly on one side
        image.at(col, row) = rc > 1.0 ? 1.0f : yc < surface(xc) ? k_dark : k_light;
        continue;
      }
      double sum = 0.0;
      for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 4; ++k) {
          const double x = (col + (i + 0.5) / 4 - half) / half, y = (half - row - (k + 0.5) / 4) / half;
          const double r = std::hypot(x, y);
          sum += r > 1.0 ? 1.0 : r > 1.0 - 1.5 / half ? 0.3 : y < surface(x) ? k_dark : k_light;
        }
      image.at(col, row) = static_cast<float>(sum / 16);
    }
  if (blur_px > 0.0) {
    const int reach = static_cast<int>(std::ceil(3 * blur_px));
    std::vector<double> kernel(2 * reach + 1);
    double total = 0.0;
    for (int k = -reach; k <= reach; ++k) total += kernel[k + reach] = std::exp(-0.5 * k * k / (blur_px * blur_px));
    for (double& w : kernel) w /= total;
    for (int pass = 0; pass < 2; ++pass) {  // rows, then columns
      GreyImage blurred = image;
      for (int row = 0; row < size; ++row)
        for (int col = 0; col < size; ++col) {
          double v = 0.0;
          for (int k = -reach; k <= reach; ++k) {
            const int c = pass == 0 ? std::clamp(col + k, 0, size - 1) : col;
            const int r = pass == 1 ? std::clamp(row + k, 0, size - 1) : row;
            v += kernel[k + reach] * image.at(c, r);
          }
          blurred.at(col, row) = static_cast<float>(v);
        }
      image = std::move(blurred);
    }
  }
  std::mt19937 rng(seed);
  std::normal_distribution<double> jitter(0.0, noise);
  for (float& v : image.pixels)
    v = static_cast<float>(std::round(std::clamp(v + (noise > 0.0 ? jitter(rng) : 0.0), 0.0, 1.0) * 255.0) / 255.0);
  return image;
}

/// The drawn photograph written as `name` (.png through write_grey_png, .bmp as an 8-bit palette BMP) and measured
/// from the file.
DrumSurfaceResult measure_file(const test::TempDir& tmp, const std::string& name, const GreyImage& photograph,
                               DrumRotation rotation, const DrumSurfaceOptions& options = {}) {
  if (name.ends_with(".png"))
    postprocess::write_grey_png(tmp / name, photograph);
  else
    test::write_file(tmp / name, drum_test_files::grey_bmp(photograph));
  return postprocess::measure_drum_photograph(tmp / name, k_radius, rotation, options);
}

DrumImage from_photograph(const GreyImage& photograph, DrumRotation rotation) {
  return postprocess::drum_image_from_photograph(
      photograph, DrumGeometry::spanning(photograph.width, photograph.height, k_radius, rotation));
}

/// The area of the disc of radius R below the line y = offset·R + slope·x [m²].
double area_below(double offset, double slope) {
  const double h = offset / std::sqrt(1.0 + slope * slope);  // signed distance of the line above the centre, in R
  const double cap = std::acos(h) - h * std::sqrt(1.0 - h * h);
  return (std::numbers::pi - cap) * k_radius * k_radius;
}

// ---------------------------------------------------------------------------------------------- photographs

TEST(DrumPhotograph, StraightSurfacesAtKnownAnglesBothRotationsPngAndBmp) {
  test::TempDir tmp;
  const double offset = -0.05;
  unsigned seed = 1;
  for (double angle : {20.0, 30.0, 40.0, 50.0})
    for (DrumRotation rotation : {DrumRotation::clockwise, DrumRotation::counterclockwise}) {
      const GreyImage photograph = draw_photograph(line(angle, offset, rotation), 1.5, 0.02, ++seed);
      for (const char* extension : {".png", ".bmp"}) {
        const std::string name = fmt::format("line{}_{}{}", angle, to_string(rotation), extension);
        const DrumSurfaceResult r = measure_file(tmp, name, photograph, rotation);
        EXPECT_NEAR(r.dynamic_angle, angle, 0.3) << name;
        EXPECT_GT(r.angle_uncertainty, 0.0) << name;
        EXPECT_LT(r.angle_uncertainty, 0.3) << name;
        EXPECT_NEAR(r.s_shape, 0.0, k_s_tolerance) << name;  // a line has no S
        const double slope = std::tan(angle * k_deg) * (rotation == DrumRotation::clockwise ? -1 : 1);
        EXPECT_NEAR(r.fill_fraction, area_below(offset, slope) / (std::numbers::pi * k_radius * k_radius), 0.003)
            << name;
        // The stations: mirrored for counterclockwise, so the same heights either way; NaN where the surface at the
        // station leaves the judged circle (the 0.77 R), skipped within 3 px of it.
        const std::vector<double> stations = DrumSurfaceOptions{}.stations;
        ASSERT_EQ(r.stations.size(), stations.size());
        for (std::size_t i = 0; i < stations.size(); ++i) {
          const double x = rotation == DrumRotation::clockwise ? stations[i] : -stations[i];
          const double y = offset + slope * x;
          const double margin = 3.0 / (k_size / 2.0);
          EXPECT_NEAR(r.stations[i].x, x * k_radius, 1e-12) << name << " station " << i;
          if (std::hypot(x, y) < 0.77 - margin) {
            EXPECT_NEAR(r.stations[i].height, y * k_radius, 0.05e-3) << name << " station " << i;
          } else if (std::hypot(x, y) > 0.77 + margin) {
            EXPECT_TRUE(std::isnan(r.stations[i].height)) << name << " station " << i;
          }
        }
      }
    }
}

TEST(DrumPhotograph, SShapeOfKnownCubicTerm) {
  test::TempDir tmp;
  // y = −tan 35°·x + d·(x / 0.77)³ in units of R: steep in the middle, flatter at both ends (a fast drum's S),
  // mirrored for counterclockwise. The cubic term over the judged region is d·R.
  for (double d : {0.05})
    for (DrumRotation rotation : {DrumRotation::clockwise, DrumRotation::counterclockwise}) {
      const double sign = rotation == DrumRotation::clockwise ? 1.0 : -1.0;
      const Surface s = [=](double x) { return -sign * std::tan(35 * k_deg) * x + sign * d * std::pow(x / 0.77, 3); };
      const DrumSurfaceResult r = measure_file(tmp, fmt::format("s{}_{}.png", d, to_string(rotation)),
                                               draw_photograph(s, 1.5, 0.02, 7), rotation);
      EXPECT_NEAR(r.s_shape, d * k_radius, k_s_tolerance) << d << " " << to_string(rotation);
      // The dynamic angle is the central part's: the slope at the centre is 35°, and over |x| ≤ 0.5 R the cubic
      // flattens the chord.
      EXPECT_NEAR(r.dynamic_angle, 35.0, 2.0) << d << " " << to_string(rotation);
    }
}

TEST(DrumPhotograph, DarkSpeckAboveTheSurfaceIsPassedOver) {
  // Dust on the end plate: a dark speck 4 px high in the empty drum, in the column of the station at +0.3 R, and one
  // of 2 px at −0.15 R. The surface there is still the powder's.
  const double offset = -0.05, slope = -std::tan(30 * k_deg);
  GreyImage photograph = draw_photograph(line(30, offset, DrumRotation::clockwise), 1.5, 0.02, 5);
  const auto speck = [&](double x, double y, int rows) {
    const int col = static_cast<int>(std::floor(x * k_size / 2.0 + k_size / 2.0));
    const int row = static_cast<int>(std::floor(k_size / 2.0 - y * k_size / 2.0));
    for (int r = row; r < row + rows; ++r)
      for (int c = col - 2; c <= col + 2; ++c) photograph.at(c, r) = k_dark;
  };
  speck(0.3, 0.3, 4);
  speck(-0.15, 0.45, 2);
  const DrumSurfaceResult r = postprocess::measure_drum_surface(from_photograph(photograph, DrumRotation::clockwise));
  EXPECT_NEAR(r.stations[6].height, (offset + slope * 0.3) * k_radius, 0.05e-3);
  EXPECT_NEAR(r.stations[3].height, (offset - slope * 0.15) * k_radius, 0.05e-3);
  EXPECT_NEAR(r.stations[6].band, r.stations[5].band, 0.1e-3);  // nor does the speck widen the band
  EXPECT_NEAR(r.stations[3].band, r.stations[4].band, 0.1e-3);
  EXPECT_NEAR(r.dynamic_angle, 30.0, 0.3);
  EXPECT_NEAR(r.s_shape, 0.0, k_s_tolerance);
}

TEST(DrumPhotograph, LevelsAreTheClassMedians) {
  const GreyImage photograph = draw_photograph(line(30, 0.0, DrumRotation::clockwise), 1.5, 0.02, 3);
  const postprocess::PhotographLevels levels = postprocess::photograph_levels(
      photograph, DrumGeometry::spanning(k_size, k_size, k_radius, DrumRotation::clockwise));
  EXPECT_NEAR(levels.material, k_dark, 1.0 / 255);
  EXPECT_NEAR(levels.empty, k_light, 1.0 / 255);
  EXPECT_GT(levels.threshold, k_dark + 0.1);
  EXPECT_LT(levels.threshold, k_light - 0.1);
  EXPECT_GT(levels.separability, 0.9);
  // Light powder in a dark drum: the same levels, the other way round.
  const postprocess::PhotographLevels reverse = postprocess::photograph_levels(
      photograph, DrumGeometry::spanning(k_size, k_size, k_radius, DrumRotation::clockwise), false);
  EXPECT_EQ(reverse.material, levels.empty);
  EXPECT_EQ(reverse.empty, levels.material);
}

// ---------------------------------------------------------------------------------------------- simulations

/// Particles of radius 0.6 mm with centres uniform (Poisson) in the drum under the surface, about four discs over
/// every point, one independent draw per snapshot.
void add_particles_under(postprocess::DrumOccupancy& occupancy, const Surface& surface, unsigned seed) {
  const double r = 0.6e-3;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-k_radius, k_radius);
  std::vector<double> x, y, radius;
  const auto target =
      static_cast<std::size_t>(4.0 * 0.5 * std::numbers::pi * k_radius * k_radius / (std::numbers::pi * r * r));
  while (x.size() < target) {
    const double px = u(rng), py = u(rng);
    if (std::hypot(px, py) > k_radius - r || py > surface(px / k_radius) * k_radius) continue;
    x.push_back(px), y.push_back(py), radius.push_back(r);
  }
  occupancy.add_snapshot(x, y, radius);
}

TEST(DrumOccupancy, ParticlesUnderALineMeasureAsItsPhotograph) {
  test::TempDir tmp;
  for (DrumRotation rotation : {DrumRotation::clockwise, DrumRotation::counterclockwise}) {
    const Surface s = line(35.0, 0.0, rotation);
    postprocess::DrumOccupancy occupancy(k_size, k_radius, rotation);
    for (unsigned snapshot = 0; snapshot < 4; ++snapshot) add_particles_under(occupancy, s, 100 + snapshot);
    EXPECT_EQ(occupancy.snapshots(), 4);
    const DrumSurfaceResult simulated = postprocess::measure_drum_surface(occupancy.image());
    const DrumSurfaceResult photographed =
        measure_file(tmp, fmt::format("{}.png", to_string(rotation)), draw_photograph(s, 1.5, 0.02, 11), rotation);
    EXPECT_NEAR(simulated.dynamic_angle, 35.0, 0.3) << to_string(rotation);
    EXPECT_NEAR(simulated.dynamic_angle, photographed.dynamic_angle, 0.3) << to_string(rotation);
    // Particles 0.6 mm in radius make the surface rough on their scale, which four snapshots leave: the S of a line
    // within 0.25 mm (the lab's images measure 2–21 mm).
    EXPECT_NEAR(simulated.s_shape, 0.0, 0.25e-3) << to_string(rotation);
  }
}

/// The occupancy's summed coverage [m²].
double covered_area(const postprocess::DrumOccupancy& occupancy) {
  const DrumImage image = occupancy.image();
  double sum = 0.0;
  for (float v : image.material.pixels) sum += v;
  return sum * image.geometry.pixel_m() * image.geometry.pixel_m();
}

TEST(DrumOccupancy, DiscsCoverTheirAreaAndOverlapsCountOnce) {
  const double r = 3.3e-3, pi = std::numbers::pi;
  postprocess::DrumOccupancy one(200, 0.05, DrumRotation::clockwise);  // 0.5 mm pixels
  const std::vector<double> x1 = {1.1e-3}, y1 = {-2.3e-3}, r1 = {r};
  one.add_snapshot(x1, y1, r1);
  EXPECT_NEAR(covered_area(one), pi * r * r, 0.005 * pi * r * r);
  // The same disc twice covers it once; two discs d apart cover their union.
  postprocess::DrumOccupancy twice(200, 0.05, DrumRotation::clockwise);
  const std::vector<double> x2 = {1.1e-3, 1.1e-3}, y2 = {-2.3e-3, -2.3e-3}, r2 = {r, r};
  twice.add_snapshot(x2, y2, r2);
  EXPECT_DOUBLE_EQ(covered_area(twice), covered_area(one));
  const double d = 4.0e-3;
  postprocess::DrumOccupancy pair(200, 0.05, DrumRotation::clockwise);
  const std::vector<double> x3 = {1.1e-3, 1.1e-3 + d}, y3 = {-2.3e-3, -2.3e-3};
  pair.add_snapshot(x3, y3, r2);
  const double lens = 2 * r * r * std::acos(d / (2 * r)) - 0.5 * d * std::sqrt(4 * r * r - d * d);
  EXPECT_NEAR(covered_area(pair), 2 * pi * r * r - lens, 0.005 * pi * r * r);
  for (float v : pair.image().material.pixels) ASSERT_LE(v, 1.0f);
}

TEST(DrumOccupancy, SnapshotsAreAveraged) {
  postprocess::DrumOccupancy occupancy(100, 0.05, DrumRotation::clockwise);
  const std::vector<double> x = {0.0}, y = {0.0}, r = {5e-3}, none;
  occupancy.add_snapshot(x, y, r);
  occupancy.add_snapshot(none, none, none);
  const DrumImage image = occupancy.image();
  EXPECT_FLOAT_EQ(image.material.at(50, 50), 0.5f);  // wholly inside the disc in one snapshot of two
  EXPECT_FLOAT_EQ(image.material.at(0, 0), 0.0f);
  EXPECT_EQ(image.geometry.radius_px, 50.0);
  EXPECT_THROW(postprocess::DrumOccupancy(10, 0.05, DrumRotation::clockwise).image(), InputError);
  const std::vector<double> bad = {std::nan("")};
  EXPECT_THROW(occupancy.add_snapshot(bad, y, r), InputError);
}

// ---------------------------------------------------------------------------------------------- comparison

TEST(DrumCompare, MismatchOfTwoLinesIsTheirWedges) {
  const DrumImage a =
      from_photograph(draw_photograph(line(30, 0.0, DrumRotation::clockwise), 1.5, 0.02, 21), DrumRotation::clockwise);
  const DrumImage b =
      from_photograph(draw_photograph(line(35, 0.0, DrumRotation::clockwise), 1.5, 0.02, 22), DrumRotation::clockwise);
  // Two lines through the centre 5° apart disagree on two opposite wedges of the judged circle: 5°·ρ², ρ = 0.77 R.
  const double rho = 0.77 * k_radius;
  EXPECT_NEAR(postprocess::drum_mismatch_area(a, b), 5 * k_deg * rho * rho, 0.03 * 5 * k_deg * rho * rho);
  EXPECT_DOUBLE_EQ(postprocess::drum_mismatch_area(a, a), 0.0);
  // The same surface seen in a counterclockwise drum is compared mirrored: hardly any mismatch.
  const DrumImage mirrored = from_photograph(
      draw_photograph(line(30, 0.0, DrumRotation::counterclockwise), 1.5, 0.02, 23), DrumRotation::counterclockwise);
  EXPECT_LT(postprocess::drum_mismatch_area(a, mirrored), 0.002 * std::numbers::pi * rho * rho);
  // A picture on another grid (a simulation's 203 px) is compared in the drum frame.
  const DrumImage coarse = from_photograph(draw_photograph(line(35, 0.0, DrumRotation::clockwise), 0.75, 0.02, 24, 203),
                                           DrumRotation::clockwise);
  EXPECT_NEAR(postprocess::drum_mismatch_area(a, coarse), 5 * k_deg * rho * rho, 0.05 * 5 * k_deg * rho * rho);
  DrumImage other_drum = coarse;
  other_drum.geometry.radius_m = 0.05;
  EXPECT_NE(
      test::message_of<InputError>([&] { postprocess::drum_mismatch_area(a, other_drum); }).find("not the same drum"),
      std::string::npos);
  EXPECT_THROW(postprocess::drum_overlay(a, other_drum), InputError);
}

TEST(DrumCompare, OverlaysDrawTheirParts) {
  const DrumImage a =
      from_photograph(draw_photograph(line(30, 0.0, DrumRotation::clockwise), 1.5, 0.02, 31), DrumRotation::clockwise);
  const postprocess::RgbImage overlay = postprocess::drum_overlay(a, a);
  ASSERT_EQ(overlay.width, k_size);
  ASSERT_EQ(overlay.pixels.size(), static_cast<std::size_t>(k_size) * k_size * 3);
  const auto pixel = [&](const postprocess::RgbImage& image, int col, int row) {
    const unsigned char* p = &image.pixels[(static_cast<std::size_t>(row) * image.width + col) * 3];
    return std::vector<int>{p[0], p[1], p[2]};
  };
  const std::vector<int> bed = pixel(overlay, 203, 350), empty = pixel(overlay, 203, 60);
  EXPECT_GT(bed[2], bed[0] + 50);  // b's bed tinted blue
  EXPECT_EQ(empty[0], empty[2]);   // the empty drum grey
  EXPECT_GT(empty[0], 200);
  const DrumSurfaceResult result = postprocess::measure_drum_surface(a);
  const postprocess::RgbImage surface = postprocess::drum_surface_overlay(a, result);
  int red = 0, green = 0;
  for (int row = 0; row < k_size; ++row) {
    const std::vector<int> p = pixel(surface, 203, row);
    red += p[0] > 200 && p[1] < 60;
    green += p[1] > 180 && p[0] < 30;
  }
  EXPECT_GE(red + green, 1);  // the surface or its line crosses the centre column
}

// ---------------------------------------------------------------------------------------------- refused

TEST(DrumRefuses, EmptyDrumPhotograph) {
  test::TempDir tmp;
  const GreyImage photograph = draw_photograph([](double) { return -2.0; }, 1.5, 0.02, 41);
  postprocess::write_grey_png(tmp / "empty.png", photograph);
  const std::string message = test::message_of<InputError>(
      [&] { postprocess::measure_drum_photograph(tmp / "empty.png", k_radius, DrumRotation::clockwise); });
  EXPECT_NE(message.find((tmp / "empty.png").string() + ": "), std::string::npos) << message;
  EXPECT_NE(message.find("one grey level"), std::string::npos) << message;
}

TEST(DrumRefuses, FullDrumPhotograph) {
  test::TempDir tmp;
  const GreyImage photograph = draw_photograph([](double) { return 2.0; }, 1.5, 0.02, 42);
  postprocess::write_grey_png(tmp / "full.png", photograph);
  const std::string message = test::message_of<InputError>(
      [&] { postprocess::measure_drum_photograph(tmp / "full.png", k_radius, DrumRotation::clockwise); });
  EXPECT_NE(message.find((tmp / "full.png").string() + ": "), std::string::npos) << message;
  EXPECT_NE(message.find("one grey level"), std::string::npos) << message;
}

TEST(DrumRefuses, EmptyAndFullPictures) {
  DrumImage image;
  image.geometry = DrumGeometry::spanning(100, 100, k_radius, DrumRotation::clockwise);
  image.material = GreyImage{100, 100, std::vector<float>(10000, 0.0f)};
  std::string message = test::message_of<InputError>([&] { postprocess::measure_drum_surface(image); });
  EXPECT_NE(message.find("no free surface"), std::string::npos) << message;
  EXPECT_NE(message.find("an empty drum"), std::string::npos) << message;
  std::fill(image.material.pixels.begin(), image.material.pixels.end(), 1.0f);
  message = test::message_of<InputError>([&] { postprocess::measure_drum_surface(image); });
  EXPECT_NE(message.find("a full drum"), std::string::npos) << message;
}

TEST(DrumRefuses, PhotographNotSquare) {
  test::TempDir tmp;
  postprocess::write_grey_png(tmp / "wide.png", GreyImage{4, 2, std::vector<float>(8, 0.5f)});
  const std::string message = test::message_of<InputError>(
      [&] { postprocess::measure_drum_photograph(tmp / "wide.png", k_radius, DrumRotation::clockwise); });
  EXPECT_NE(message.find((tmp / "wide.png").string() + ": a picture of 4 × 2 pixels"), std::string::npos) << message;
}

TEST(DrumRefuses, InvalidOptionsNameTheField) {
  const auto message = [](DrumSurfaceOptions o) {
    return test::message_of<std::invalid_argument>([&] { o.validate(); });
  };
  EXPECT_NE(message({.judged_radius = 1.2}).find("judged_radius = 1.2"), std::string::npos);
  EXPECT_NE(message({.angle_half_width = 0.8}).find("angle_half_width = 0.8"), std::string::npos);
  EXPECT_NE(message({.stations = {0.1, 0.9}}).find("stations holds 0.9"), std::string::npos);
  EXPECT_NE(message({.threshold = 1.0}).find("threshold = 1"), std::string::npos);
  EXPECT_EQ(message({}), "");
  EXPECT_EQ(postprocess::drum_rotation_from_string("counterclockwise"), DrumRotation::counterclockwise);
  EXPECT_NE(test::message_of<std::invalid_argument>([] {
              postprocess::drum_rotation_from_string("cw");
            }).find("valid: clockwise, counterclockwise"),
            std::string::npos);
}

}  // namespace
}  // namespace demsa
