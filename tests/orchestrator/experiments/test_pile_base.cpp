// [pile] base = "particles": the frozen layer of the material's particles on the pedestal top (its assembly, the case
// files that glue it, and a measurement that leaves it out).
#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/exec/measure.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "postprocess/pile_angle.hpp"
#include "support/test_support.hpp"
#include "tests/postprocess/synthetic_cone.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

namespace demsa {
namespace {

using namespace demsa::experiments;
namespace fs = std::filesystem;

const std::string k_study =
    "[study]\nname = \"rough\"\nexperiment = \"pile\"\nseed = 7\n[parameters]\nmu_r_pp = { low = 0.05, high = 0.5 }\n"
    "[pile]\nparticles = 300\npedestal_radius = 0.025\n";

TEST(PileBase, TheLayerCoversThePedestalTopInsideItsRim) {
  const study::StudyConfig config = parse_study(k_study + "base = \"particles\"\n", "study.toml");
  const pile::PileSettings& s = pile::settings(config);
  const std::vector<Particle> layer = pile::build_base_layer(s, config.seed);
  // A hexagonal lattice of pitch 2 r_mean = 4 mm over a disc of radius 25 mm: about pi R^2 / (sqrt(3)/2 p^2) sites.
  const double sites = std::numbers::pi * 0.025 * 0.025 / (std::sqrt(3.0) / 2.0 * 0.004 * 0.004);
  EXPECT_GT(static_cast<double>(layer.size()), 0.9 * sites);
  EXPECT_LT(static_cast<double>(layer.size()), 1.1 * sites);
  for (const Particle& p : layer) {
    EXPECT_LE(std::hypot(p.x, p.y), s.pedestal_radius + 1e-15);
    EXPECT_DOUBLE_EQ(p.z, s.pedestal_height + p.radius);  // resting on the pedestal top
    EXPECT_GE(p.radius, s.radii.r_min);
    EXPECT_LE(p.radius, s.radii.r_max);
  }
  // Drawn from the seed alone: the same layer every time; another seed draws other radii.
  const std::vector<Particle> again = pile::build_base_layer(s, config.seed);
  ASSERT_EQ(again.size(), layer.size());
  for (std::size_t i = 0; i < layer.size(); ++i) EXPECT_EQ(again[i].radius, layer[i].radius);
  const std::vector<Particle> other = pile::build_base_layer(s, config.seed + 1);
  bool differs = false;
  for (std::size_t i = 0; i < std::min(other.size(), layer.size()); ++i)
    differs = differs || other[i].radius != layer[i].radius;
  EXPECT_TRUE(differs);
}

TEST(PileBase, TheCaseGluesTheLayerAndKeepsThePilesOwnParticles) {
  test::TempDir tmp;
  const study::StudyConfig wall = parse_study(k_study, "study.toml");
  const study::StudyConfig rough = parse_study(k_study + "base = \"particles\"\n", "study.toml");
  EXPECT_NE(study::design_hash(rough), study::design_hash(wall));
  EXPECT_EQ(study::design_hash(parse_study(k_study + "base = \"wall\"\n", "study.toml")), study::design_hash(wall));
  const auto request = cases::request_from_unit_point(wall, 0, {0.5});
  const cases::CaseSummary w = cases::write_case(wall, request, tmp / "wall");
  const cases::CaseSummary r = cases::write_case(rough, request, tmp / "rough");
  const long layer = static_cast<long>(pile::build_base_layer(pile::settings(rough), rough.seed).size());
  EXPECT_EQ(r.particles, w.particles + layer);
  // The wall case's script is the template; the rough one glues atoms 1..layer and counts the pile without them.
  const std::string script = test::read_file(tmp / "rough" / "in.liggghts");
  EXPECT_EQ(test::read_file(tmp / "wall" / "in.liggghts").find("base"), std::string::npos);
  EXPECT_NE(script.find("group           base id <= ${base_particles}\nfix             glue base freeze\n"
                        "neigh_modify    exclude group base base\n"),
            std::string::npos);
  EXPECT_NE(script.find("count(all,on_pedestal)-${base_particles}"), std::string::npos);
  // fix freeze must follow gravity and the walls (their forces come first and are then zeroed).
  EXPECT_LT(script.find("fix pedw"), script.find("fix             glue base freeze"));
  EXPECT_NE(
      test::read_file(tmp / "rough" / "params.liggghts").find(fmt::format("base_particles       equal {}", layer)),
      std::string::npos);
  // The data file: the layer first, then the same column as on a wall (same radii and horizontal positions, ids
  // shifted), lifted as a whole so that its lowest disc clears the layer.
  const std::string wall_data = test::read_file(tmp / "wall" / "pile_particles.data");
  const std::string rough_data = test::read_file(tmp / "rough" / "pile_particles.data");
  const auto atom_fields = [](const std::string& data, long id) {
    const std::size_t at = data.find(fmt::format("\n{} ", id), data.find("\nAtoms\n\n"));
    EXPECT_NE(at, std::string::npos) << "no atom " << id;
    std::istringstream line(data.substr(at + 1, data.find('\n', at + 1) - at - 1));
    std::vector<double> fields;
    for (double v = 0; line >> v;) fields.push_back(v);
    return fields;
  };
  const std::vector<double> on_wall = atom_fields(wall_data, 1);
  const std::vector<double> on_layer = atom_fields(rough_data, layer + 1);
  ASSERT_EQ(on_wall.size(), 7U);
  ASSERT_EQ(on_layer.size(), 7U);
  for (std::size_t k = 1; k < 6; ++k) EXPECT_EQ(on_layer[k], on_wall[k]) << "field " << k;
  EXPECT_GT(on_layer[6], on_wall[6]);
  const nlohmann::json doc = nlohmann::json::parse(test::read_file(tmp / "rough" / "case.json"));
  EXPECT_EQ(doc["pile"]["base"]["particles"].get<long>(), layer);
  EXPECT_GT(doc["pile"]["base"]["top_m"].get<double>(), 0.005 + 2 * 0.001);
  EXPECT_FALSE(nlohmann::json::parse(test::read_file(tmp / "wall" / "case.json"))["pile"].contains("base"));
}

TEST(PileBase, TheMeasurementLeavesTheLayerOut) {
  test::TempDir tmp;
  // A cone of 30 degrees standing on a layer whose mean top is 4 mm above the pedestal top: measured without the
  // layer and from the layer's top, it reads the cone. The layer's particles (centres just above that plane, out to
  // 45 mm) would count as the pile and be the outermost particles at the lowest levels.
  test::SyntheticConeOptions cone;
  cone.angle_deg = 30.0;
  cone.pedestal_top = 0.009;
  postprocess::Particles pile = test::make_synthetic_cone(cone);
  postprocess::Particles all;
  const int layer = 400;
  for (int i = 0; i < layer; ++i) {  // ids 1..layer: a flat layer over the whole pedestal
    const double a = 2.39996 * i, r = 0.045 * std::sqrt((i + 0.5) / layer);
    all.id.push_back(i + 1);
    all.type.push_back(1);
    all.x.push_back(r * std::cos(a));
    all.y.push_back(r * std::sin(a));
    all.z.push_back(0.0095);
    all.radius.push_back(0.002);
  }
  for (std::size_t i = 0; i < pile.size(); ++i) {
    all.id.push_back(layer + 1 + static_cast<long>(i));
    all.type.push_back(1);
    all.x.push_back(pile.x[i]);
    all.y.push_back(pile.y[i]);
    all.z.push_back(pile.z[i]);
    all.radius.push_back(pile.radius[i]);
  }
  test::write_file(tmp / pile::k_final_dump, test::synthetic_dump_text(all));
  test::write_file(tmp / study::k_case_json,
                   fmt::format("{{\"experiment\": \"pile\", \"pile\": {{\"pedestal_radius_m\": 0.05, "
                               "\"pedestal_height_m\": 0.005, \"base\": {{\"particles\": {}, \"top_m\": 0.009}}}}}}\n",
                               layer));
  const std::map<std::string, double> values = exec::measure_case(tmp.path());
  postprocess::PileAngleOptions options;
  options.pedestal_top = 0.009;
  const postprocess::PileAngleResult expected = postprocess::measure_pile_angle(pile, options);
  EXPECT_NEAR(values.at(std::string(pile::k_angle)), expected.angle, 1e-3);
  EXPECT_NEAR(values.at(std::string(pile::k_pile_height)), expected.pile_height, 1e-9);
  EXPECT_EQ(values.at(std::string(pile::k_particles_on_pedestal)), static_cast<double>(expected.particles_on_pedestal));
}

}  // namespace
}  // namespace demsa
