// The rotating drum: its [drum] settings (refused values name file:line:key), its fill (count, coarse grain, classes,
// identical for every sample), its wall mesh and the case files (the rotation's sign as the camera sees it), and the
// geometry file of a laboratory photograph.
#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/experiments/assembly.hpp"
#include "orchestrator/experiments/drum/drum.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/stl.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>
#include <string>

namespace demsa {
namespace {

using namespace demsa::experiments;
namespace fs = std::filesystem;

// The MCC of the GranuDrum's images (psd.csv): diameters 1.05-1.50 mm and their number fractions.
const std::string k_classes =
    "diameters = [1.05e-3, 1.10e-3, 1.15e-3, 1.20e-3, 1.25e-3, 1.30e-3, 1.35e-3, 1.40e-3, 1.45e-3, 1.50e-3]\n"
    "fractions = [0.0064659, 0.07387693, 0.26249571, 0.25249525, 0.17012964, 0.10530736, 0.06885834, 0.03662696, "
    "0.01861549, 0.00512842]\n";

std::string study_text(const std::string& drum) {
  return "[study]\nname = \"drum\"\nexperiment = \"drum\"\nseed = 11\n[parameters]\nmu_pp = { low = 0.2, high = 0.8 "
         "}\n[material]\nE = 5e6\ne_r = 0.3\ndensity = 1580\n[drum]\npreset = \"granudrum\"\n" +
         drum;
}

study::StudyConfig parse(const std::string& drum) { return parse_study(study_text(drum), "study.toml"); }

/// The message of the UserError that parsing `drum` throws.
std::string refusal(const std::string& drum) {
  return test::message_of<util::UserError>([&] { parse(drum); });
}

/// The refusal of `drum` holds `part`; the whole message is printed when it does not.
void expect_refusal_holds(const std::string& drum, const std::string& part) {
  const std::string message = refusal(drum);
  EXPECT_NE(message.find(part), std::string::npos) << message;
}

TEST(DrumSettings, ThePresetAndTheDefaultsAreTheGranuDrums) {
  const study::StudyConfig c = parse(k_classes);
  const drum::DrumSettings& s = drum::settings(c);
  EXPECT_EQ(s.radius, 0.042);
  EXPECT_EQ(s.depth, 0.020);
  EXPECT_EQ(s.rotation, postprocess::DrumRotation::clockwise);
  EXPECT_EQ(s.image_size, 406);
  EXPECT_EQ(c.material.density, 1580);  // [material] density sets the particles' density for the drum too
  // 50 mL of bulk at a solid fraction of 0.6 over the mean volume of the classes, π/6 Σ f d³ = 9.6812e-10 m³.
  EXPECT_NEAR(drum::mean_particle_volume(s), 9.6812e-10, 1e-13);
  EXPECT_EQ(drum::fill_count(s), std::lround(5e-5 * 0.6 / drum::mean_particle_volume(s)));
  EXPECT_NEAR(static_cast<double>(drum::fill_count(s)), 30988, 1);
}

TEST(DrumSettings, BadValuesAreRefusedAtTheirLine) {
  // study_text's [drum] starts at line 11 (preset on 12); the key given first is on line 13.
  EXPECT_EQ(refusal("fractions = [0.5, 0.4]\ndiameters = [1e-3, 2e-3]\n").substr(0, 38),
            "study.toml:13: [drum] fractions: the f");
  EXPECT_NE(refusal("fractions = [0.5, 0.4]\ndiameters = [1e-3, 2e-3]\n").find("sum to 0.9"), std::string::npos);
  EXPECT_NE(refusal("diameters = [1e-3, 2e-3]\nfractions = [1.0]\n")
                .find("study.toml:14: [drum] fractions: 1 "
                      "fractions for 2 diameters"),
            std::string::npos);
  EXPECT_NE(refusal("diameters = [1e-3, 2e-3]\nfractions = [1.0, 0.0]\n")
                .find("study.toml:14: [drum] fractions: "
                      "fraction 2 = 0"),
            std::string::npos);
  EXPECT_NE(refusal(k_classes + "r_min = 0.5e-3\n").find("study.toml:15: [drum] r_min: give the sizes either"),
            std::string::npos);
  EXPECT_NE(refusal("rotation = \"left\"\n").find("study.toml:13:"), std::string::npos);
  EXPECT_NE(refusal("rotation = \"left\"\n").find("counterclockwise"), std::string::npos);
  EXPECT_NE(refusal("rpm = -3\n").find("study.toml:13:"), std::string::npos);
  EXPECT_NE(refusal("coarse_grain = 0.5\n").find("study.toml:13:"), std::string::npos);
  EXPECT_NE(refusal("bulk_volume = 1e-4\nparticles = 3000\n")
                .find("study.toml:14: [drum] particles: give the fill "
                      "either"),
            std::string::npos);
  EXPECT_NE(refusal("bulk_volume = 1.1e-4\n").find("study.toml:13: [drum] bulk_volume: a bulk volume"),
            std::string::npos);
  EXPECT_NE(refusal("stations = [-0.9, 0.0]\n").find("study.toml:13: [drum] stations: station -0.9 lies outside"),
            std::string::npos);
  EXPECT_NE(refusal("snapshot_interval = 3\n").find("study.toml:13: [drum] snapshot_interval:"), std::string::npos);
  EXPECT_NE(refusal(k_classes + "coarse_grain = 8\n").find("[drum] depth:"), std::string::npos);
  // Another experiment's study refuses the section.
  EXPECT_NE(test::message_of<util::UserError>([] {
              parse_study(
                  "[study]\nname = \"p\"\nexperiment = \"pile\"\n[parameters]\nmu_pp = { low = 0.2, high = "
                  "0.8 }\n[drum]\nrpm = 10\n",
                  "study.toml");
            }).find("study.toml:"),
            std::string::npos);
}

TEST(DrumSettings, AFillOrAScheduleTheMeasurementCannotUseIsRefusedAtItsLine) {
  // A drum of 10 m with the default 50 mL: the writer enumerated every lattice site of the drum (1e11, out of
  // memory, exit 3); the bed would lie far below the judged circle.
  expect_refusal_holds("radius = 10\ndepth = 10\n",
                       "study.toml:11: [drum] bulk_volume: a bulk volume of 5e-05 m³ fills 1.59e-06 % of the drum");
  // 5.9 % of the GranuDrum: its level surface lies 0.78 R below the centre; 6.4 % is the least.
  EXPECT_NE(refusal("bulk_volume = 6.5e-6\n").find("at least 6.39 %"), std::string::npos);
  EXPECT_NO_THROW(parse("bulk_volume = 7.5e-6\n"));
  // More particles than any study may hold (a cubic metre of them: 2.3e7 at K = 3): the dry run ran out of time and
  // memory writing them.
  expect_refusal_holds("radius = 1\ndepth = 1\nbulk_volume = 1\ncoarse_grain = 3\n",
                       "study.toml:15: [drum] bulk_volume: 2.339e+07 particles (coarse_grain = 3), more than 1e+07");
  // Below 90 % of the drum but more than its lattice holds: refused at the line, not by the case writer without one.
  expect_refusal_holds("coarse_grain = 3\nbulk_volume = 9e-5\n",
                       "study.toml:14: [drum] bulk_volume: 2105 particles (coarse_grain = 3) do not fit into the drum: "
                       "it holds 1203 of the lattice sites");
  // A window of 2e300 snapshots (rounded to a long, one step) or of 2e7 one-step snapshots.
  EXPECT_NE(refusal("snapshot_interval = 1e-300\n")
                .find("study.toml:13: [drum] snapshot_interval: 1e-300 s over a "
                      "window of 2 s is 2e+300 snapshots, more than 10000"),
            std::string::npos);
  // A drum that has not turned a quarter turn by the first snapshot shows a bed that may be at rest.
  expect_refusal_holds("rpm = 1e-9\n",
                       "study.toml:13: [drum] rpm: 1.5 s at 1e-09 rpm turns the drum 2.5e-11 of a turn");
  EXPECT_NE(refusal("rpm = 5\nspin_up = 2\n").find("study.toml:14: [drum] spin_up:"), std::string::npos);
  EXPECT_NO_THROW(parse("rpm = 5\nspin_up = 3\n"));
  EXPECT_NE(refusal("stations = [0.1, -0.2, 0.1]\n").find("study.toml:13: [drum] stations: station 0.1 is given twice"),
            std::string::npos);
}

TEST(DrumCase, TheWindowLastsWhatItAsksWhereTheIntervalRoundsToAStep) {
  // A snapshot interval below the time step is one step; the window's intervals were counted in seconds, so a window
  // of 1 ms at an interval of 1e-7 s lasted a hundred times longer.
  test::TempDir tmp;
  const study::StudyConfig c = parse(k_classes + "coarse_grain = 3\nwindow = 1e-3\nsnapshot_interval = 1e-7\n");
  const cases::CaseSummary a = cases::write_case(c, cases::request_from_unit_point(c, 0, {0.5}), tmp / "a");
  const nlohmann::json doc = nlohmann::json::parse(test::read_file(tmp / "a" / "case.json"));
  EXPECT_EQ(doc["drum"]["snapshot_steps"].get<long>(), 1);
  EXPECT_EQ(doc["drum"]["window_steps"].get<long>(), std::lround(1e-3 / a.dt));
  EXPECT_EQ(doc["drum"]["snapshots"].get<long>(), std::lround(1e-3 / a.dt));
}

TEST(DrumFill, CoarseGrainScalesTheRadiiAndDividesTheCount) {
  const drum::DrumSettings full = drum::settings(parse(k_classes));
  const drum::DrumSettings coarse = drum::settings(parse(k_classes + "coarse_grain = 3\n"));
  EXPECT_EQ(drum::fill_count(coarse), std::lround(static_cast<double>(drum::fill_count(full)) / 27.0));
  const std::vector<Particle> fill = drum::build_fill(coarse, 11);
  ASSERT_EQ(static_cast<long>(fill.size()), drum::fill_count(coarse));
  double r_min = 1, r_max = 0, solid = 0;
  for (const Particle& p : fill) {
    r_min = std::min(r_min, p.radius);
    r_max = std::max(r_max, p.radius);
    solid += 4.0 / 3.0 * std::numbers::pi * std::pow(p.radius, 3);
    // Inside the drum's flat sides and between its end plates.
    EXPECT_LE(std::hypot(p.x, p.z) + p.radius, 0.042 * 0.9993);
    EXPECT_GE(p.y - p.radius, 0.0);
    EXPECT_LE(p.y + p.radius, 0.020);
  }
  EXPECT_NEAR(r_min, 3 * 1.05e-3 / 2, 1e-12);
  EXPECT_NEAR(r_max, 3 * 1.50e-3 / 2, 1e-12);
  // The same bulk: the solid volume of the coarse fill is the full fill's (50 mL × 0.6) within the rounding.
  EXPECT_NEAR(solid, 5e-5 * 0.6, 5e-5 * 0.6 * 0.01);
  EXPECT_GT(min_pair_gap(fill), 0.0);
  // The lattice fills from the bottom: the fill's centre of mass lies below the axis.
  double z = 0;
  for (const Particle& p : fill) z += p.z;
  EXPECT_LT(z / static_cast<double>(fill.size()), 0.0);
}

TEST(DrumFill, TheClassesKeepTheirNumberFractions) {
  const drum::DrumSettings s = drum::settings(parse(k_classes + "coarse_grain = 2\n"));
  const std::vector<Particle> fill = drum::build_fill(s, 11);
  std::map<long, long> per_class;
  for (const Particle& p : fill) ++per_class[std::lround(p.radius * 1e6)];  // 2 r / K in µm (K = 2)
  const double n = static_cast<double>(fill.size());
  EXPECT_NEAR(per_class[1150] / n, 0.26249571, 1.0 / n);
  EXPECT_NEAR(per_class[1500] / n, 0.00512842, 1.0 / n);
}

TEST(DrumFill, ItIsDrawnFromTheSeedAlone) {
  const drum::DrumSettings s = drum::settings(parse(k_classes + "coarse_grain = 3\n"));
  const std::vector<Particle> a = drum::build_fill(s, 11), b = drum::build_fill(s, 11), c = drum::build_fill(s, 12);
  ASSERT_EQ(a.size(), b.size());
  bool differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].radius, b[i].radius);
    EXPECT_EQ(a[i].z, b[i].z);
    differs = differs || a[i].radius != c[i].radius;
  }
  EXPECT_TRUE(differs);
}

