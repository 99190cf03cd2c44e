// The laboratory targets of examples/calibration/lab/ (docs/tutorials/lab-to-parameters.md) as `demsa calibrate
// --target-file` reads them: every file parses, and the calibration's targets carry the file's mean and sd.
#include "orchestrator/study/store.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <string>

using namespace demsa::study;

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

TEST(LabTargets, EveryExampleTargetFileCalibratesAStudy) {
  TempDir dir;
  // A pile study without LIGGGHTS whose angle spans 10-55° over mu_r_pp, so that every example's value is reachable.
  SyntheticStudy study = start_synthetic_study(
      dir / "pile",
      StudyToml{.name = "pile",
                .seed = 5,
                .samples = 16,
                .parameters = "mu_r_pp = { low = 0.05, high = 0.5 }\nmu_r_pw = { low = 0.05, high = 0.5 }\n",
                .analysis = "metamodels = [\"rsm2\"]\nbootstrap = 5\nbase_samples = 256\n"}
          .text(),
      2);
  record_every_sample_done(study, [](const SampleRow& row) -> std::map<std::string, double> {
    return {{"angle", 10.0 + 45.0 * row.unit[0] + 1.0 * row.unit[1]}};
  });
  const fs::path lab = fs::path(DEMSA_SOURCE_DIR) / "examples" / "calibration" / "lab";
  int files = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(lab)) {
    if (entry.path().extension() != ".csv") continue;
    ++files;
    std::ifstream in(entry.path());
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    ASSERT_EQ(header, "mean,sd") << entry.path();
    const double mean = std::stod(row.substr(0, row.find(',')));
    const double sd = std::stod(row.substr(row.find(',') + 1));
    const CommandResult r =
        run_demsa({"calibrate", (dir / "pile").string(), "--target-file", "angle=" + entry.path().string(),
                   "--no-plots", "--json", "--out", (dir / entry.path().stem()).string()});
    ASSERT_EQ(r.exit_code, 0) << entry.path() << "\n" << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j.at("targets").size(), 1u) << entry.path();
    EXPECT_EQ(j.at("targets").at(0).at("name").get<std::string>(), "angle");
    EXPECT_DOUBLE_EQ(j.at("targets").at(0).at("value").get<double>(), mean) << entry.path();
    EXPECT_DOUBLE_EQ(j.at("targets").at(0).at("sd").get<double>(), sd) << entry.path();
  }
  EXPECT_EQ(files, 4) << lab;
}

}  // namespace
}  // namespace demsa::test
