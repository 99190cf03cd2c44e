// A real laboratory photograph measured: the GranuDrum's time average of microcrystalline cellulose at 45 rpm
// (tests/data/postprocess/drum/, with its source and license), as docs/explanation/drum-images.md records it. With
// DEMSA_DRUM_FIGURES=DIR the test also writes its figure there (docs/images/drum-mcc-45rpm.png is that file).
#include "postprocess/drum.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

namespace demsa {
namespace {

using postprocess::DrumRotation;

TEST(DrumMcc, Photograph45RpmAsRecorded) {
  const std::filesystem::path file = test::data_path("postprocess/drum/granudrum_mcc_45rpm.bmp");
  const postprocess::GreyImage photograph = postprocess::read_grey_image(file);
  ASSERT_EQ(photograph.width, 406);
  const postprocess::DrumGeometry geometry =
      postprocess::DrumGeometry::spanning(406, 406, 0.042, DrumRotation::clockwise);

  // The levels are the picture's own greys: the powder 25/255 or 26/255, the empty drum 247/255.
  const postprocess::PhotographLevels levels = postprocess::photograph_levels(photograph, geometry);
  EXPECT_NEAR(levels.material, 26.0 / 255, 1.0 / 255);
  EXPECT_NEAR(levels.empty, 247.0 / 255, 0.5 / 255);
  EXPECT_GT(levels.separability, 0.98);

  const postprocess::DrumImage image = postprocess::drum_image_from_photograph(photograph, geometry);
  const postprocess::DrumSurfaceResult r = postprocess::measure_drum_surface(image);
  // The values of docs/explanation/drum-images.md.
  EXPECT_NEAR(r.dynamic_angle, 51.48, 0.01);
  EXPECT_NEAR(r.angle_uncertainty, 0.09, 0.01);
  EXPECT_NEAR(r.s_shape, 21.25e-3, 0.01e-3);
  EXPECT_NEAR(r.fill_fraction, 0.5223, 0.0005);
  ASSERT_EQ(r.stations.size(), 9u);
  EXPECT_TRUE(std::isnan(r.stations[0].height));  // above the judged circle at −0.6 R
  EXPECT_NEAR(r.stations[4].height, -1.04e-3, 0.01e-3);
  EXPECT_TRUE(std::isnan(r.stations[8].height));  // below it at +0.6 R

  // The surface found is the powder's: one point in every column from where it enters the judged circle to where it
  // leaves it, falling to the right all the way (flat at its lower end), its band (the time average's blur) 0.7–2.5 mm
  // wide. The rim, its shadow and the light strip along the rim on the left would show as gaps, jumps or wide bands.
  ASSERT_GE(r.surface.size(), 200u);
  const double pixel = geometry.pixel_m();
  for (std::size_t i = 1; i < r.surface.size(); ++i) {
    EXPECT_NEAR(r.surface[i].x - r.surface[i - 1].x, pixel, 1e-9) << i;
    EXPECT_LT(r.surface[i].height, r.surface[i - 1].height + 0.02e-3) << i;  // flat at the lower end
  }
  for (const postprocess::SurfacePoint& p : r.surface) {
    EXPECT_GT(p.band, 0.7e-3) << p.x;
    EXPECT_LT(p.band, 2.5e-3) << p.x;
  }

  if (const char* folder = std::getenv("DEMSA_DRUM_FIGURES"))
    postprocess::write_rgb_png(std::filesystem::path(folder) / "drum-mcc-45rpm.png",
                               postprocess::drum_surface_overlay(image, r));
}

}  // namespace
}  // namespace demsa
