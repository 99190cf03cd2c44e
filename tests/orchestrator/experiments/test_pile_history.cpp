// The pile in time: which settling checks write a snapshot, the drift of a series, pile_history.csv read back, and the
// case files that take the snapshots.
#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "postprocess/error.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>

#include <cmath>
#include <string>
#include <vector>

namespace demsa {
namespace {

using namespace demsa::experiments;
namespace fs = std::filesystem;

pile::PileSettings with(double history, std::vector<double> times) {
  pile::PileSettings s;
  s.settle_check_time = 0.01;
  s.history_interval = history;
  s.measure_times = std::move(times);
  return s;
}

std::vector<pile::PileMoment> series(const std::vector<std::pair<double, double>>& points) {
  std::vector<pile::PileMoment> moments;
  for (const auto& [t, angle] : points) {
    pile::PileMoment m;
    m.time = t;
    m.angle = angle;
    moments.push_back(m);
  }
  return moments;
}

}  // namespace

TEST(PileHistory, SnapshotsEveryIntervalAndAtEachMeasureTime) {
  // 100 checks of 1000 steps of 1e-5 s (0.01 s each): every 5th check, and the checks of 0.3 s and 0.47 s.
  const pile::SnapshotPlan plan = pile::snapshot_plan(with(0.05, {0.3, 0.47}), 100, 1000, 1e-5);
  EXPECT_EQ(plan.measure_checks, (std::vector<long>{30, 47}));
  EXPECT_EQ(plan.min_checks, 47);
  EXPECT_EQ(plan.checks.size(), 21u + 1u);  // 0, 5, ..., 100 and 47
  EXPECT_EQ(plan.checks.front(), 0);
  EXPECT_EQ(plan.checks.back(), 100);
  EXPECT_TRUE(std::is_sorted(plan.checks.begin(), plan.checks.end()));
  // No history: the measure times alone; neither: nothing, and the criterion may stop at any check.
  EXPECT_EQ(pile::snapshot_plan(with(0, {0.3}), 100, 1000, 1e-5).checks, (std::vector<long>{30}));
  const pile::SnapshotPlan none = pile::snapshot_plan(with(0, {}), 100, 1000, 1e-5);
  EXPECT_TRUE(none.checks.empty());
  EXPECT_EQ(none.min_checks, 0);
  // An interval shorter than a check: every check.
  EXPECT_EQ(pile::snapshot_plan(with(0.001, {}), 10, 1000, 1e-5).checks.size(), 11u);
}

TEST(PileHistory, DriftIsTheTheilSenSlopeOverTheLastWindow) {
  // 1°/s until 0.5 s, then static: over the last 0.2 s the pile does not move.
  std::vector<std::pair<double, double>> points;
  for (int k = 0; k <= 10; ++k) points.emplace_back(0.1 * k, 30.0 + std::min(0.1 * k, 0.5));
  EXPECT_NEAR(pile::angle_drift(series(points), 0.2), 0.0, 1e-12);
  // A falling angle with one snapshot off by 5°: the slope is the fall's.
  points.clear();
  for (int k = 0; k <= 10; ++k) points.emplace_back(0.1 * k, 30.0 - 3.0 * 0.1 * k + (k == 8 ? 5.0 : 0.0));
  EXPECT_NEAR(pile::angle_drift(series(points), 0.5), -3.0, 1e-9);
  // One moment in the window: no drift. NaN angles are left out.
  EXPECT_TRUE(std::isnan(pile::angle_drift(series({{0.0, 30.0}, {1.0, 31.0}}), 0.5)));
  EXPECT_NEAR(pile::angle_drift(series({{0.0, NAN}, {0.9, 30.0}, {1.0, 31.0}}), 0.5), 10.0, 1e-9);
}

TEST(PileHistory, TheSeriesReadsBackAndBadFilesAreRefusedAtTheirLine) {
  test::TempDir tmp;
  std::vector<pile::PileMoment> moments = series({{0.0, NAN}, {0.1, 31.25}, {0.2, 30.5}});
  moments[1].check = 10;
  moments[1].height = 0.03;
  moments[1].on_pedestal = 1200;
  pile::write_history(tmp.path(), moments);
  const std::vector<pile::PileMoment> back = pile::read_history(tmp.path());
  ASSERT_EQ(back.size(), 3u);
  EXPECT_TRUE(std::isnan(back[0].angle));
  EXPECT_EQ(back[1].check, 10);
  EXPECT_EQ(back[1].angle, 31.25);
  EXPECT_EQ(back[1].height, 0.03);
  EXPECT_EQ(back[1].on_pedestal, 1200);
  const auto refused = [&](const std::string& text, const std::string& expected) {
    test::write_file(tmp / "pile_history.csv", text);
    try {
      pile::read_history(tmp.path());
      ADD_FAILURE() << "accepted: " << text;
    } catch (const postprocess::ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  const std::string header = "check,time_s,angle_deg,angle_paper_deg,angle_robust_deg,pile_height_m,on_pedestal\n";
  refused("time,angle\n", "pile_history.csv:1: expected the header");
  refused(header + "0,0,30,30,30,0.03,100\n1,0.1,x,30,30,0.03,100\n", "pile_history.csv:3: column 3: 'x'");
  refused(header + "0,0,30,30,30,0.03\n", "6 columns, expected 7");
  refused(header + "0,-1,30,30,30,0.03,100\n", "time -1 s");
  refused(header + "0.5,0,30,30,30,0.03,100\n", "whole numbers");
  refused("", "no header line");
}

TEST(PileHistory, TheCaseWritesASnapshotAtEachPlannedCheck) {
  test::TempDir tmp;
  const study::StudyConfig config = parse_study(
      "[study]\nname = \"h\"\nexperiment = \"pile\"\n[parameters]\nmu_r_pp = { low = 0.05, high = 0.5 }\n"
      "[pile]\nparticles = 300\npedestal_radius = 0.025\nsettle_time = 0.5\nsettle_check_time = 0.05\n"
      "history_interval = 0.1\nmeasure_times = [0.25]\n",
      "h.toml");
  const fs::path dir = tmp / "case";
  cases::write_case(config, cases::request_from_unit_point(config, 0, {0.5}), dir);
  const std::string script = test::read_file(dir / "pile_history.liggghts");
  // Checks 0, 2, 4, 6, 8, 10 (every 0.1 s) and 5 (0.25 s).
  for (const int k : {0, 2, 4, 5, 6, 8, 10})
    EXPECT_NE(script.find(fmt::format("${{history_check}} == {}\"", k)), std::string::npos) << k << "\n" << script;
  EXPECT_EQ(script.find("${history_check} == 1\""), std::string::npos);
  EXPECT_NE(test::read_file(dir / "params.liggghts").find("settle_min_checks    equal 5 "), std::string::npos)
      << test::read_file(dir / "params.liggghts");
  const nlohmann::json doc = read_case_json(dir);
  EXPECT_EQ(doc["pile"]["history"]["measure_checks"], nlohmann::json::array({5}));
  EXPECT_EQ(doc["pile"]["history"]["snapshot_checks"].size(), 7u);
}

}  // namespace demsa
