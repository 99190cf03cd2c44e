// The ParaView files of a case: written by `demsa run` after each case is measured, and by `demsa export-vtk` for a
// case folder or a dump. Every file is read back with VTK's own XML reader (Debian's python3-vtk9, through
// tests/data/vtk/read_vtp.py) and compared with the dump, the case's meshes and its case.json.
#include "postprocess/dump.hpp"
#include "postprocess/oedometer.hpp"
#include "support/test_support.hpp"
#include "support/vtk_check.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace demsa {
namespace {

namespace fs = std::filesystem;

std::string fake_study(const std::string& experiment, int samples, const std::string& liggghts_lines) {
  return test::StudyToml{
      .name = "vtk-" + experiment,
      .experiment = experiment,
      .samples = samples,
      .parameters = "mu_pp = { low = 0.2, high = 0.8 }\nmu_r_pp = { low = 0.05, high = 0.3 }\n",
      .tables = experiment == "pile" ? "[pile]\nparticles = 300\n" : "[oedometer]\nparticles = 200\n",
      .run = liggghts_lines + "parallel = 1\nretries = 0\n",
      .analysis = ""}
      .text();
}

/// `demsa run` of a fake-LIGGGHTS study of `experiment` in TMP/study.
void run_fake_study(const test::TempDir& tmp, const std::string& experiment, int samples) {
  test::write_file(tmp / "study.toml", fake_study(experiment, samples, test::fake_liggghts_run_lines()));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--no-analyze", "--quiet"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
}

TEST(ExportVtk, HelpListsTheCommand) {
  const test::CommandResult r = test::run_demsa({"--help"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\n  export-vtk "), std::string::npos) << r.out;
}

TEST(ExportVtk, FakePileCaseWritesParticlesPedestalAndGroundThatVtkReads) {
  test::TempDir tmp;
  run_fake_study(tmp, "pile", 2);
  for (const char* sample : {"000000", "000001"}) {
    SCOPED_TRACE(sample);
    const fs::path dir = tmp / "study" / "cases" / sample;
    const fs::path vtk = dir / "vtk";
    const nlohmann::json files = test::read_vtp({vtk / "particles.vtp", vtk / "pedestal.vtp", vtk / "ground.vtp"});
    const postprocess::DumpFrame frame = postprocess::read_last_frame(dir / "pile_final.dump");
    test::expect_particles_match(files.at((vtk / "particles.vtp").string()), frame);
    test::expect_pedestal_matches(files.at((vtk / "pedestal.vtp").string()), dir);
    // The ground: one quad at z = 0 over the dump's box.
    const nlohmann::json& ground = files.at((vtk / "ground.vtp").string());
    EXPECT_EQ(ground.at("polys").get<int>(), 1);
    EXPECT_EQ(ground.at("polygon_sizes"), nlohmann::json::array({4}));
    EXPECT_EQ(ground.at("bounds"),
              nlohmann::json::array({frame.box[0], frame.box[1], frame.box[2], frame.box[3], 0, 0}));
  }
}

TEST(ExportVtk, FakeOedometerCaseWritesTheBoxAndThePlateAtItsLastHeight) {
  test::TempDir tmp;
  run_fake_study(tmp, "oedometer", 2);
  const fs::path dir = tmp / "study" / "cases" / "000000";
  const fs::path vtk = dir / "vtk";
  EXPECT_FALSE(fs::exists(vtk / "pedestal.vtp"));
  const nlohmann::json files = test::read_vtp({vtk / "particles.vtp", vtk / "box.vtp", vtk / "plate.vtp"});
  test::expect_particles_match(files.at((vtk / "particles.vtp").string()),
                               postprocess::read_last_frame(dir / "oedometer_final.dump"));
  test::expect_oedometer_geometry_matches(files.at((vtk / "box.vtp").string()), files.at((vtk / "plate.vtp").string()),
                                          dir);
}

TEST(ExportVtk, CaseFolderToAnotherFolderGivesTheSameFilesAsTheRun) {
  test::TempDir tmp;
  run_fake_study(tmp, "oedometer", 2);
  const fs::path dir = tmp / "study" / "cases" / "000000";
  const test::CommandResult r = test::run_demsa({"export-vtk", dir.string(), "--out", (tmp / "out").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"particles.vtp", "box.vtp", "plate.vtp"}) {
    EXPECT_NE(r.out.find((tmp / "out" / name).string()), std::string::npos) << r.out;
    EXPECT_EQ(test::read_file(tmp / "out" / name), test::read_file(dir / "vtk" / name)) << name;
  }
}

const std::string k_two_frames =
    "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS ff ff ff\n-1 1\n-1 1\n0 2\n"
    "ITEM: ATOMS id type x y z radius vx vy vz\n1 1 0 0 0.5 0.1 0 0 0\n"
    "ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS ff ff ff\n-1 1\n-1 1\n0 2\n"
    "ITEM: ATOMS type vz id x y z radius vx vy\n"
    "1 -0.25 7 0.1 0.2 0.3 0.01 1.5 -2\n"
    "2 3e-7 3 -0.1 -0.2 0.6 0.02 0 0.125\n"
    "1 0 12 0.4 0.5 1.75 0.015 -1e-3 4\n";

TEST(ExportVtk, DumpFileGivesItsLastFrameWithVelocities) {
  test::TempDir tmp;
  test::write_file(tmp / "run.dump", k_two_frames);
  const test::CommandResult r = test::run_demsa({"export-vtk", (tmp / "run.dump").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, (tmp / "run.vtp").string() + "\n");
  const nlohmann::json all = test::read_vtp({tmp / "run.vtp"});
  const nlohmann::json& p = all.at((tmp / "run.vtp").string());
  EXPECT_EQ(p.at("points").get<int>(), 3);
  EXPECT_EQ(p.at("verts").get<int>(), 3);
  const nlohmann::json& a = p.at("arrays");
  EXPECT_EQ(a.at("id").at("values"), nlohmann::json::array({7, 3, 12}));
  EXPECT_EQ(a.at("type").at("values"), nlohmann::json::array({1, 2, 1}));
  EXPECT_EQ(a.at("radius").at("values"), nlohmann::json::array({0.01, 0.02, 0.015}));
  EXPECT_EQ(a.at("velocity").at("components").get<int>(), 3);
  EXPECT_EQ(a.at("velocity").at("values"), nlohmann::json::array({1.5, -2, -0.25, 0, 0.125, 3e-7, -1e-3, 4, 0}));
  EXPECT_EQ(p.at("coordinates"), nlohmann::json::parse("[[0.1,0.2,0.3],[-0.1,-0.2,0.6],[0.4,0.5,1.75]]"));

  // --out: the file goes there; a dump without velocities gives the particles without a velocity array.
  const std::string no_velocity =
      "ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS ff ff ff\n-1 1\n-1 1\n0 2\n"
      "ITEM: ATOMS id type x y z radius\n5 1 0 0 1 0.01\n";
  test::write_file(tmp / "plain.dump", no_velocity);
  const test::CommandResult out =
      test::run_demsa({"export-vtk", (tmp / "plain.dump").string(), "--out", (tmp / "pictures").string()});
  ASSERT_EQ(out.exit_code, 0) << out.err;
  const nlohmann::json plain = test::read_vtp({tmp / "pictures" / "plain.vtp"});
  const nlohmann::json& q = plain.begin().value();
  EXPECT_EQ(q.at("points").get<int>(), 1);
  EXPECT_FALSE(q.at("arrays").contains("velocity"));
  EXPECT_TRUE(q.at("arrays").contains("radius"));
}

/// `demsa export-vtk ARGS`: exit 2 with every piece of `expected` in the message.
void expect_user_error(const std::vector<std::string>& args, const std::vector<std::string>& expected) {
  std::vector<std::string> full{"export-vtk"};
  full.insert(full.end(), args.begin(), args.end());
  const test::CommandResult r = test::run_demsa(full);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  for (const std::string& piece : expected) EXPECT_NE(r.err.find(piece), std::string::npos) << piece << "\n" << r.err;
}

TEST(ExportVtk, BadInputIsAUserErrorNamingFileLineAndValue) {
  test::TempDir tmp;
  std::string bad = k_two_frames;
  bad.replace(bad.find("0.015"), 5, "0.0x5");
  test::write_file(tmp / "bad.dump", bad);
  expect_user_error({(tmp / "bad.dump").string()}, {"bad.dump:22:", "0.0x5"});
  std::string partial = k_two_frames;
  partial.replace(partial.find("type vz id"), 10, "type vq id");
  test::write_file(tmp / "partial.dump", partial);
  expect_user_error({(tmp / "partial.dump").string()},
                    {"partial.dump", "ITEM: ATOMS of time step 100 has vx vy but not all of vx vy vz"});
  test::write_file(tmp / "empty.dump", "");
  expect_user_error({(tmp / "empty.dump").string()}, {"empty.dump"});
  expect_user_error({(tmp / "nothing-here").string()}, {"nothing-here", "no such case folder or dump file"});
  fs::create_directories(tmp / "not-a-case");
  expect_user_error({(tmp / "not-a-case").string()}, {"not-a-case", "not a case folder (no case.json)"});
  EXPECT_FALSE(fs::exists(tmp / "not-a-case" / "vtk"));

  // A case whose pedestal mesh or case.json is broken: the file, the line or key, and the value.
  run_fake_study(tmp, "pile", 2);
  const fs::path pile = tmp / "study" / "cases" / "000000";
  fs::remove_all(pile / "vtk");
  std::string stl = test::read_file(pile / "pedestal.stl");
  // The first coordinate of the first facet's second vertex (line 5).
  const std::size_t at = stl.find("vertex ", stl.find("vertex ") + 1) + 7;
  stl.replace(at, stl.find(' ', at) - at, "1.0e-3x");
  test::write_file(pile / "pedestal.stl", stl);
  expect_user_error({pile.string()}, {"pedestal.stl:5:", "'1.0e-3x'"});
  EXPECT_FALSE(fs::exists(pile / "vtk")) << "nothing is written when an input is bad";
  nlohmann::json doc = nlohmann::json::parse(test::read_file(pile / "case.json"));
  doc["experiment"] = "silo";
  test::write_file(pile / "case.json", doc.dump(2));
  expect_user_error({pile.string()}, {"case.json", "experiment = \"silo\""});
}

TEST(ExportVtk, OedometerCaseJsonWithoutTheBoxNamesTheKey) {
  test::TempDir tmp;
  run_fake_study(tmp, "oedometer", 2);
  const fs::path dir = tmp / "study" / "cases" / "000000";
  nlohmann::json doc = nlohmann::json::parse(test::read_file(dir / "case.json"));
  doc["oedometer"]["box_side_m"] = -0.1;
  test::write_file(dir / "case.json", doc.dump(2));
  expect_user_error({dir.string()}, {"case.json", "oedometer.box_side_m = -0.1"});
  doc["oedometer"].erase("box_side_m");
  test::write_file(dir / "case.json", doc.dump(2));
  expect_user_error({dir.string()}, {"case.json", "no oedometer.box_side_m"});
}

TEST(ExportVtk, AFailureToWriteTheFilesOnlyWarnsAndTheCaseCounts) {
  // A LIGGGHTS that leaves a file named `vtk` where the folder would go: the case is measured and done all the same.
  test::TempDir tmp;
  const fs::path fake = fs::path(DEMSA_SOURCE_DIR) / "tests" / "integration" / "fake_liggghts";
  test::write_file(tmp / "liggghts",
                   fmt::format("#!/bin/bash\n'{}' \"$@\"\nstatus=$?\necho blocked > vtk\nexit $status\n",
                               (fake / "liggghts").string()));
  fs::permissions(tmp / "liggghts", fs::perms::owner_all);
  test::write_file(tmp / "study.toml",
                   fake_study("pile", 2,
                              fmt::format("liggghts = \"{}\"\nmpirun = \"{}\"\n", (tmp / "liggghts").string(),
                                          (fake / "mpirun").string())));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--no-analyze"}));
  EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.err.find("the case was measured, but its ParaView files were not written"), std::string::npos)
      << run.err;
  EXPECT_TRUE(fs::exists(tmp / "study" / "cases" / "000000" / "result.json"));
}

}  // namespace
}  // namespace demsa
