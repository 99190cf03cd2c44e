// `demsa measure CASE`: a finished case folder of any experiment is measured exactly as `demsa run` measured it (the
// same numbers as its result.json), from the folder alone; a case made with `demsa case` and run by hand too.
// `demsa measure IMAGE`: a drum's photograph is measured under the names of a drum case, with the geometry file
// beside it.
#include "postprocess/image.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>

namespace demsa {
namespace {

namespace fs = std::filesystem;

std::string study(const std::string& experiment) {
  return test::StudyToml{
      .name = "measure-" + experiment,
      .experiment = experiment,
      .samples = 4,  // rsm1 in two parameters has 3 terms: on 3 samples its Q² is not computable
      .tables = experiment == "pile" ? "[pile]\nparticles = 300\n" : "",
      .run = test::fake_liggghts_run_lines() + "parallel = 2\noversubscribe = true\n",
      .analysis = "metamodels = [\"rsm1\"]\nbootstrap = 0\nbase_samples = 64\nsecond_order = false\n"}
      .text();
}

TEST(CliMeasure, ACaseOfAStudyMeasuresAsItsResult) {
  for (const std::string experiment : {"pile", "oedometer"}) {
    test::TempDir tmp;
    test::write_file(tmp / "study.toml", study(experiment));
    const test::CommandResult run =
        test::run_demsa({"run", (tmp / "study.toml").string(), "--dir", (tmp / "s").string()});
    ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
    for (int sample = 0; sample < 3; ++sample) {
      const fs::path folder = tmp / "s" / "cases" / fmt::format("{:06d}", sample);
      const nlohmann::json result = nlohmann::json::parse(test::read_file(folder / "result.json"));
      const test::CommandResult m = test::run_demsa({"measure", folder.string(), "--json"});
      ASSERT_EQ(m.exit_code, 0) << m.out << m.err;
      const nlohmann::json measured = nlohmann::json::parse(m.out);
      EXPECT_EQ(measured["experiment"], experiment);
      EXPECT_EQ(measured["observables"], result["observables"]) << experiment << " sample " << sample;
      for (const auto& [name, value] : measured["observables"].items()) EXPECT_TRUE(measured["units"].contains(name));
    }
  }
}

TEST(CliMeasure, TablePrintsNamesValuesAndStoredUnits) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study("pile"));
  ASSERT_EQ(test::run_demsa({"run", (tmp / "study.toml").string(), "--dir", (tmp / "s").string()}).exit_code, 0);
  const test::CommandResult m = test::run_demsa({"measure", (tmp / "s" / "cases" / "000001").string()});
  ASSERT_EQ(m.exit_code, 0) << m.err;
  EXPECT_NE(m.out.find("(pile)"), std::string::npos) << m.out;
  EXPECT_NE(m.out.find("angle "), std::string::npos) << m.out;
  EXPECT_NE(m.out.find(" m    pile height"), std::string::npos) << m.out;
}

TEST(CliMeasure, AFolderThatIsNoFinishedCaseIsAnInputError) {
  test::TempDir tmp;
  fs::create_directories(tmp / "empty");
  test::CommandResult m = test::run_demsa({"measure", (tmp / "empty").string()});
  EXPECT_EQ(m.exit_code, 2);
  EXPECT_NE(m.err.find("not a case folder (no case.json)"), std::string::npos) << m.err;
  // A case written but not run: its dump is missing, named.
  test::write_file(tmp / "study.toml", study("pile"));
  ASSERT_EQ(
      test::run_demsa({"case", (tmp / "study.toml").string(), "--sample", "0", "-o", (tmp / "c").string()}).exit_code,
      0);
  m = test::run_demsa({"measure", (tmp / "c").string()});
  EXPECT_EQ(m.exit_code, 2) << m.out << m.err;
  EXPECT_NE(m.err.find("pile_final.dump"), std::string::npos) << m.err;
}

TEST(CliMeasure, ACaseThatHoldsNothingToMeasureIsNamed) {
  // A final dump whose one particle has a radius of 1e300 m: "no direction has 3 boundary points ... not a pile",
  // naming neither the case nor its dump.
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study("pile"));
  ASSERT_EQ(test::run_demsa({"run", (tmp / "study.toml").string(), "--dir", (tmp / "s").string()}).exit_code, 0);
  const fs::path folder = tmp / "s" / "cases" / "000000";
  std::string dump = test::read_file(folder / "pile_final.dump");
  const std::size_t row = dump.find('\n', dump.find("ITEM: ATOMS")) + 1;
  dump.replace(row, dump.find('\n', row) - row, "1 1 0.01 0 0.01 1e300 0 0 0");
  test::write_file(folder / "pile_final.dump", dump);
  const test::CommandResult m = test::run_demsa({"measure", folder.string()});
  EXPECT_EQ(m.exit_code, 2) << m.out;
  EXPECT_EQ(m.err.rfind("demsa: error: " + folder.string() + ": ", 0), 0u) << m.err;
}

