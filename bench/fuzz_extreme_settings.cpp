// Extreme settings through the real binary: every numeric row of the settings table (numbers, integers, number lists
// and the [parameters] ranges), in a study of the experiment that reads it, set to extreme values (0, ±1e-300,
// ±1e300, denormals, the largest doubles and integers, the row's own bounds and just beyond them) one at a time, then
// random combinations of two or three until the time budget is spent; each study through `demsa run --dry-run` and
// `demsa case`. Every run must end with exit 0 or 2 within the time bound: not an abort (134), an out-of-memory
// (3) or a hang. Not part of CI: docs/explanation/benchmarks.md has the command and the counts.
//
// Usage: fuzz_extreme_settings DEMSA_BINARY WORK_DIR [SECONDS (default 600)] [SEED (default 1)] [BOUND_S (30)]
#include "orchestrator/experiments/experiment.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/process.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace demsa;

/// One key of one experiment's study with its candidate TOML values.
struct Target {
  std::string experiment;
  std::string section;
  std::string key;
  std::vector<std::string> values;
};

std::string number_text(double v) { return fmt::format("{:.17g}", v); }

/// The extreme values of a row, as TOML text of its type.
std::vector<std::string> extremes(const study::Setting& s) {
  std::vector<double> numbers{0.0,
                              1e-300,
                              -1e-300,
                              1e300,
                              -1e300,
                              std::numeric_limits<double>::denorm_min(),
                              4.9e-320,
                              std::numeric_limits<double>::max(),
                              -std::numeric_limits<double>::max(),
                              1e8,
                              1e-8,
                              -1};
  for (const auto& bound : {s.bounds.low, s.bounds.high})
    if (bound)
      for (double f : {1.0, 1.0 + 1e-12, 1.0 - 1e-12, 2.0, 0.5}) numbers.push_back(bound->value * f);
  std::vector<std::string> values;
  switch (s.type) {
    case study::SettingType::integer:
      for (const char* v : {"0", "-1", "1", "2147483647", "2147483648", "4294967304", "9223372036854775807",
                            "-9223372036854775808", "100000000", "1000000000000"})
        values.emplace_back(v);
      for (const bool high : {false, true})
        if (const auto& bound = high ? s.bounds.high : s.bounds.low;
            bound && bound->value < 9e18 && bound->value > -9e18)
          for (long d : {-1L, 0L, 1L}) {
            // A particle count at its bound (1e7) is a valid case that takes half a minute and 3.3 GB to write:
            // measured once (docs/explanation/benchmarks.md), not on every input of the sweep.
            if (s.key == "particles" && high && d <= 0) continue;
            values.push_back(std::to_string(static_cast<long>(bound->value) + d));
          }
      break;
    case study::SettingType::number:
      for (double v : numbers) values.push_back(number_text(v));
      values.emplace_back("nan");
      values.emplace_back("inf");
      break;
    case study::SettingType::number_list:
      for (double v : numbers) values.push_back(fmt::format("[{}]", number_text(v)));
      for (double v : numbers) values.push_back(fmt::format("[1, {}]", number_text(v)));
      values.emplace_back("[]");
      break;
    case study::SettingType::table:  // a [parameters] range
      for (double v : numbers) {
        values.push_back(fmt::format("{{ low = {}, high = {} }}", number_text(v), number_text(v * 2 + 1)));
        values.push_back(fmt::format("{{ low = {}, high = {}, scale = \"log\" }}", number_text(v / 2), number_text(v)));
      }
      break;
    default:
      break;
  }
  return values;
}

std::vector<Target> targets() {
  std::vector<Target> out;
  const study::SettingsTable& table = experiments::settings_table();
  for (const experiments::Experiment* e : experiments::all()) {
    const std::string name(e->name);
    for (const study::Setting& s : table.rows()) {
      const bool numeric = s.type == study::SettingType::number || s.type == study::SettingType::integer ||
                           s.type == study::SettingType::number_list ||
                           (s.type == study::SettingType::table && s.section == "parameters");
      if (!numeric) continue;
      const study::ExperimentSchema* owner = table.owner(s.section);
      if (owner && owner->name != name) continue;
      out.push_back({name, s.section, s.key, extremes(s)});
    }
  }
  return out;
}

