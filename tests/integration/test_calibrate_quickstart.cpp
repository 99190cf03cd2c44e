// `demsa calibrate` on the quickstart's own LIGGGHTS output (tests/data/quickstart/, provenance in its README): the
// study folder is rebuilt from examples/quickstart.toml, its design drawn as `demsa run` draws it and checked against
// the recorded one, and the measured observables of the real run stored; then the analysis and the posterior for a
// target at the median of the measured angles ± 1°. What the angle does not depend on keeps its prior width; the
// two rolling frictions that it does depend on trade off along one ridge.
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/csv.hpp"
#include "sobol/posterior.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace demsa::test {
namespace {
namespace fs = std::filesystem;
using namespace demsa::study;
using namespace demsa::experiments;

/// Builds DIR (study.toml, study.db) from the quickstart's study file and the recorded observables of its run.
/// Returns the measured angles.
std::vector<double> rebuild_quickstart(const fs::path& dir) {
  fs::create_directories(dir);
  fs::copy_file(fs::path(DEMSA_SOURCE_DIR) / "examples" / "quickstart.toml", dir / "study.toml");
  const StudyConfig config = load_study(dir / "study.toml");
  const std::vector<SampleRow> design = exec::draw_design(config);
  // The angles in time (`angle_series@T`) are empty past a case's stop: they are left out, as the analysis does.
  util::CsvReadOptions numeric;
  numeric.numeric_columns = {"sample"};
  for (const std::string& c : util::read_csv(data_path("quickstart/observables.csv"), numeric).columns)
    if (!c.starts_with("angle_series@")) numeric.numeric_columns.push_back(c);
  const util::CsvTable recorded = util::read_csv(data_path("quickstart/observables.csv"), numeric);
  EXPECT_EQ(recorded.rows(), static_cast<int>(design.size()));

  Store store((dir / "study.db").string());
  store.initialize(design_hash(config), config.name, design);
  std::vector<double> angles;
  for (int r = 0; r < recorded.rows(); ++r) {
    const int sample = static_cast<int>(recorded.values(r, recorded.column_index("sample")));
    const auto row = std::find_if(design.begin(), design.end(), [&](const SampleRow& s) { return s.sample == sample; });
    EXPECT_NE(row, design.end()) << "sample " << sample;
    if (row == design.end()) continue;
    // The recorded run is of this very design: the study file (or the design code) has not changed since
    // (observables.csv holds 10 significant digits).
    for (std::size_t k = 0; k < config.parameters.size(); ++k)
      EXPECT_NEAR(recorded.values(r, recorded.column_index("u_" + config.parameters[k].name)), row->unit[k], 1e-9)
          << "sample " << sample << ", " << config.parameters[k].name;
    // observables.csv: the sample, the unit and the physical values, then every observable the store held.
    std::map<std::string, double> values;
    for (std::size_t c = 1 + 2 * config.parameters.size(); c < recorded.columns.size(); ++c)
      if (!recorded.columns[c].starts_with("angle_series@"))
        values[recorded.columns[c]] = recorded.values(r, static_cast<Eigen::Index>(c));
    angles.push_back(values.at("angle"));
    RunOutcome done;
    done.exit_code = 0;
    store.record_done(store.add_run(sample, 1), done, values);
  }
  return angles;
}

TEST(CalibrateQuickstart, TheInertParametersKeepTheirPriorAndTheRollingFrictionsShareOneRidge) {
  TempDir dir;
  const fs::path study = dir / "quickstart";
  const std::vector<double> angles = rebuild_quickstart(study);
  ASSERT_EQ(angles.size(), 20u);
  const double target = sobol::quantile(angles, 0.5);  // the median

  const CommandResult analyzed = run_demsa({"analyze", study.string()});
  ASSERT_EQ(analyzed.exit_code, 0) << analyzed.err;
  const CommandResult r = run_demsa(
      {"calibrate", study.string(), "--target", fmt::format("angle={:.3f}±1", target), "--json", "--no-plots"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j.at("diagnostics").at("converged").get<bool>()) << j.at("diagnostics").dump();

  // The total indices of the metamodel the posterior uses for the angle.
  const std::string model = j.at("targets").at(0).at("model").get<std::string>();
  const nlohmann::json sobol =
      nlohmann::json::parse(read_file(study / "analysis" / fmt::format("sobol_{}.json", model))).at("angle").at("ST");
  const nlohmann::json& parameters = j.at("parameters");
  std::size_t dominant = 0, narrowest = 0, pw = parameters.size();
  int inert = 0;
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const std::string name = parameters[k].at("name").get<std::string>();
    const double st = sobol.at(name).at("value").get<double>();
    const double width = parameters[k].at("width_ratio").get<double>();
    if (st < 0.02) {
      ++inert;
      EXPECT_GE(width, 0.8) << name << ": ST " << st << " (" << model << ")";
    }
    if (st > sobol.at(parameters[dominant].at("name").get<std::string>()).at("value").get<double>()) dominant = k;
    if (width < parameters[narrowest].at("width_ratio").get<double>()) narrowest = k;
    if (name == "mu_r_pw") pw = k;
  }
  EXPECT_GE(inert, 3) << "E, nu and mu_pp do not move the quickstart's angle";
  ASSERT_EQ(parameters[dominant].at("name").get<std::string>(), "mu_r_pp") << "as in the paper's piles (Table 4)";
  // The angle narrows the dominant parameter most, but one angle pins only a combination of the two rolling
  // frictions: at low mu_r_pp the particle-wall one holds the pile's base, so they trade off along a ridge (a
  // negative correlation) and mu_r_pp keeps more than half its prior width (0.76 when this was written).
  EXPECT_EQ(narrowest, dominant) << parameters.dump();
  EXPECT_LT(parameters[dominant].at("width_ratio").get<double>(), 0.85);
  ASSERT_LT(pw, parameters.size());
  EXPECT_LT(j.at("correlation").at(dominant).at(pw).get<double>(), -0.3) << j.at("correlation").dump();
}

}  // namespace
}  // namespace demsa::test
