// `demsa measure CASE`: a finished case folder of any experiment is measured exactly as `demsa run` measured it (the
// same numbers as its result.json), from the folder alone; a case made with `demsa case` and run by hand too.
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

}  // namespace
}  // namespace demsa
