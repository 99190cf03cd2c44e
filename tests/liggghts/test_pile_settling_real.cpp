// Real LIGGGHTS piles for the settling criterion and the removal of particles that fall off the pedestal
// ([pile] settle_speed, settle_quantile, settle_window, remove_fallen): a pile of the quickstart's size settles by the
// criterion; a pile with little particle-wall rolling friction loses particles off the pedestal and is not failed; a
// study whose time cap is too short is flagged unsettled by `demsa status`.
#include "orchestrator/exec/failure.hpp"
#include "orchestrator/exec/measure.hpp"
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/observables.hpp"
#include "postprocess/dump.hpp"

#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>

namespace demsa {

using namespace demsa::study;
using namespace demsa::experiments;
using namespace demsa::exec;
namespace {

namespace fs = std::filesystem;

/// Writes one case of `study` at the parameter values `set` into `dir` and runs it with its run.sh.
void write_and_run(const fs::path& study, const std::string& set, const fs::path& dir) {
  const test::CommandResult w = test::run_demsa({"case", study.string(), "--set", set, "-o", dir.string()});
  ASSERT_EQ(w.exit_code, 0) << w.out << w.err;
  const test::CommandResult r = test::run_command({(dir / "run.sh").string()}, dir.parent_path());
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err << test::read_file(dir / "screen.txt");
}

CaseExit clean_exit() {
  CaseExit exit;
  exit.exit_code = 0;
  return exit;
}

FailureOptions strict_options(long particles) {
  // A pile study: its experiment names the final dump and the particles removed on purpose.
  static const StudyConfig pile_study = parse_study(
      "[study]\nname = \"s\"\nexperiment = \"pile\"\n[parameters]\nE = { low = 1e8, high = 1e9 }\n", "s.toml");
  FailureOptions options;
  options.config = &pile_study;
  options.expected_particles = particles;
  options.lost_fraction = 0.01;
  options.kinetic_energy_limit = 1e6;
  return options;
}

// The baseline of the one-at-a-time runs of docs/reference/study-file.md ("Settling and removal") at the quickstart's
// softest E (its range is [1e7, 1e8] Pa): the cheapest of its cases.
const char* k_quickstart_baseline = "E=1e7,nu=0.3,mu_pp=1.3,mu_pw=1.15,e_r=0.4,mu_r_pp=0.275,mu_r_pw=0.275";

}  // namespace

TEST(PileSettlingReal, QuickstartSizePileSettlesByTheCriterion) {
  test::TempDir tmp;
  const fs::path study = fs::path(DEMSA_SOURCE_DIR) / "examples" / "quickstart.toml";
  const fs::path dir = tmp / "case";
  write_and_run(study, k_quickstart_baseline, dir);
  const StudyConfig config = load_study(study);
  const std::optional<pile::PileSettling> settling = pile::read_settling(dir);
  ASSERT_TRUE(settling.has_value());
  EXPECT_TRUE(settling->criterion);
  EXPECT_TRUE(settling->settled) << test::read_file(dir / "pile_settling.txt");
  const std::map<std::string, double> values = measure_case(dir);
  // The pile in time: a snapshot every 0.1 s from the end of the last disc, then the final dump; the settling verdict
  // is the speed criterion's and the angle's drift over the last 0.2 s (at most 1 °/s).
  const std::vector<pile::PileMoment> moments = pile::read_history(dir);
  ASSERT_GE(moments.size(), 3u);
  EXPECT_EQ(moments.front().check, 0);
  EXPECT_EQ(moments.front().time, 0.0);
  const double dt = read_case_json(dir)["dt"].get<double>();
  EXPECT_NEAR(moments.back().time, static_cast<double>(settling->end_step - *settling->start_step) * dt, 1e-9);
  EXPECT_EQ(moments.back().angle, values.at(std::string(pile::k_angle)));
  for (const pile::PileMoment& m : moments) {
    if (m.check >= 0) {
      EXPECT_TRUE(values.count(fmt::format("angle_series@{}", std::stod(fmt::format("{:.9g}", 0.01 * m.check)))))
          << m.check;
    }
    if (m.time >= 0.1) {
      EXPECT_TRUE(std::isfinite(m.angle) && std::isfinite(m.angle_robust)) << m.time;
    }
  }
  EXPECT_FALSE(fs::exists(dir / pile::snapshot_file(0)));  // removed once measured
  const double drift = values.at(std::string(pile::k_angle_drift));
  EXPECT_DOUBLE_EQ(drift, pile::angle_drift(moments, 0.2));
  EXPECT_EQ(values.at(std::string(k_settled)), std::abs(drift) <= 1.0 ? 1.0 : 0.0) << drift;
  // The quickstart's pile overflows its pedestal: particles fell off and were removed, none lost.
  EXPECT_GT(values.at(std::string(pile::k_removed_off_pedestal)), 0.0);
  EXPECT_EQ(classify_case(clean_exit(), dir, strict_options(pile::settings(config).particles)).failure,
            FailureClass::none);
}

TEST(PileSettlingReal, LowWallRollingFrictionPileRemovesParticlesAndIsNotFailed) {
  // 300 particles on the 50 mm pedestal with mu_R,PW = 0.05: particles roll off the pedestal. They are removed once
  // past its rim (below its top, on the mesh; at any height, on the plane), counted, and the case passes a 1 %
  // lost-atom check.
  for (const std::string top : {"mesh", "plane"}) {
    SCOPED_TRACE(top);
    test::TempDir tmp;
    std::string text = test::read_file(test::data_path("cases/tiny_pile.toml"));
    const std::string from = "mu_r_pw = 0.3\n";
    ASSERT_NE(text.find(from), std::string::npos);
    text.replace(text.find(from), from.size(), "mu_r_pw = 0.05\n");
    const std::string settle = "settle_time = 0.35\n";
    ASSERT_NE(text.find(settle), std::string::npos);
    text.replace(text.find(settle), settle.size(), settle + "remove_fallen = true\npedestal_top = \"" + top + "\"\n");

    test::write_file(tmp / "low.toml", text);
    const fs::path dir = tmp / "case";
    write_and_run(tmp / "low.toml", "E=1e8,mu_r_pp=0.275", dir);
    EXPECT_EQ(read_case_json(dir)["pile"]["pedestal_top"].get<std::string>(), top);
    const std::optional<pile::PileSettling> settling = pile::read_settling(dir);
    ASSERT_TRUE(settling.has_value());
    EXPECT_GT(settling->removed, 0);
    const long atoms = static_cast<long>(postprocess::read_particles(dir / "pile_final.dump", 1).size());
    EXPECT_EQ(atoms + settling->removed, 300);  // every particle is in the dump or was removed: none lost
    const FailureReport report = classify_case(clean_exit(), dir, strict_options(300));
    EXPECT_EQ(report.failure, FailureClass::none) << report.message;
    // Nothing removed lies in the dump: no particle centre past the rim below the pedestal top (on the plane, at
    // any height: the last check removed them just before the dump).
    const postprocess::Particles all = postprocess::read_particles(dir / "pile_final.dump", 1);
    for (std::size_t i = 0; i < all.size(); ++i)
      EXPECT_FALSE((top == "plane" || all.z[i] < 0.005) && std::hypot(all.x[i], all.y[i]) > 0.05) << i;
  }
}

TEST(PileSettlingReal, StudyWithATinyTimeCapIsFlaggedUnsettled) {
  test::TempDir tmp;
  const std::string study =
      test::StudyToml{
          .name = "unsettled",
          .samples = 3,
          .parameters = "mu_r_pp = { low = 0.05, high = 0.5 }\n",
          .tables = "[material]\nE = 1e8\n\n[pile]\nparticles = 120\nsettle_time = 0.02\nsettle_speed = 0.02\n",
          .run = "ranks = 1\ntimeout = 600\nretries = 0\n",
          .analysis = "metamodels = [\"rsm1\"]\nbootstrap = 0\nbase_samples = 1024\n"}
          .text();
  test::write_file(tmp / "s.toml", study);
  const fs::path dir = tmp / "s";
  const test::CommandResult run = test::run_demsa({"run", (tmp / "s.toml").string(), "--dir", dir.string()});
  EXPECT_NE(run.out.find("3 of 3 samples done"), std::string::npos) << run.out << run.err;
  const test::CommandResult status = test::run_demsa({"status", dir.string()});
  ASSERT_EQ(status.exit_code, 0) << status.err;
  // Each sample named (with the drift of its angle where both snapshots hold a pile to measure: 120 particles
  // 0.02 s into settling may not, and an angle outside (0°, 90°) is no pile).
  EXPECT_NE(status.out.find("unsettled 3 of 3 done: sample 0"), std::string::npos) << status.out;
  EXPECT_NE(status.out.find("still moving at the end of settling"), std::string::npos) << status.out;
  const test::CommandResult json = test::run_demsa({"status", dir.string(), "--json"});
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_EQ(nlohmann::json::parse(json.out).at("unsettled"), nlohmann::json::parse("[0, 1, 2]")) << json.out;
}

}  // namespace demsa
