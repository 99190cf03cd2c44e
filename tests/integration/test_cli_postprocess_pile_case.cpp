// `demsa postprocess pile CASE` measures a pile with the pedestal and the measurement settings its case.json records
// (written by `demsa case`), options override them, and a case.json without the pedestal is an error. `demsa compare`
// measures each pile the same way: on its own pedestal, and without the base layer of a rough-base case.
#include "support/test_support.hpp"
#include "tests/postprocess/synthetic_cone.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

namespace demsa::test {
namespace {

/// A 30° synthetic cone whose flank meets a pedestal of radius 30 mm and top at z = 12 mm 28 mm from the axis.
postprocess::Particles small_pedestal_cone() {
  SyntheticConeOptions cone;
  cone.angle_deg = 30.0;
  cone.base_radius = 0.028;
  cone.pedestal_radius = 0.030;
  cone.pedestal_top = 0.012;
  cone.cap_radius = 0.004;
  return make_synthetic_cone(cone);
}

/// h_P of the cone above a pedestal top at z = top: the highest particle top.
double height_above(const postprocess::Particles& p, double top) {
  double highest = 0.0;
  for (std::size_t j = 0; j < p.size(); ++j) highest = std::max(highest, p.z[j] + p.radius[j]);
  return highest - top;
}

/// `demsa case` of a pile study on that pedestal (8 levels, the robust estimator) with the cone as its final dump.
void write_small_pedestal_case(const TempDir& tmp, const postprocess::Particles& cone) {
  StudyToml study;
  study.tables =
      "[pile]\nparticles = 300\npedestal_radius = 0.03\npedestal_height = 0.012\nlevels = 8\n"
      "angle_estimator = \"robust\"\n";
  write_file(tmp / "study.toml", study.text());
  const CommandResult c =
      run_demsa({"case", (tmp / "study.toml").string(), "--sample", "0", "-o", (tmp / "case").string()});
  ASSERT_EQ(c.exit_code, 0) << c.err;
  write_file(tmp / "case" / "pile_final.dump", synthetic_dump_text(cone));
}

TEST(CliPostprocessPileCase, MeasuresWithTheCasesOwnPedestal) {
  TempDir tmp;
  const postprocess::Particles cone = small_pedestal_cone();
  write_small_pedestal_case(tmp, cone);
  const CommandResult r = run_demsa({"postprocess", "pile", (tmp / "case").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_DOUBLE_EQ(j["options"]["pedestal_radius_m"].get<double>(), 0.03);
  EXPECT_DOUBLE_EQ(j["options"]["pedestal_top_m"].get<double>(), 0.012);
  EXPECT_EQ(j["options"]["levels"].get<int>(), 8);
  EXPECT_EQ(j["options"]["estimator"], "robust");
  // ... with its own band of levels (postprocess::k_robust_level_low/high), as `demsa run` measured it: on this
  // 16 mm cone its lowest level is 1.5 r_max above the pedestal (postprocess::k_robust_floor_radii), above 0.25 h_P.
  double r_max = 0.0;
  for (std::size_t k = 0; k < cone.size(); ++k)
    if (std::hypot(cone.x[k], cone.y[k]) <= 0.03 && cone.z[k] >= 0.012) r_max = std::max(r_max, cone.radius[k]);
  const double h = height_above(cone, 0.012);
  ASSERT_GT(1.5 * r_max / h, 0.25);
  EXPECT_NEAR(j["options"]["level_low"].get<double>(), 1.5 * r_max / h, 1e-9);
  EXPECT_DOUBLE_EQ(j["options"]["level_high"].get<double>(), 0.8);
  EXPECT_NE(j["case_json"].get<std::string>().find("case.json"), std::string::npos);
  EXPECT_NEAR(j["pile_height_m"].get<double>(), height_above(cone, 0.012), 1e-9);
  EXPECT_NEAR(j["angle_deg"].get<double>(), 30.0, 1.0);

  // The dump path itself finds the case.json beside it; the text names the pedestal and where it came from.
  const CommandResult text = run_demsa({"postprocess", "pile", (tmp / "case" / "pile_final.dump").string()});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("radius 0.03 m, top at z = 0.012 m"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("estimator              robust"), std::string::npos) << text.out;
}

TEST(CliCompare, EachPileIsMeasuredOnItsOwnCasesPedestal) {
  TempDir tmp;
  const postprocess::Particles cone = small_pedestal_cone();
  write_small_pedestal_case(tmp, cone);
  std::filesystem::copy(tmp / "case", tmp / "same", std::filesystem::copy_options::recursive);
  const CommandResult r = run_demsa({"compare", (tmp / "case").string(), (tmp / "same").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const nlohmann::json pile = nlohmann::json::parse(r.out)["comparisons"][0]["pile"];
  for (const char* side : {"pedestal_a", "pedestal_b"}) {
    ASSERT_TRUE(pile.contains(side)) << pile.dump();
    EXPECT_DOUBLE_EQ(pile.at(side).at("radius_m").get<double>(), 0.03) << pile.dump();
    EXPECT_DOUBLE_EQ(pile.at(side).at("top_m").get<double>(), 0.012) << pile.dump();
  }
  EXPECT_NEAR(pile["angle_a_deg"].get<double>(), 30.0, 1.0);
  EXPECT_NEAR(pile["height_a_m"].get<double>(), height_above(cone, 0.012), 1e-9);
  // A pedestal given on the command line wins over the cases'.
  const CommandResult given =
      run_demsa({"compare", (tmp / "case").string(), (tmp / "same").string(), "--json", "--pedestal-top", "0.011"});
  ASSERT_EQ(given.exit_code, 0) << given.err;
  EXPECT_DOUBLE_EQ(
      nlohmann::json::parse(given.out).at("comparisons").at(0).at("pile").at("pedestal_b").at("top_m").get<double>(),
      0.011);
}

/// A rough-base pile case (`[pile] base = "particles"`) in tmp/NAME whose final dump holds its base layer (ids
/// 1..N as its case.json records, tops at the layer's recorded mean top) under a 30° cone standing on that top, every
/// pile particle moved by `shift` along x. Returns N.
long write_rough_base_case(const TempDir& tmp, const std::string& name, double shift) {
  StudyToml study;
  study.tables = "[pile]\nparticles = 300\npedestal_radius = 0.03\npedestal_height = 0.012\nbase = \"particles\"\n";
  write_file(tmp / "study.toml", study.text());
  const CommandResult c =
      run_demsa({"case", (tmp / "study.toml").string(), "--sample", "0", "-o", (tmp / name).string()});
  EXPECT_EQ(c.exit_code, 0) << c.err;
  const nlohmann::json base = nlohmann::json::parse(read_file(tmp / name / "case.json")).at("pile").at("base");
  const long n = base.at("particles").get<long>();
  const double top = base.at("top_m").get<double>();
  postprocess::Particles dump;
  for (long k = 0; k < n; ++k) {  // a frozen layer on the pedestal, spread over it on a sunflower spiral
    const double rho = 0.028 * std::sqrt((static_cast<double>(k) + 0.5) / static_cast<double>(n));
    const double phi = 2.399963 * static_cast<double>(k), r = 1.5e-3;
    dump.id.push_back(k + 1);
    dump.type.push_back(1);
    dump.x.push_back(rho * std::cos(phi));
    dump.y.push_back(rho * std::sin(phi));
    dump.z.push_back(top - r);
    dump.radius.push_back(r);
  }
  SyntheticConeOptions options;
  options.angle_deg = 30.0;
  options.base_radius = 0.028;
  options.pedestal_radius = 0.030;
  options.pedestal_top = top;
  options.cap_radius = 0.004;
  const postprocess::Particles cone = make_synthetic_cone(options);
  for (std::size_t j = 0; j < cone.size(); ++j) {
    dump.id.push_back(n + cone.id[j]);
    dump.type.push_back(cone.type[j]);
    dump.x.push_back(cone.x[j] + shift);
    dump.y.push_back(cone.y[j]);
    dump.z.push_back(cone.z[j]);
    dump.radius.push_back(cone.radius[j]);
  }
  write_file(tmp / name / "pile_final.dump", synthetic_dump_text(dump));
  return n;
}

TEST(CliCompare, RoughBasePilesAreComparedWithoutTheirBaseLayers) {
  TempDir tmp;
  const long base = write_rough_base_case(tmp, "a", 0.0);
  ASSERT_GT(base, 0);
  write_rough_base_case(tmp, "b", 1e-4);
  const CommandResult r =
      run_demsa({"compare", (tmp / "a").string(), (tmp / "b").string(), "--json", "--tol-pos", "1e-3"});
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const nlohmann::json c = nlohmann::json::parse(r.out)["comparisons"][0];
  // Measured as `demsa postprocess pile CASE` measures it: the pile's particles only, every one of them moved by
  // 0.1 mm (the layer's would count as the pile's and dilute the RMS).
  const nlohmann::json measured =
      nlohmann::json::parse(run_demsa({"postprocess", "pile", (tmp / "a").string(), "--json"}).out);
  EXPECT_EQ(c["particles_a"].get<std::size_t>(), measured["particles_total"].get<std::size_t>()) << c.dump();
  EXPECT_NEAR(c["rms_displacement_m"].get<double>(), 1e-4, 1e-9) << c.dump();
  EXPECT_EQ(c["pile"]["pedestal_a"]["base_particles"].get<long>(), base) << c.dump();
  EXPECT_DOUBLE_EQ(c["pile"]["angle_a_deg"].get<double>(), measured["angle_deg"].get<double>());
  EXPECT_DOUBLE_EQ(c["pile"]["height_a_m"].get<double>(), measured["pile_height_m"].get<double>());
  const CommandResult text = run_demsa({"compare", (tmp / "a").string(), (tmp / "b").string(), "--tol-pos", "1e-3"});
  EXPECT_NE(text.out.find(fmt::format("base layers          {} vs {} particles, left out", base, base)),
            std::string::npos)
      << text.out;
}

TEST(CliPostprocessPileCase, OptionsOverrideTheCase) {
  TempDir tmp;
  const postprocess::Particles cone = small_pedestal_cone();
  write_small_pedestal_case(tmp, cone);
  const CommandResult r = run_demsa({"postprocess", "pile", (tmp / "case").string(), "--json", "--pedestal-radius",
                                     "0.05", "--pedestal-top", "0.005", "--levels", "10", "--estimator", "paper"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_DOUBLE_EQ(j["options"]["pedestal_radius_m"].get<double>(), 0.05);
  EXPECT_DOUBLE_EQ(j["options"]["pedestal_top_m"].get<double>(), 0.005);
  EXPECT_EQ(j["options"]["levels"].get<int>(), 10);
  EXPECT_EQ(j["options"]["estimator"], "paper");
  EXPECT_DOUBLE_EQ(j["options"]["level_low"].get<double>(), 0.2);
  // Levels given on the command line hold for the robust estimator too.
  const CommandResult robust =
      run_demsa({"postprocess", "pile", (tmp / "case").string(), "--json", "--level-low", "0.3"});
  ASSERT_EQ(robust.exit_code, 0) << robust.err;
  const nlohmann::json jr = nlohmann::json::parse(robust.out);
  EXPECT_EQ(jr["options"]["estimator"], "robust");
  EXPECT_DOUBLE_EQ(jr["options"]["level_low"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(jr["options"]["level_high"].get<double>(), 0.75);
  // Measured from the wrong pedestal top, the pile is 7 mm higher than it is.
  EXPECT_NEAR(j["pile_height_m"].get<double>(), height_above(cone, 0.005), 1e-9);
}

TEST(CliPostprocessPileCase, CaseJsonWithoutPedestalIsAnError) {
  TempDir tmp;
  write_file(tmp / "pile_final.dump", synthetic_dump_text(small_pedestal_cone()));
  write_file(tmp / "case.json", R"({"experiment": "pile", "pile": {"settle_steps": 1000}})");
  const CommandResult r = run_demsa({"postprocess", "pile", tmp.path().string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("case.json: records no pile.pedestal_radius_m (a case written by an older demsa): give the "
                       "pile's pedestal as --pedestal-radius and --pedestal-top"),
            std::string::npos)
      << r.err;
  const CommandResult given =
      run_demsa({"postprocess", "pile", tmp.path().string(), "--pedestal-radius", "0.03", "--pedestal-top", "0.012"});
  EXPECT_EQ(given.exit_code, 0) << given.err;

  write_file(tmp / "case.json", R"({"experiment": "pile", "pile": {"pedestal_radius_m": "wide"}})");
  const CommandResult typed = run_demsa({"postprocess", "pile", tmp.path().string()});
  EXPECT_EQ(typed.exit_code, 2);
  EXPECT_NE(typed.err.find("case.json: pile.pedestal_radius_m = \"wide\": not a finite number"), std::string::npos)
      << typed.err;

  write_file(tmp / "case.json", R"({"experiment": "oedometer"})");
  const CommandResult oedometer = run_demsa({"postprocess", "pile", tmp.path().string()});
  EXPECT_EQ(oedometer.exit_code, 2);
  EXPECT_NE(oedometer.err.find("case.json: experiment = \"oedometer\": not a pile case"), std::string::npos)
      << oedometer.err;
}

TEST(CliPostprocessPileCase, DumpWithoutCaseJsonWarnsAndUsesTheOptions) {
  TempDir tmp;
  write_file(tmp / "pile_final.dump", read_file(data_path("postprocess/liggghts_pile/pile_final.dump")));
  const CommandResult r = run_demsa({"postprocess", "pile", tmp.path().string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("no case.json beside the dump: measured on the pedestal of the options (radius 0.05 m, top at "
                       "z = 0.005 m)"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(nlohmann::json::parse(r.out)["case_json"].is_null());
  const CommandResult given =
      run_demsa({"postprocess", "pile", tmp.path().string(), "--pedestal-radius", "0.05", "--pedestal-top", "0.005"});
  ASSERT_EQ(given.exit_code, 0) << given.err;
  EXPECT_EQ(given.err.find("no case.json"), std::string::npos) << given.err;
}

}  // namespace
}  // namespace demsa::test
