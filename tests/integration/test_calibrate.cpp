// `demsa calibrate` and `demsa report` through the real binary, on a synthetic study folder (store written
// directly, no LIGGGHTS): exit statuses, JSON output, error messages, files.
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <random>

using namespace demsa::study;

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

double angle_of(double u1, double u2) { return 21.0 + 12.0 * u2 + 6.0 * u1 * u1; }
double height_of(double u1, double u2) { return 0.025 + 0.008 * u1 + 0.003 * u2; }

void write_study(const fs::path& dir) {
  SyntheticStudy study = start_synthetic_study(
      dir,
      StudyToml{.name = "cli-synthetic",
                .seed = 3,
                .samples = 25,
                .parameters = "mu_pw = { low = 0.4, high = 1.9 }\nmu_r_pw = { low = 0.1, high = 0.5 }\n",
                .analysis = "metamodels = [\"rsm2\"]\nbootstrap = 5\nbase_samples = 256\n"}
          .text(),
      2);
  record_every_sample_done(study, [](const SampleRow& row) -> std::map<std::string, double> {
    return {{"angle", angle_of(row.unit[0], row.unit[1])}, {"pile_height", height_of(row.unit[0], row.unit[1])}};
  });
}

TEST(CalibrateCli, JsonOutputRecoversTheOptimum) {
  TempDir dir;
  write_study(dir / "study");
  const CommandResult r =
      run_demsa({"calibrate", (dir / "study").string(), "--target", fmt::format("angle={:.12g}", angle_of(0.7, 0.2)),
                 "--target", fmt::format("pile_height={:.12g}", height_of(0.7, 0.2)), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j.at("parameters").at(0).at("unit").get<double>(), 0.7, 0.02);
  EXPECT_NEAR(j.at("parameters").at(1).at("unit").get<double>(), 0.2, 0.02);
  EXPECT_NEAR(j.at("parameters").at(0).at("value").get<double>(), 0.4 + 1.5 * 0.7, 0.02 * 1.5);
  EXPECT_EQ(j.at("targets").at(0).at("model").get<std::string>(), "rsm2");
  EXPECT_TRUE(fs::exists(dir / "study" / "analysis" / "calibration.json"));
}

TEST(CalibrateCli, TextOutputNamesOptimumAndMisfit) {
  TempDir dir;
  write_study(dir / "study");
  const CommandResult r = run_demsa({"calibrate", (dir / "study").string(), "--target", "angle=30"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("optimum:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("mu_pw"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("misfit J = "), std::string::npos) << r.out;
}

TEST(CalibrateCli, ATargetTheStudyCannotProduceFailsTheCheck) {
  TempDir dir;
  write_study(dir / "study");
  // The study's angles span about 21 to 39°.
  const CommandResult r = run_demsa({"calibrate", (dir / "study").string(), "--target", "angle=60", "--json"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(j.at("checks").at("passed").get<bool>());
  EXPECT_TRUE(j.at("targets").at(0).at("contradicted").get<bool>());
  EXPECT_NE(r.err.find("check failed: angle = 60 °: the optimum predicts"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("in study cli-synthetic, angle of repose spans"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("60 ° is above it"), std::string::npos) << r.err;
  const nlohmann::json written = nlohmann::json::parse(read_file(dir / "study" / "analysis" / "calibration.json"));
  EXPECT_FALSE(written.at("checks").at("passed").get<bool>());
  const CommandResult text = run_demsa({"calibrate", (dir / "study").string(), "--target", "angle=60"});
  EXPECT_EQ(text.exit_code, 1);
  EXPECT_NE(text.out.find("CHECK FAILED"), std::string::npos) << text.out;
}

TEST(CalibrateCli, UnknownObservableExits2) {
  TempDir dir;
  write_study(dir / "study");
  const CommandResult r = run_demsa({"calibrate", (dir / "study").string(), "--target", "slope=30"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("demsa: error: --target 'slope=30': unknown observable 'slope'"), std::string::npos) << r.err;
}

TEST(CalibrateCli, UnknownAlgorithmExits2) {
  TempDir dir;
  write_study(dir / "study");
  const CommandResult r = run_demsa({"calibrate", (dir / "study").string(), "--global", "simplex"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("simplex"), std::string::npos) << r.err;
}

TEST(ReportCli, WritesReportAndListsItInJson) {
  TempDir dir;
  write_study(dir / "study");
  ASSERT_EQ(run_demsa({"calibrate", (dir / "study").string()}).exit_code, 0);
  const CommandResult r = run_demsa({"report", (dir / "study").string(), "--json", "--width", "800"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(fs::exists(j.at("markdown").get<std::string>()));
  EXPECT_TRUE(fs::exists(j.at("html").get<std::string>()));
  // 2 observables × (bars, LOO, response) + calibration; no case files: one note for the pile figure
  EXPECT_EQ(j.at("images").size(), 7u);
  for (const auto& png : j.at("images")) EXPECT_TRUE(fs::exists(png.get<std::string>())) << png;
  EXPECT_EQ(j.at("notes").size(), 1u);
}

TEST(ReportCli, NotAStudyExits2) {
  TempDir dir;
  const CommandResult r = run_demsa({"report", dir.path().string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("not a study folder"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace demsa::test