TEST(DrumMesh, APrismOfSixTrianglesASideWithTheCirclesAreaAndInwardNormals) {
  const double radius = 0.042, depth = 0.02;
  const std::vector<Triangle> mesh = drum::drum_mesh(radius, depth, 48);
  ASSERT_EQ(mesh.size(), 6u * 48u);
  double plate_area = 0;
  for (const Triangle& t : mesh) {
    const Vertex u{t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]};
    const Vertex v{t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]};
    const Vertex n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const Vertex c{(t[0][0] + t[1][0] + t[2][0]) / 3, (t[0][1] + t[1][1] + t[2][1]) / 3,
                   (t[0][2] + t[1][2] + t[2][2]) / 3};
    // Into the drum: towards the axis point at the centroid's... the drum's centre (0, depth/2, 0).
    EXPECT_LT(n[0] * c[0] + n[1] * (c[1] - depth / 2) + n[2] * c[2], 0.0);
    if (t[0][1] == 0 && t[1][1] == 0 && t[2][1] == 0) plate_area += 0.5 * std::abs(n[1]);
    // Compact: no edge longer than R/2 + a side's length.
    for (int k = 0; k < 3; ++k) {
      const Vertex& p = t[k];
      const Vertex& q = t[(k + 1) % 3];
      EXPECT_LE(std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]), radius * (0.5 + 2 * std::numbers::pi / 48) * 1.01);
    }
  }
  EXPECT_NEAR(plate_area, std::numbers::pi * radius * radius, 1e-12);
}

