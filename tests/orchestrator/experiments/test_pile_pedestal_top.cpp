// [pile] pedestal_top: the pedestal's top as a mesh (the default) or as a primitive plane with the particles past the
// rim deleted (the case script of each, the hash, and the settings a plane cannot stand with).
#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace demsa {
namespace {

using namespace demsa::experiments;
namespace fs = std::filesystem;

const std::string k_study =
    "[study]\nname = \"p\"\nexperiment = \"pile\"\nseed = 7\n[parameters]\nmu_r_pp = { low = 0.05, high = 0.5 }\n"
    "[pile]\nparticles = 300\n";

std::string error_of(const std::string& text) {
  return test::message_of<util::UserError>([&] { parse_study(text, "study.toml"); });
}

bool plane(const std::string& lines) { return pile::plane_pedestal(pile::settings(parse_study(k_study + lines, "s"))); }

TEST(PilePedestalTop, TheMeshIsTheDefaultAndThePlaneIsChosen) {
  EXPECT_FALSE(plane(""));
  EXPECT_FALSE(plane("remove_fallen = true\n"));
  EXPECT_FALSE(plane("remove_fallen = true\npedestal_top = \"mesh\"\n"));
  EXPECT_TRUE(plane("remove_fallen = true\npedestal_top = \"plane\"\n"));
}

TEST(PilePedestalTop, APlaneIsRefusedWhereItCannotStandInForTheMesh) {
  const std::string keep = error_of(k_study + "pedestal_top = \"plane\"\n");
  EXPECT_NE(keep.find("study.toml:9"), std::string::npos) << keep;
  EXPECT_NE(keep.find("pedestal_top"), std::string::npos) << keep;
  EXPECT_NE(keep.find("needs remove_fallen = true"), std::string::npos) << keep;
  const std::string rough =
      error_of(k_study + "remove_fallen = true\nbase = \"particles\"\npedestal_top = \"plane\"\n");
  EXPECT_NE(rough.find("base = \"particles\" has none"), std::string::npos) << rough;
  EXPECT_NE(error_of(k_study + "pedestal_top = \"auto\"\n").find("pedestal_top"), std::string::npos);
}

TEST(PilePedestalTop, ThePlaneIsAnotherCaseAndTheMeshKeepsItsHash) {
  const study::StudyConfig before = parse_study(k_study + "remove_fallen = true\n", "s");
  const study::StudyConfig mesh = parse_study(k_study + "remove_fallen = true\npedestal_top = \"mesh\"\n", "s");
  const study::StudyConfig flat = parse_study(k_study + "remove_fallen = true\npedestal_top = \"plane\"\n", "s");
  const std::string mesh_text = settings_table().hash_text(mesh);
  EXPECT_EQ(mesh_text.find("pedestal_top"), std::string::npos) << mesh_text;  // as before the key existed
  EXPECT_EQ(study::design_hash(before), study::design_hash(mesh));
  EXPECT_NE(settings_table().hash_text(flat).find("pile.pedestal_top=plane"), std::string::npos);
  EXPECT_NE(study::design_hash(flat), study::design_hash(mesh));
}

TEST(PilePedestalTop, ThePlaneCaseHasAPrimitiveTopAndRemovesEveryParticlePastTheRim) {
  test::TempDir tmp;
  const study::StudyConfig mesh = parse_study(k_study + "remove_fallen = true\npedestal_top = \"mesh\"\n", "s");
  const study::StudyConfig flat = parse_study(k_study + "remove_fallen = true\npedestal_top = \"plane\"\n", "s");
  const auto request = cases::request_from_unit_point(mesh, 0, {0.5});
  const cases::CaseSummary m = cases::write_case(mesh, request, tmp / "mesh");
  const cases::CaseSummary p = cases::write_case(flat, request, tmp / "plane");
  EXPECT_EQ(p.particles, m.particles);
  const std::string m_script = test::read_file(tmp / "mesh" / "in.liggghts");
  const std::string p_script = test::read_file(tmp / "plane" / "in.liggghts");
  EXPECT_NE(m_script.find("fix pedm        all mesh/surface file pedestal.stl type 2\n"), std::string::npos);
  EXPECT_NE(m_script.find("region          fallen intersect 2 below_top off_radius\n"), std::string::npos);
  EXPECT_EQ(p_script.find("mesh/surface"), std::string::npos);
  EXPECT_NE(p_script.find("fix pedw        all wall/gran model hertz tangential history rolling_friction cdt "
                          "primitive type 2 zplane ${pedestal_height}\n"),
            std::string::npos);
  EXPECT_NE(p_script.find("region          fallen cylinder z 0.0 0.0 ${pedestal_radius} INF INF units box side out\n"),
            std::string::npos);
  // The same particles, schedule and drawing of the pedestal: only the wall differs.
  for (const char* file : {"pile_particles.data", "pile_discs.liggghts", "params.liggghts", "pedestal.stl"})
    EXPECT_EQ(test::read_file(tmp / "plane" / file), test::read_file(tmp / "mesh" / file)) << file;
  EXPECT_EQ(nlohmann::json::parse(test::read_file(tmp / "plane" / "case.json"))["pile"]["pedestal_top"], "plane");
  EXPECT_EQ(nlohmann::json::parse(test::read_file(tmp / "mesh" / "case.json"))["pile"]["pedestal_top"], "mesh");
}

TEST(PilePedestalTop, ThePlaneTakesTheStudysRollingModel) {
  test::TempDir tmp;
  const study::StudyConfig flat = parse_study(
      k_study + "remove_fallen = true\npedestal_top = \"plane\"\n[contact]\nrolling_model = \"epsd2\"\n", "s");
  cases::write_case(flat, cases::request_from_unit_point(flat, 0, {0.5}), tmp / "c");
  const std::string script = test::read_file(tmp / "c" / "in.liggghts");
  EXPECT_NE(script.find("rolling_friction epsd2 primitive type 2 zplane ${pedestal_height}"), std::string::npos)
      << script;
  EXPECT_EQ(script.find("rolling_friction cdt"), std::string::npos);
}

}  // namespace
}  // namespace demsa