TEST(CliMeasure, APhotographIsMeasuredUnderTheCasesNamesWithItsBands) {
  // The GranuDrum's MCC at 15 and 45 rpm (examples/drum-mcc/, drum.toml beside them): clockwise, the surface high on
  // the left and steeper at 45 rpm.
  const fs::path examples = fs::path(DEMSA_SOURCE_DIR) / "examples" / "drum-mcc";
  std::map<int, nlohmann::json> measured;
  for (const int rpm : {15, 45}) {
    const test::CommandResult m =
        test::run_demsa({"measure", (examples / fmt::format("granudrum_mcc_{}rpm.bmp", rpm)).string(), "--json"});
    ASSERT_EQ(m.exit_code, 0) << m.out << m.err;
    measured[rpm] = nlohmann::json::parse(m.out);
  }
  const nlohmann::json& slow = measured[15];
  EXPECT_EQ(slow["experiment"], "drum");
  EXPECT_GT(slow["observables"]["dynamic_angle"].get<double>(), 30.0);
  EXPECT_LT(slow["observables"]["dynamic_angle"].get<double>(), 50.0);
  EXPECT_GT(measured[45]["observables"]["dynamic_angle"].get<double>(),
            slow["observables"]["dynamic_angle"].get<double>() + 5.0);
  EXPECT_GT(slow["observables"]["surface_1"].get<double>(), 0.01);    // high on the left [m]
  EXPECT_LT(slow["observables"]["surface_5"].get<double>(), -0.005);  // low on the right
  // drum.toml's stations are the example studies' five, so that surface_K names the same place in both.
  EXPECT_FALSE(slow["observables"].contains("surface_6")) << slow.dump();
  EXPECT_EQ(slow["units"]["surface_1"], "m");
  EXPECT_EQ(slow["units"]["dynamic_angle"], "°");
  EXPECT_GT(slow["uncertainty"]["dynamic_angle"].get<double>(), 0.0);
  EXPECT_GT(slow["uncertainty"]["surface_4"].get<double>(), 0.0);
  EXPECT_NEAR(slow["observables"]["fill_fraction"].get<double>(), 0.5, 0.1);
  // The table prints each value with its band.
  const test::CommandResult table = test::run_demsa({"measure", (examples / "granudrum_mcc_15rpm.bmp").string()});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("dynamic_angle"), std::string::npos);
  EXPECT_NE(table.out.find("± "), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("drum.toml"), std::string::npos) << table.out;
}

TEST(CliMeasure, APhotographWithoutOrWithABadGeometryFileIsAnInputError) {
  test::TempDir tmp;
  const fs::path image = tmp / "photo.bmp";
  fs::copy_file(fs::path(DEMSA_SOURCE_DIR) / "examples" / "drum-mcc" / "granudrum_mcc_15rpm.bmp", image);
  const test::CommandResult none = test::run_demsa({"measure", image.string()});
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find(image.string() + ": no geometry for this photograph"), std::string::npos) << none.err;
  test::write_file(tmp / "photo.bmp.drum.toml", "preset = \"granudrum\"\nrotation = \"sideways\"\n");
  const test::CommandResult bad = test::run_demsa({"measure", image.string()});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find((tmp / "photo.bmp.drum.toml").string() + ":2: rotation = sideways"), std::string::npos)
      << bad.err;
  test::write_file(tmp / "notes.txt", "x");
  const test::CommandResult other = test::run_demsa({"measure", (tmp / "notes.txt").string()});
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_NE(other.err.find("no experiment measures files of this kind"), std::string::npos) << other.err;
}

/// A GranuDrum-like photograph (406 px spanning the drum) of a bed under a straight surface through the centre at
/// `degrees`, dark material on light, high on the left when `left_high`.
void write_photograph(const fs::path& file, double degrees, bool left_high) {
  postprocess::GreyImage image;
  image.width = image.height = 406;
  image.pixels.assign(406 * 406, 1.0f);
  const double slope = std::tan(degrees * 3.141592653589793 / 180) * (left_high ? -1 : 1);
  for (int row = 0; row < 406; ++row)
    for (int col = 0; col < 406; ++col) {
      const double x = col + 0.5 - 203, y = 203 - row - 0.5;
      if (x * x + y * y < 203.0 * 203.0) image.at(col, row) = y < slope * x ? 0.1f : 0.95f;
    }
  postprocess::write_grey_png(file, image);
}