TEST(DrumCase, TheFilesTurnTheDrumAsTheCameraSeesItWithTheSameParticlesEverySample) {
  test::TempDir tmp;
  const study::StudyConfig cw = parse(k_classes + "coarse_grain = 3\nwall_sides = 36\nrpm = 30\n");
  const study::StudyConfig ccw = parse(k_classes +
                                       "coarse_grain = 3\nwall_sides = 36\nrpm = 30\nrotation = "
                                       "\"counterclockwise\"\n");
  EXPECT_NE(study::design_hash(cw), study::design_hash(ccw));
  const cases::CaseSummary a = cases::write_case(cw, cases::request_from_unit_point(cw, 0, {0.1}), tmp / "a");
  const cases::CaseSummary b = cases::write_case(cw, cases::request_from_unit_point(cw, 1, {0.9}), tmp / "b");
  cases::write_case(ccw, cases::request_from_unit_point(ccw, 0, {0.1}), tmp / "c");
  EXPECT_EQ(a.particles, drum::fill_count(drum::settings(cw)));
  // Identical particles in every sample: the data files are the same bytes.
  EXPECT_EQ(test::read_file(tmp / "a" / "drum_particles.data"), test::read_file(tmp / "b" / "drum_particles.data"));
  // The rotation: +y (clockwise through the end plate at y = 0) or −y, one turn in 60/rpm = 2 s.
  const std::string params_a = test::read_file(tmp / "a" / "params.liggghts");
  const auto variable = [](const std::string& name, const std::string& value) {
    return fmt::format("variable {:<20} equal {:<24} #", name, value);
  };
  EXPECT_NE(params_a.find(variable("axis_y", "1")), std::string::npos) << params_a;
  EXPECT_NE(test::read_file(tmp / "c" / "params.liggghts").find(variable("axis_y", "-1")), std::string::npos);
  EXPECT_NE(params_a.find(variable("period", "2")), std::string::npos) << params_a;
  const std::string script = test::read_file(tmp / "a" / "in.liggghts");
  EXPECT_NE(script.find("rotate origin 0.0 0.0 0.0 axis 0.0 ${axis_y} 0.0 period ${period}"), std::string::npos);
  EXPECT_NE(script.find("mesh n_meshes 1 meshes drum"), std::string::npos);
  EXPECT_LT(script.find("run             ${settle_steps}"), script.find("fix turn"));
  // The wall: one mesh of 6 × 36 triangles, as LIGGGHTS reads it.
  EXPECT_EQ(postprocess::read_ascii_stl(tmp / "a" / drum::k_mesh_file).triangles.size(), 6u * 36u);
  const nlohmann::json doc = nlohmann::json::parse(test::read_file(tmp / "a" / "case.json"));
  EXPECT_EQ(doc["drum"]["camera"]["looks_along"], "+y");
  EXPECT_EQ(doc["drum"]["camera"]["image_up"], "z");
  EXPECT_EQ(doc["drum"]["wall_triangles"], 216);
  EXPECT_EQ(doc["drum"]["rotation"], "clockwise");
  EXPECT_EQ(doc["assembly"]["coarse_grain"], 3.0);
  // The schedule: whole snapshot intervals over the window; its cost counts every atom over every step.
  const long window = doc["drum"]["window_steps"], snapshot = doc["drum"]["snapshot_steps"];
  EXPECT_EQ(window % snapshot, 0);
  EXPECT_EQ(window / snapshot, 50);
  const CaseCost cost = drum::case_cost(cw, doc, tmp / "a" / "case.json", nullptr);
  const long steps = doc["drum"]["settle_steps"].get<long>() + doc["drum"]["spin_up_steps"].get<long>() + window;
  EXPECT_EQ(cost.steps, steps);
  EXPECT_DOUBLE_EQ(cost.atom_steps, static_cast<double>(steps) * static_cast<double>(a.particles));
  EXPECT_FALSE(cost.may_end_early);
  // A turning drum is billed below the standard run's rate, by its measured share of it (docs/how-to/cost.md).
  EXPECT_GT(cost.rate_factor, 0.0);
  EXPECT_LT(cost.rate_factor, 1.0);
  EXPECT_NE(cost.rate_factor_source.find("coarse 45 rpm"), std::string::npos) << cost.rate_factor_source;
  EXPECT_DOUBLE_EQ(b.dt, a.dt);
  // ParaView's wall: the mesh turned as far as the drum turned by the end, clockwise (+z towards +x) here.
  const std::vector<CaseSurface> surfaces = drum::experiment().vtk_surfaces(tmp / "a", doc, postprocess::DumpFrame{});
  ASSERT_EQ(surfaces.size(), 1u);
  ASSERT_TRUE(surfaces[0].surface);
  EXPECT_EQ(surfaces[0].surface->polygons.size(), 216u);
  const double turned =
      2 * std::numbers::pi * static_cast<double>(doc["drum"]["spin_up_steps"].get<long>() + window) * a.dt / 2.0;
  const std::vector<Triangle> mesh = drum::drum_mesh(0.042, 0.02, 36);
  const std::array<double, 3>& p = surfaces[0].surface->points[1];
  const Vertex& q = mesh[0][1];
  EXPECT_NEAR(std::atan2(p[0], p[2]), std::remainder(std::atan2(q[0], q[2]) + turned, 2 * std::numbers::pi), 1e-9);
}

