// A real LIGGGHTS run of a tiny rotating drum (written by `demsa case`, run by hand with run.sh, measured by `demsa
// measure`): the wall mesh turns, the snapshots are written, and the side view shows a bed whose surface rises on the
// side the rotation carries it up to — the left for clockwise as the camera sees it, the right for counterclockwise.
// About 400 particles over a second of simulated time: seconds of CPU each.
#include "postprocess/dump.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace demsa {
namespace {

namespace fs = std::filesystem;

class DrumReal : public testing::TestWithParam<std::string> {};

TEST_P(DrumReal, ItTurnsAndTheBedRisesOnTheSideTheRotationCarriesItUpTo) {
  const std::string rotation = GetParam();
  test::TempDir tmp;
  const fs::path study = tmp / "tiny_drum.toml";
  std::string text = test::read_file(test::data_path("cases/tiny_drum.toml"));
  text.replace(text.find("rotation = \"clockwise\""), 22, fmt::format("rotation = \"{}\"", rotation));
  test::write_file(study, text);
  const fs::path dir = tmp / "case";
  const test::CommandResult w =
      test::run_demsa({"case", study.string(), "--set", "mu_pp=0.5,mu_r_pp=0.1", "-o", dir.string()});
  ASSERT_EQ(w.exit_code, 0) << w.out << w.err;
  const test::CommandResult r = test::run_command({(dir / "run.sh").string()}, tmp.path());
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err << test::read_file(dir / "screen.txt");
  // It turned: the snapshots are there, 0.4 s / 0.02 s of them (and the first of the window).
  postprocess::DumpReader reader(dir / "drum_snapshots.dump");
  postprocess::DumpFrame frame;
  int frames = 0;
  while (reader.next(frame)) ++frames;
  EXPECT_GE(frames, 20);
  EXPECT_LE(frames, 21);
  const test::CommandResult m = test::run_demsa({"measure", dir.string(), "--json"});
  ASSERT_EQ(m.exit_code, 0) << m.out << m.err;
  const nlohmann::json j = nlohmann::json::parse(m.out)["observables"];
  const double angle = j["dynamic_angle"].get<double>();
  EXPECT_GT(angle, 0.0) << m.out;
  EXPECT_LT(angle, 60.0) << m.out;
  // The stations are mirrored for counterclockwise: surface_1 is always on the side the powder is carried up to.
  EXPECT_GT(j["surface_1"].get<double>(), j["surface_5"].get<double>()) << m.out;
  // Where that is in the picture: the bed's particles lie on the carrying side of the axis on average (x < 0 for
  // clockwise), since the bed leans that way.
  const postprocess::Particles last = postprocess::read_particles(dir / "drum_snapshots.dump", 1);
  double x = 0;
  for (const double v : last.x) x += v;
  x /= static_cast<double>(last.size());
  if (rotation == "clockwise")
    EXPECT_LT(x, -0.001);
  else
    EXPECT_GT(x, 0.001);
  EXPECT_TRUE(fs::is_regular_file(dir / "occupancy.png"));
}

INSTANTIATE_TEST_SUITE_P(BothWays, DrumReal, testing::Values("clockwise", "counterclockwise"));

}  // namespace
}  // namespace demsa
