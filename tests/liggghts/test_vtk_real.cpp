// The ParaView files of real LIGGGHTS cases: a two-sample study of 120-particle piles through `demsa run` (a few
// seconds), whose runner writes CASE/vtk/ after measuring the case. VTK's own reader (python3-vtk9) reads them back;
// they must match the final dump (ids, types, radii, positions, the velocities LIGGGHTS wrote) and the pedestal mesh.
#include "postprocess/dump.hpp"
#include "support/test_support.hpp"
#include "support/vtk_check.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace demsa {
namespace {

namespace fs = std::filesystem;

TEST(VtkReal, TinyPileCaseOpensInVtkWithItsDumpAndPedestal) {
  test::TempDir tmp;
  test::write_file(tmp / "tiny.toml",
                   test::StudyToml{.name = "tiny-vtk-pile",
                                   .seed = 3,
                                   .samples = 2,
                                   .parameters = "mu_pp = { low = 0.2, high = 0.9 }\n",
                                   .tables = "[material]\nE = 1e8\n\n[pile]\nparticles = 120\nsettle_time = 0.1\n",
                                   .run = "ranks = 1\ntimeout = 600\nretries = 0\n",
                                   .analysis = ""}
                       .text());
  const test::CommandResult run =
      test::run_demsa({"run", (tmp / "tiny.toml").string(), "--dir", (tmp / "tiny").string(), "--no-analyze"});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const fs::path dir = tmp / "tiny" / "cases" / "000000";
  const fs::path vtk = dir / "vtk";
  const nlohmann::json files = test::read_vtp({vtk / "particles.vtp", vtk / "pedestal.vtp", vtk / "ground.vtp"});
  const postprocess::DumpFrame frame = postprocess::read_last_frame(dir / "pile_final.dump");
  ASSERT_GT(frame.atom_count, 50u);
  const nlohmann::json& particles = files.at((vtk / "particles.vtp").string());
  test::expect_particles_match(particles, frame);
  // A real run leaves the particles with some velocity: the velocity array is LIGGGHTS's, not zeros.
  double largest = 0;
  for (const nlohmann::json& v : particles.at("arrays").at("velocity").at("values"))
    largest = std::max(largest, std::abs(v.get<double>()));
  EXPECT_GT(largest, 0.0);
  test::expect_pedestal_matches(files.at((vtk / "pedestal.vtp").string()), dir);
  EXPECT_EQ(files.at((vtk / "ground.vtp").string()).at("polys").get<int>(), 1);
}

}  // namespace
}  // namespace demsa