TEST(DrumObservables, EveryStationIsAnObservableWithItsPosition) {
  const study::StudyConfig c = parse(k_classes);
  const std::vector<std::string> names = observable_names(c);
  ASSERT_EQ(names.size(), 10u);
  EXPECT_EQ(names.front(), "dynamic_angle");
  EXPECT_EQ(names[1], "surface_1");
  EXPECT_EQ(names[7], "surface_7");
  EXPECT_EQ(drum::experiment().observables(c)[1].label, "surface height at x = -0.45 R");
  EXPECT_EQ(describe_observable("surface_12").unit, "mm");
  EXPECT_EQ(describe_observable("surface_12").stored_unit, "m");
  EXPECT_EQ(describe_observable("s_shape").factor, 1e3);
  EXPECT_EQ(drum::experiment().describe("surface_0"), std::nullopt);
  EXPECT_EQ(drum::experiment().lab_observables(c).size(), 8u);
  EXPECT_NE(
      test::message_of<util::UserError>([&] { drum::experiment().default_targets(c); }).find("demsa measure IMAGE"),
      std::string::npos);
}

TEST(DrumPhotograph, TheGeometryFileIsFoundBesideTheImageAndCheckedAtItsLines) {
  test::TempDir tmp;
  test::write_file(tmp / "a.bmp", "");
  EXPECT_EQ(drum::photograph_geometry_file(tmp / "a.bmp"), std::nullopt);
  test::write_file(tmp / "drum.toml", "preset = \"granudrum\"\n");
  EXPECT_EQ(drum::photograph_geometry_file(tmp / "a.bmp"), tmp / "drum.toml");
  test::write_file(tmp / "a.bmp.drum.toml", "radius = 0.05\nrotation = \"counterclockwise\"\nstations = [-0.5, 0.5]\n");
  EXPECT_EQ(drum::photograph_geometry_file(tmp / "a.bmp"), tmp / "a.bmp.drum.toml");
  const drum::PhotographSettings s = drum::read_photograph_settings(tmp / "a.bmp.drum.toml");
  EXPECT_EQ(s.radius_m, 0.05);
  EXPECT_EQ(s.rotation, postprocess::DrumRotation::counterclockwise);
  EXPECT_EQ(s.surface.stations.size(), 2u);
  EXPECT_TRUE(s.spans_diameter);
  const auto refused = [&](const std::string& text) {
    test::write_file(tmp / "bad.toml", text);
    return test::message_of<util::UserError>([&] { drum::read_photograph_settings(tmp / "bad.toml"); });
  };
  const std::string bad = (tmp / "bad.toml").string();
  EXPECT_EQ(refused("radius = 0.042\nradius_mm = 42\n"), bad +
                                                             ":2: unknown key 'radius_mm' (valid: preset, radius, "
                                                             "spans_diameter, centre_col, centre_row, radius_px, "
                                                             "rotation, dark_material, judged_radius, "
                                                             "angle_half_width, stations, threshold)");
  EXPECT_EQ(refused("radius = -1\n"), bad + ":1: radius = -1: must lie in [0.0001, 100]");
  EXPECT_NE(refused("preset = \"granudrum\"\nrotation = \"up\"\n").find(bad + ":2: rotation = up:"), std::string::npos);
  EXPECT_NE(refused("rotation = \"clockwise\"\n").find("give the drum's inner radius"), std::string::npos);
  EXPECT_NE(
      refused("radius = 0.04\ncentre_col = 10\n")
          .find("centre_col, centre_row and radius_px (the drum's centre and inner radius in pixels) go together"),
      std::string::npos);
  EXPECT_NE(refused("radius = 0.04\njudged_radius = 0.5\nangle_half_width = 0.6\n").find("angle_half_width"),
            std::string::npos);
}

}  // namespace
}  // namespace demsa
