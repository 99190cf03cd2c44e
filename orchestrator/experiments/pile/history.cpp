#include "orchestrator/experiments/pile/pile.hpp"

#include "postprocess/error.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

// The pile in time: which settling checks write a snapshot, the series measured on them, and its drift.
namespace demsa::experiments::pile {

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

std::string snapshot_file(long check) { return fmt::format("pile_snapshot_{}.dump", check); }

std::string timed_observable(std::string_view prefix, double t) {
  // fmt's shortest round-trip text: 0.6 -> "0.6", 2.0 -> "2".
  return fmt::format("{}{}", prefix, t);
}

SnapshotPlan snapshot_plan(const PileSettings& s, long checks, long check_steps, double dt) {
  SnapshotPlan plan;
  const double check_time = static_cast<double>(check_steps) * dt;
  const auto check_of = [&](double t) {
    return std::clamp(static_cast<long>(std::llround(t / check_time)), 0L, checks);
  };
  if (s.history_interval > 0) {
    const long every = std::max(1L, static_cast<long>(std::llround(s.history_interval / s.settle_check_time)));
    for (long k = 0; k <= checks; k += every) plan.checks.push_back(k);
  }
  for (const double t : s.measure_times) {
    plan.measure_checks.push_back(check_of(t));
    plan.checks.push_back(plan.measure_checks.back());
    plan.min_checks = std::max(plan.min_checks, plan.measure_checks.back());
  }
  std::sort(plan.checks.begin(), plan.checks.end());
  plan.checks.erase(std::unique(plan.checks.begin(), plan.checks.end()), plan.checks.end());
  return plan;
}

double angle_drift(const std::vector<PileMoment>& moments, double window) {
  std::vector<double> angle;
  std::vector<double> time;
  double last = -std::numeric_limits<double>::infinity();
  for (const PileMoment& m : moments)
    if (std::isfinite(m.angle)) last = std::max(last, m.time);
  for (const PileMoment& m : moments) {
    if (!std::isfinite(m.angle) || m.time < last - window * (1 + 1e-9)) continue;
    angle.push_back(m.angle);
    time.push_back(m.time);
  }
  if (angle.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  return pp::fit_theil_sen_line(angle, time).slope;
}

namespace {

constexpr const char* k_history_header =
    "check,time_s,angle_deg,angle_paper_deg,angle_robust_deg,pile_height_m,"
    "on_pedestal";

}  // namespace

void write_history(const fs::path& folder, const std::vector<PileMoment>& moments) {
  std::string text = std::string(
                         "# the pile in time: check -1 is the final dump; angles in degrees, NaN where a "
                         "snapshot holds no pile to measure\n") +
                     k_history_header + "\n";
  for (const PileMoment& m : moments)
    text += fmt::format("{},{},{},{},{},{},{}\n", m.check, m.time, m.angle, m.angle_paper, m.angle_robust, m.height,
                        m.on_pedestal);
  const fs::path file = folder / k_history_csv;
  std::ofstream out(file);
  out << text;
  if (!out.flush()) throw pp::InputError(fmt::format("{}: cannot write", file.string()));
}

std::vector<PileMoment> read_history(const fs::path& folder) {
  const fs::path file = folder / k_history_csv;
  std::ifstream in(file);
  if (!in) throw pp::InputError(fmt::format("{}: cannot read", file.string()));
  std::vector<PileMoment> moments;
  std::string line;
  long number = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      if (line != k_history_header)
        throw pp::ParseError(file.string(), number, fmt::format("expected the header '{}'", k_history_header));
      header = true;
      continue;
    }
    if (moments.size() >= 100000) throw pp::ParseError(file.string(), number, "more than 100000 moments");
    std::vector<std::string> cells;
    std::stringstream words(line);
    for (std::string cell; std::getline(words, cell, ',');) cells.push_back(cell);
    const auto value = [&](std::size_t i) {
      const std::string& cell = cells[i];
      // strtod reads "nan" as the measurement wrote it; anything else that is not a whole number is refused.
      char* end = nullptr;
      const double v = std::strtod(cell.c_str(), &end);
      if (cell.empty() || end != cell.c_str() + cell.size())
        throw pp::ParseError(file.string(), number, fmt::format("column {}: '{}' is not a number", i + 1, cell));
      return v;
    };
    if (cells.size() != 7)
      throw pp::ParseError(file.string(), number, fmt::format("{} columns, expected 7", cells.size()));
    PileMoment m;
    const double check = value(0);
    const double on_pedestal = value(6);
    if (!(check >= -1 && check <= 1e9 && check == std::floor(check)) ||
        !(on_pedestal >= 0 && on_pedestal <= 1e9 && on_pedestal == std::floor(on_pedestal)))
      throw pp::ParseError(file.string(), number, "check and on_pedestal must be whole numbers");
    m.check = static_cast<long>(check);
    m.time = value(1);
    if (!std::isfinite(m.time) || m.time < 0)
      throw pp::ParseError(file.string(), number, fmt::format("time {} s is not a time after the last disc", m.time));
    m.angle = value(2);
    m.angle_paper = value(3);
    m.angle_robust = value(4);
    m.height = value(5);
    m.on_pedestal = static_cast<long>(on_pedestal);
    moments.push_back(m);
  }
  if (!header) throw pp::ParseError(file.string(), number, "no header line");
  return moments;
}

}  // namespace demsa::experiments::pile
