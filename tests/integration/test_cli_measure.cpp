// `demsa measure CASE`: a finished case folder of any experiment is measured exactly as `demsa run` measured it (the
// same numbers as its result.json), from the folder alone; a case made with `demsa case` and run by hand too.
// `demsa measure IMAGE`: a drum's photograph is measured under the names of a drum case, with the geometry file
// beside it.
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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
      .samples = 3,
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
  EXPECT_GT(slow["observables"]["surface_1"].get<double>(), 0.01);   // high on the left [m]
  EXPECT_LT(slow["observables"]["surface_7"].get<double>(), -0.01);  // low on the right
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

}  // namespace
}  // namespace demsa