TEST(CliMeasure, APhotographThatContradictsItsGeometryFileIsRefusedNamingTheFile) {
  test::TempDir tmp;
  const fs::path image = tmp / "photo.png";
  const fs::path geometry = tmp / "photo.png.drum.toml";
  write_photograph(image, 40, false);  // high on the right: a counterclockwise drum
  const auto measure = [&](const std::string& toml) {
    test::write_file(geometry, toml);
    return test::run_demsa({"measure", image.string(), "--json"});
  };
  // Said to turn clockwise, its angle came out as -40° with exit 0.
  test::CommandResult r = measure("preset = \"granudrum\"\nrotation = \"clockwise\"\n");
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find(image.string() + ": the surface falls by 40.0"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("set rotation = \"counterclockwise\""), std::string::npos) << r.err;
  r = measure("preset = \"granudrum\"\nrotation = \"counterclockwise\"\n");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["observables"]["dynamic_angle"].get<double>(), 40.0, 0.1);
  // The radius in pixels alone left the centre at (0, 0), the picture's corner: 1.5° with exit 0.
  r = measure("radius = 0.042\nrotation = \"counterclockwise\"\nradius_px = 203\n");
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find(geometry.string() + ": centre_col, centre_row and radius_px"), std::string::npos) << r.err;
  // Not spanning the diameter, and placed nowhere: exit 3 ("DrumGeometry.radius_px = 0").
  r = measure("radius = 0.042\nspans_diameter = false\n");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find(geometry.string() + ":2: spans_diameter = false: give the drum's centre"), std::string::npos)
      << r.err;
  // A drum larger than the picture: its fill was measured as 0.13 for 0.50, the picture's edge taken for a surface.
  r = measure("radius = 0.042\nrotation = \"counterclockwise\"\ncentre_col = 203\ncentre_row = 203\nradius_px = 400\n");
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find(image.string() + ": the drum (centre at column 203, row 203, radius 400 px) reaches beyond"),
            std::string::npos)
      << r.err;
  // A picture without two grey levels: the message names the file.
  postprocess::GreyImage grey;
  grey.width = grey.height = 406;
  grey.pixels.assign(406 * 406, 0.5f);
  postprocess::write_grey_png(image, grey);
  r = measure("preset = \"granudrum\"\n");
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find(image.string() + ": the photograph shows one grey level"), std::string::npos) << r.err;
}

TEST(CliMeasure, AnOverlayThatWouldOverwriteAnInputIsRefusedBeforeMeasuring) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", test::StudyToml{.name = "overlay",
                                                       .experiment = "drum",
                                                       .samples = 4,
                                                       .parameters = "mu_pp = { low = 0.4, high = 0.9 }\n",
                                                       .tables = "[drum]\npreset = \"granudrum\"\ncoarse_grain = 3\n",
                                                       .run = test::fake_liggghts_run_lines(),
                                                       .analysis = "metamodels = [\"rsm1\"]\nbootstrap = 0\n"}
                                           .text());
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult run =
      test::run_demsa({"run", (tmp / "study.toml").string(), "--dir", (tmp / "s").string(), "--quiet", "--no-analyze"});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const fs::path folder = tmp / "s" / "cases" / "000000";
  const fs::path photo = tmp / "photo.png";
  write_photograph(photo, 40, true);
  test::write_file(tmp / "drum.toml", "preset = \"granudrum\"\n");
  const auto overlay = [&](const fs::path& picture) {
    return test::run_demsa({"measure", folder.string(), "--photograph", photo.string(), "--overlay", picture.string()});
  };
  const std::string photo_bytes = test::read_file(photo), study_bytes = test::read_file(tmp / "study.toml");
  const std::string occupancy = test::read_file(folder / "occupancy.png");
  // Each was overwritten with exit 0: the photograph, the case's own side view, the study file.
  test::CommandResult r = overlay(photo);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--overlay " + photo.string() + ": is the photograph itself"), std::string::npos) << r.err;
  r = overlay(folder / "occupancy.png");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("is the case's own occupancy.png"), std::string::npos) << r.err;
  r = overlay(tmp / "study.toml");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("exists and is not a PNG"), std::string::npos) << r.err;
  EXPECT_EQ(test::read_file(photo), photo_bytes);
  EXPECT_EQ(test::read_file(folder / "occupancy.png"), occupancy);
  EXPECT_EQ(test::read_file(tmp / "study.toml"), study_bytes);
  // A folder that does not exist, or a folder as the file: exit 3 after the work, now 2 before it.
  r = overlay(tmp / "missing" / "o.png");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("its folder " + (tmp / "missing").string() + " does not exist"), std::string::npos) << r.err;
  r = overlay(tmp.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("is a folder"), std::string::npos) << r.err;
  // A new file, and the same file again (a PNG written before), are written.
  EXPECT_EQ(overlay(tmp / "o.png").exit_code, 0);
  r = overlay(tmp / "o.png");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // `report --photograph` with a file that is no photograph wrote the report without the comparison (and without the
  // case's own figures) with exit 0 and a note.
  ASSERT_EQ(test::run_demsa({"analyze", (tmp / "s").string()}).exit_code, 0)
      << test::run_demsa({"analyze", (tmp / "s").string()}).err;
  test::write_file(tmp / "notes.png", "not a picture\n");
  r = test::run_demsa({"report", (tmp / "s").string(), "--photograph", (tmp / "notes.png").string(), "--no-html"});
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("--photograph " + (tmp / "notes.png").string() + ": against sample "), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("not a BMP or PNG image"), std::string::npos) << r.err;
  // A FIFO named as the case: named as one, not "no such case folder".
  ASSERT_EQ(::mkfifo((tmp / "fifo").c_str(), 0600), 0);
  r = test::run_demsa({"measure", (tmp / "fifo").string(), "--photograph", photo.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find((tmp / "fifo").string() + ": a FIFO"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace demsa
