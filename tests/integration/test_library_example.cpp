// The second front end (examples/library_front_end.cpp): a study's analysis, a calibration and a prediction through
// the libraries alone give what the study's known observable says: the angle 22 + 14 u2 + 5 u1² + sin(6 u1 u2) of
// the unit-cube point (u1, u2) of (mu_pp, mu_r_pp).
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/csv.hpp"
#include "support/synthetic_study.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

using namespace demsa::util;
using namespace demsa::study;

namespace demsa::test {
namespace {

namespace fs = std::filesystem;

double angle_at(double u1, double u2) { return 22.0 + 14.0 * u2 + 5.0 * u1 * u1 + std::sin(6.0 * u1 * u2); }

TEST(LibraryExample, AnalysisCalibrationAndPredictionWithoutTheCommandLine) {
  TempDir tmp;
  const fs::path dir = tmp / "study";
  const StudyToml toml{.samples = 40,
                       .analysis = "metamodels = [\"rsm2\", \"gp\"]\nbootstrap = 0\nbase_samples = 64\n"};
  SyntheticStudy study = start_synthetic_study(dir, toml.text(), 5);
  for (const SampleRow& row : study.samples) {
    const long run = study.store.add_run(row.sample, 1);
    RunOutcome outcome;
    outcome.exit_code = 0;
    study.store.record_done(run, outcome, {{"angle", angle_at(row.unit[0], row.unit[1])}});
  }
  // Three points in physical units (mu_pp in [0.7, 1.9], mu_r_pp in [0.05, 0.5]), at known unit-cube points.
  const double u[3][2] = {{0.25, 0.5}, {0.5, 0.25}, {0.75, 0.75}};
  std::string points = "mu_pp,mu_r_pp\n";
  for (const auto& p : u) points += fmt::format("{},{}\n", 0.7 + 1.2 * p[0], 0.05 + 0.45 * p[1]);
  write_file(tmp / "points.csv", points);

  const fs::path example = fs::path(DEMSA_BINARY).parent_path().parent_path() / "examples" / "demsa_library_example";
  const CommandResult r = run_command({example.string(), dir.string(), "30", (tmp / "points.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("analysed angle: 40 samples, 2 metamodels"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir / "analysis" / "analysis.json"));

  // The calibration reaches the target within the metamodel's error.
  const std::size_t at = r.out.find("angle at the optimum ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const double reached = std::stod(r.out.substr(at + 21));
  EXPECT_NEAR(reached, 30.0, 0.05) << r.out;

  // The prediction follows the known angle at the three points.
  const std::size_t csv = r.out.find("mu_pp,mu_r_pp,angle\n");
  ASSERT_NE(csv, std::string::npos) << r.out;
  const CsvTable predicted = parse_csv(r.out.substr(csv), "prediction");
  ASSERT_EQ(predicted.rows(), 3);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(predicted.values(i, 2), angle_at(u[i][0], u[i][1]), 0.3) << "point " << i << "\n" << r.out;
}

}  // namespace
}  // namespace demsa::test