/// A small study of `experiment` with `changes` (section, key, value) applied.
std::string study_text(const std::string& experiment, const std::vector<std::array<std::string, 3>>& changes) {
  std::map<std::string, std::map<std::string, std::string>> sections;
  sections["study"] = {{"name", "\"x\""}, {"experiment", "\"" + experiment + "\""}};
  sections["design"] = {{"samples", "2"}};
  sections["parameters"] = {{"mu_pp", "{ low = 0.7, high = 1.9 }"}};
  // Small cases: each `demsa case` draws and writes its particles.
  sections[experiment == "incline" ? "incline" : experiment] = {};
  if (experiment != "incline") sections[experiment]["particles"] = "300";
  for (const auto& [section, key, value] : changes) sections[section][key] = value;
  std::string text;
  for (const auto& [section, keys] : sections) {
    text += "[" + section + "]\n";
    for (const auto& [key, value] : keys) text += key + " = " + value + "\n";
  }
  return text;
}

struct Counts {
  long inputs = 0;
  long runs = 0;
  long exit0 = 0;
  long exit2 = 0;
  long bad = 0;
  double slowest = 0;
};

/// Runs both commands on `text`; reports and counts every run that ends otherwise than 0 or 2 within `bound`.
void try_study(const std::string& demsa, const fs::path& work, const std::string& text, std::chrono::seconds bound,
               Counts& counts) {
  ++counts.inputs;
  fs::remove_all(work / "run");
  fs::create_directories(work / "run");
  const fs::path study = work / "run" / "study.toml";
  std::ofstream(study) << text;
  const std::vector<std::vector<std::string>> commands{
      {demsa, "run", study.string(), "--dir", (work / "run" / "study").string(), "--dry-run"},
      {demsa, "case", study.string(), "--sample", "0", "-o", (work / "run" / "case").string()}};
  for (const std::vector<std::string>& argv : commands) {
    util::CaptureOptions options;
    options.timeout = bound;
    const auto start = std::chrono::steady_clock::now();
    const util::CaptureResult r = util::run_capture(argv, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    counts.slowest = std::max(counts.slowest, seconds);
    ++counts.runs;
    if (r.exit_code == 0) {
      ++counts.exit0;
    } else if (r.exit_code == 2) {
      ++counts.exit2;
    } else {
      ++counts.bad;
      const fs::path kept = work / fmt::format("failure-{}.toml", counts.bad);
      std::ofstream(kept) << text;
      fmt::print("FAIL: `{}` exit {}{} after {:.1f} s ({}): {}\n", argv[1], r.exit_code,
                 r.timed_out ? " (timed out)" : "", seconds, kept.string(), r.err.substr(0, 400));
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    fmt::print(stderr, "usage: {} DEMSA_BINARY WORK_DIR [SECONDS] [SEED] [BOUND_S]\n", argv[0]);
    return 2;
  }
  const std::string demsa = fs::absolute(argv[1]).string();
  const fs::path work = fs::absolute(argv[2]);
  const double budget = argc > 3 ? std::atof(argv[3]) : 600.0;
  const unsigned seed = argc > 4 ? static_cast<unsigned>(std::atoi(argv[4])) : 1u;
  const std::chrono::seconds bound(argc > 5 ? std::atoi(argv[5]) : 30);
  fs::create_directories(work);
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };

  const std::vector<Target> all = targets();
  Counts counts;
  // Every value of every row, one at a time.
  for (const Target& t : all) {
    for (const std::string& v : t.values) {
      if (elapsed() > budget) break;
      try_study(demsa, work, study_text(t.experiment, {{{t.section, t.key, v}}}), bound, counts);
    }
  }
  const long single = counts.inputs;
  // Then two or three rows of one experiment at once.
  std::mt19937_64 rng(seed);
  while (elapsed() < budget) {
    const Target& first = all[rng() % all.size()];
    std::vector<std::array<std::string, 3>> changes;
    const int n = 2 + static_cast<int>(rng() % 2);
    for (int i = 0; i < 50 && static_cast<int>(changes.size()) < n; ++i) {
      const Target& t = all[rng() % all.size()];
      if (t.experiment != first.experiment || t.values.empty()) continue;
      changes.push_back({t.section, t.key, t.values[rng() % t.values.size()]});
    }
    try_study(demsa, work, study_text(first.experiment, changes), bound, counts);
  }
  fmt::print(
      "{} rows x experiments, {} inputs ({} one row at a time), {} runs in {:.0f} s: {} exit 0, {} exit 2, {} other; "
      "slowest run {:.2f} s\n",
      all.size(), counts.inputs, single, counts.runs, elapsed(), counts.exit0, counts.exit2, counts.bad,
      counts.slowest);
  return counts.bad == 0 ? 0 : 1;
}
