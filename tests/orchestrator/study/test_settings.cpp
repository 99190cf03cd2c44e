// The table of study settings: every row is read by the parser into its own field, the design hash is that of the
// previous version for unchanged measurement settings and sees [pile] levels and directions, and
// docs/reference/study-file.md holds the table's rendering.
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/experiments/settings_docs.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/errors.hpp"

#include "sobol/design.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace demsa {

using namespace demsa::study;
using namespace demsa::experiments;
namespace {

namespace fs = std::filesystem;

/// Section -> key -> TOML value text.
using StudyMap = std::map<std::string, std::map<std::string, std::string>>;

/// The study file of `values`, sections in the table's order.
std::string study_text(const StudyMap& values) {
  std::string text;
  for (const SettingSection& section : settings_table().sections()) {
    const auto it = values.find(section.name);
    if (it == values.end()) continue;
    text += "[" + section.name + "]\n";
    for (const auto& [key, value] : it->second) text += key + " = " + value + "\n";
  }
  return text;
}

StudyMap minimal_study() {
  return {{"study", {{"name", "\"s\""}, {"experiment", "\"pile\""}}},
          {"parameters", {{"E", "{ low = 1e8, high = 1e9, scale = \"log\" }"}}}};
}

/// Every row's value as shown.
std::map<std::string, std::string> shown(const StudyConfig& c) {
  std::map<std::string, std::string> values;
  for (const Setting& s : settings_table().rows()) values[s.section + "." + s.key] = s.show(c);
  return values;
}

/// A value of `s` other than the default `c` has, in TOML, admissible by the row; "" when none is tried.
std::string other_value(const Setting& s, const StudyConfig& c) {
  const std::string current = s.show(c);
  switch (s.type) {
    case SettingType::number: {
      const double d = std::stod(current);
      // [drum] r_max: larger, the lattice the fill starts on no longer holds the default 50 mL.
      if (s.section == "drum" && s.key == "r_max") return fmt::format("{:.17g}", d * 0.9);
      for (double v : {d * 1.1, d * 0.9, d + 1, d + 0.01, 1e-6})
        if (v != d && s.bounds.contains(v)) return fmt::format("{:.17g}", v);
      return "";
    }
    case SettingType::integer:
      // [drum] particles: a fill whose surface lies in the judged circle (the default's, 50 mL of the MCC).
      if (s.section == "drum" && s.key == "particles") return "30000";
      return std::to_string(std::stol(current) + 1);
    case SettingType::boolean:
      return current == "true" ? "false" : "true";
    case SettingType::string:
      return current.substr(0, current.size() - 1) + "x\"";
    case SettingType::enumeration:
      for (const std::string& name : s.choices)
        if ("\"" + name + "\"" != current) return "\"" + name + "\"";
      return "";
    case SettingType::string_list:
      return current == "[]" ? "[\"--x\"]" : "[\"rsm1\"]";
    case SettingType::number_list:
      // measured_settlements: one per load after the first; loads: one more, larger load; [drum] stations: fractions
      // of the radius within judged_radius.
      if (s.key == "stations") return "[-0.2, 0.2]";
      return current == "[]" ? "[1e-3, 2e-3, 3e-3]" : "[100, 400, 1100, 2700, 5000]";
    case SettingType::table:
      if (s.key == "replicates") return "{ points = 2, repeats = 3 }";
      return s.key == "E" ? "{ low = 2e8, high = 3e8 }" : "{ low = 0.1, high = 0.2 }";
  }
  return "";
}

TEST(StudySettings, EveryRowIsReadIntoItsOwnField) {
  // A row of an experiment's section is tried in a study of that experiment (another's refuses the table).
  int checked = 0;
  for (const Setting& s : settings_table().rows()) {
    if (s.first) continue;  // presets set other rows (StudyConfig tests)
    StudyMap base = minimal_study();
    if (const ExperimentSchema* owner = settings_table().owner(s.section))
      base["study"]["experiment"] = "\"" + owner->name + "\"";
    const StudyConfig defaults = parse_study(study_text(base), "study.toml");
    const std::map<std::string, std::string> before = shown(defaults);
    const std::string value = other_value(s, defaults);
    ASSERT_FALSE(value.empty()) << s.section << "." << s.key;
    StudyMap study = base;
    study[s.section][s.key] = value;
    // mode = "fixed" needs a value: that row may change along.
    const bool fixed_mode = s.section == "timestep" && s.key == "mode";
    if (fixed_mode) study["timestep"]["value"] = "1e-6";
    // [pile] pedestal_top = "plane" needs remove_fallen.
    const bool plane_top = s.section == "pile" && s.key == "pedestal_top";
    if (plane_top) study["pile"]["remove_fallen"] = "true";
    // [drum] diameters and fractions are given together, as many of each.
    const bool size_classes = s.section == "drum" && (s.key == "diameters" || s.key == "fractions");
    if (size_classes) {
      study["drum"]["diameters"] = "[1e-3, 1.2e-3, 1.4e-3]";
      study["drum"]["fractions"] = "[0.2, 0.3, 0.5]";
    }
    const std::string text = study_text(study);
    StudyConfig c;
    try {
      c = parse_study(text, "study.toml");
    } catch (const util::UserError& e) {
      FAIL() << e.what() << "\n" << text;
    }
    const std::map<std::string, std::string> after = shown(c);
    for (const auto& [name, shown_value] : after) {
      if (fixed_mode && name == "timestep.value") continue;
      if (plane_top && name == "pile.remove_fallen") continue;
      if (size_classes && name != s.section + "." + s.key && (name == "drum.diameters" || name == "drum.fractions"))
        continue;
      if (name == s.section + "." + s.key)
        EXPECT_NE(shown_value, before.at(name)) << name << " = " << value << " was not read";
      else
        EXPECT_EQ(shown_value, before.at(name)) << "setting " << s.section << "." << s.key << " changed " << name;
    }
    ++checked;
  }
  EXPECT_GE(checked, 90);
}

TEST(StudySettings, AFileOfEveryDefaultReadsAsTheDefaults) {
  // Once per experiment: a study holds its own experiment's table only. The presets are left out: they set other
  // rows, whose defaults the file gives.
  for (const Experiment* experiment : all()) {
    StudyConfig expected;
    expected.name = std::string("s");  // not from the literal: GCC 12 gives a false -Wrestrict warning here at -O3
    expected.experiment = std::string(experiment->name);
    expected.timestep.value = 1e-6;  // 0 = not given, which the file cannot say
    expected.parameters.push_back({"E", sobol::Bounds{1e8, 1e9, sobol::Scale::log_uniform}, 0});
    StudyMap study;
    for (const Setting& s : settings_table().rows()) {
      const ExperimentSchema* owner = settings_table().owner(s.section);
      if (s.first || (owner && owner->name != experiment->name)) continue;
      const std::string value = s.show(expected);
      // "none": [design] replicates off, which the file says by leaving it out.
      if (value != "not varied" && value != "none") study[s.section][s.key] = value;
    }
    const std::string text = study_text(study);
    StudyConfig c;
    try {
      c = parse_study(text, "study.toml");
    } catch (const util::UserError& e) {
      FAIL() << e.what() << "\n" << text;
    }
    EXPECT_EQ(shown(c), shown(expected)) << text;
    EXPECT_EQ(settings_table().hash_text(c), settings_table().hash_text(expected));
  }
}

TEST(StudySettings, TheKeysOfThePreviousVersionAreRows) {
  // The keys the previous parser knew, section by section (but [pile] ke_stop, retired with its own message, and
  // the settling rows that replaced it: test_pile_settling.cpp).
  const std::map<std::string, std::string> keys{
      {"study", "name, experiment, seed"},
      {"design", "method, samples, replicates"},
      {"parameters", "E, nu, mu_pp, mu_pw, e_r, mu_r_pp, mu_r_pw"},
      {"material", "E, nu, mu_pp, mu_pw, e_r, mu_r_pp, mu_r_pw, density, gravity, soft_particles, hard_particles"},
      {"pile",
       "preset, particles, r_min, r_max, r_mean, r_sd, disc_radius, fill_height, pedestal_radius, "
       "pedestal_height, settle_time, settle_speed, settle_quantile, settle_window, settle_check_time, "
       "remove_fallen, domain_half_width, target_angle, directions, "
       "levels, angle_estimator, base, pedestal_top, history_interval, keep_snapshots, measure_times, drift_window, "
       "drift_limit"},
      {"oedometer",
       "preset, particles, r_min, r_max, r_mean, r_sd, box_side, box_height, fill_time, loads, "
       "measured_settlements, plate_mode, plate_gap, load_tolerance, servo_vel_max, servo_kp, servo_ki, "
       "servo_kd, servo_max_steps, servo_check_steps, rest_velocity, trial_steps, relax_steps, "
       "trial_reduction, trial_step0, trial_floor, max_trials"},
      {"incline",
       "preset, r_min, r_max, r_mean, r_sd, rolling_probes, sliding_probes, lane_spacing, settle_time, tilt_rate, "
       "max_angle, record_angle, onset_distance, speed_angle, stop_distance"},
      {"drawdown",
       "preset, particles, r_min, r_max, r_mean, r_sd, slot_width, side_width, depth, fill_height, floor, fill_time, "
       "check_time, window, stop_share, min_time, time_cap, removal_depth, slices, bin_width, edge_skip, wall_skip"},
      {"drum",
       "preset, radius, depth, rpm, rotation, bulk_volume, particles, packing_fraction, diameters, fractions, r_min, "
       "r_max, r_mean, r_sd, coarse_grain, wall_sides, settle_time, spin_up, window, snapshot_interval, image_size, "
       "judged_radius, angle_half_width, stations, threshold"},
      {"timestep", "mode, fraction, value, skin"},
      {"contact", "rolling_model, rolling_damping, rolling_stiffness, viscous_unit"},
      {"run", "executor, ranks, parallel, oversubscribe, timeout, retries, lost_fraction, liggghts, mpirun, slurm"},
      {"run.slurm", "mode, partition, account, time_limit, throttle, sbatch_options, prologue, poll_interval"},
      {"analysis",
       "metamodels, second_order, bootstrap, interval, confidence, base_samples, gp_kernel, gp_trend, gp_nugget"},
  };
  std::size_t rows = 0;
  for (const auto& [section, list] : keys) {
    std::set<std::string> expected;
    std::istringstream in(list);
    for (std::string key; std::getline(in, key, ',');) expected.insert(key.substr(key.find_first_not_of(' ')));
    const std::vector<std::string> actual = settings_table().keys(section);
    EXPECT_EQ(std::set<std::string>(actual.begin(), actual.end()), expected) << section;
    for (const std::string& key : actual) rows += settings_table().find(section, key) ? 1 : 0;
  }
  EXPECT_EQ(rows, settings_table().rows().size());
  for (const Setting& s : settings_table().rows()) {
    EXPECT_FALSE(s.doc.empty()) << s.key;
    EXPECT_FALSE(s.default_text.empty()) << s.key;
    EXPECT_TRUE(s.canonical && s.show) << s.key;
    EXPECT_EQ(s.type == SettingType::table, !s.assign) << s.key;
  }
}

TEST(StudySettings, RangesComeFromTheTable) {
  const std::string base = study_text(minimal_study());
  const auto error_of = [&](const std::string& more) {
    try {
      parse_study(base + more, "study.toml");
    } catch (const util::UserError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error_of("[pile]\nlevels = 1\n"), "study.toml:7: [pile] levels: must lie in [2, 100000], got 1");
  EXPECT_EQ(error_of("[analysis]\nconfidence = 1\n"), "study.toml:7: [analysis] confidence: must lie in (0, 1), got 1");
  EXPECT_EQ(error_of("[run]\nlost_fraction = -0.5\n"),
            "study.toml:7: [run] lost_fraction: must lie in [0, 1], got -0.5");
  EXPECT_EQ(error_of("[timestep]\nfraction = 0.5\n"),
            "study.toml:7: [timestep] fraction: must lie in [1e-06, 0.3], got 0.5: a time step above 0.3 Rayleigh "
            "times is unstable for Hertz contacts; below 1e-6 it underflows for the smallest particles");
  EXPECT_EQ(settings_table().find("pile", "levels")->range_text, "[2, 100000]");
  EXPECT_EQ(settings_table().find("parameters", "nu")->bounds.text(), "(0, 0.5)");
}

TEST(StudySettings, EveryNumberHasAPhysicalRange) {
  // Both ends, finite: a value of 1e300 or 1e-300 is refused at its line, before it sizes a lattice, a mesh or a
  // step count.
  for (const Setting& s : settings_table().rows()) {
    if (s.type != SettingType::number && s.type != SettingType::integer && s.type != SettingType::number_list &&
        !(s.type == SettingType::table && s.section == "parameters"))
      continue;
    SCOPED_TRACE(s.section + "." + s.key);
    ASSERT_TRUE(s.bounds.low.has_value());
    ASSERT_TRUE(s.bounds.high.has_value());
    EXPECT_TRUE(std::isfinite(s.bounds.low->value));
    EXPECT_TRUE(std::isfinite(s.bounds.high->value));
    EXPECT_FALSE(s.bounds.contains(1e300));
    EXPECT_FALSE(s.bounds.contains(-1e300));
  }
}

TEST(StudySettings, UnknownKeySuggestsTheNearestKey) {
  const std::string e = [] {
    try {
      parse_study(study_text(minimal_study()) + "[run]\nparalel = 2\n", "study.toml");
    } catch (const util::UserError& error) {
      return std::string(error.what());
    }
    return std::string();
  }();
  EXPECT_NE(e.find("study.toml:7: unknown key 'paralel' in [run] (did you mean 'parallel'? valid: executor, ranks"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("mpirun, slurm)"), std::string::npos) << e;
  EXPECT_EQ(settings_table().unknown_key_hint("parameters.E", "hi"),
            " (did you mean 'high'? valid: low, high, scale, same_as)");
  EXPECT_EQ(settings_table().unknown_key_hint("run.slurm", "zzz"),
            " (valid: mode, partition, account, time_limit, throttle, sbatch_options, prologue, poll_interval)");
}

TEST(StudySettings, DesignMethodsAreSobolsNames) {
  const StudyConfig centred = parse_study(study_text(minimal_study()) + "[design]\nmethod = \"lhs-centered\"\n", "s");
  EXPECT_EQ(centred.design, "lhs-centred");  // sobol's alias, kept as the canonical name
  EXPECT_EQ(settings_table().find("design", "method")->choices, sobol::design_kind_names());
  try {
    parse_study(study_text(minimal_study()) + "[design]\nmethod = \"halton\"\n", "study.toml");
    FAIL() << "halton accepted";
  } catch (const util::UserError& e) {
    EXPECT_EQ(std::string(e.what()),
              "study.toml:7: [design] method: unknown design 'halton' (valid: lhs, lhs-centred, lhs-maximin, "
              "lhs-cl2, sobol)");
  }
}

// ------------------------------------------------------------------------------------------------ design hash

/// Hashes computed by the previous version (commit 6807f91, build-base/orchestrator/demsa run --dry-run, read from
/// study.db): a study made by it must resume, so these may never change.
TEST(StudySettings, HashOfThePreviousVersionIsKept) {
  const std::string pile = R"(
[study]
name = "s"
experiment = "pile"

[parameters]
mu_r_pp = { low = 0.45, high = 4.5 }
E = { low = 1e8, high = 1e9, scale = "log" }
)";
  EXPECT_EQ(design_hash(parse_study(pile, "study.toml")), "9e331ed17738c998");
  const std::string oedometer = R"(
[study]
name = "o"
experiment = "oedometer"
seed = 99

[design]
method = "lhs-centred"
samples = 5

[parameters]
mu_pp = { low = 0.2, high = 0.8 }
nu = { low = 0.2, high = 0.4 }

[material]
density = 2600
soft_particles = true

[oedometer]
preset = "paper"
particles = 300
loads = [100, 200, 300]
plate_mode = "trial-step"

[timestep]
fraction = 0.1

[run]
ranks = 2
)";
  EXPECT_EQ(design_hash(parse_study(oedometer, "study.toml")), "7ea5cf2c874dc244");
  // The alias sobol accepts gives the same study.
  std::string alias = oedometer;
  alias.replace(alias.find("lhs-centred"), 11, "lhs-centered");
  EXPECT_EQ(design_hash(parse_study(alias, "study.toml")), "7ea5cf2c874dc244");
}

TEST(StudySettings, HashSeesMeasurementButNotRunSettings) {
  const std::string base = study_text(minimal_study());
  const std::string hash = design_hash(parse_study(base, "study.toml"));
  EXPECT_NE(design_hash(parse_study(base + "[pile]\nlevels = 12\n", "study.toml")), hash);
  EXPECT_NE(design_hash(parse_study(base + "[pile]\ndirections = 90\n", "study.toml")), hash);
  // Given at their defaults, they leave the hash alone.
  EXPECT_EQ(design_hash(parse_study(base + "[pile]\nlevels = 10\ndirections = 180\n", "study.toml")), hash);
  EXPECT_EQ(design_hash(parse_study(base + "[run]\nparallel = 3\ntimeout = 60\n", "study.toml")), hash);
  EXPECT_EQ(design_hash(parse_study(base + "[pile]\ntarget_angle = 30\n", "study.toml")), hash);
  EXPECT_NE(design_hash(parse_study(base + "[run]\nranks = 2\n", "study.toml")), hash);
  // The oedometer's measured settlements enter the hash of an oedometer study only.
  StudyMap oedometer = minimal_study();
  oedometer["study"]["experiment"] = "\"oedometer\"";
  const std::string oed = study_text(oedometer);
  EXPECT_NE(design_hash(parse_study(oed + "[oedometer]\nmeasured_settlements = [1e-3, 2e-3, 3e-3]\n", "s")),
            design_hash(parse_study(oed, "s")));
  // ... and [pile] cannot be part of an oedometer study at all.
  EXPECT_THROW(parse_study(oed + "[pile]\nlevels = 12\n", "s"), util::UserError);
  EXPECT_EQ(settings_table().find("pile", "levels")->effect, SettingEffect::measurement);
  EXPECT_EQ(settings_table().find("run", "ranks")->effect, SettingEffect::cases);
  EXPECT_EQ(settings_table().find("run", "parallel")->effect, SettingEffect::none);
}

TEST(StudySettings, ChangedSettingsNameTheKeys) {
  const std::string base = study_text(minimal_study());
  const StudyConfig a = parse_study(base, "study.toml");
  const StudyConfig b = parse_study(base + "[pile]\nlevels = 12\n[run]\nparallel = 3\n", "study.toml");
  EXPECT_EQ(settings_table().changed(a, b), std::vector<std::string>{"[pile] levels: 10 -> 12"});
  EXPECT_TRUE(settings_table().changed(a, a).empty());
}

// ------------------------------------------------------------------------------------------------ docs

TEST(StudySettings, DocsHoldTheTable) {
  const fs::path docs = fs::path(DEMSA_SOURCE_DIR) / "docs" / "reference" / "study-file.md";
  std::ifstream in(docs);
  ASSERT_TRUE(in) << docs;
  std::ostringstream text;
  text << in.rdbuf();
  const std::string file = text.str();
  const std::optional<std::string> expected = experiments::with_settings_table(file);
  ASSERT_TRUE(expected) << docs << " has no <!-- settings-table:begin --> and <!-- settings-table:end --> markers";
  const std::string& expected_file = *expected;
  if (expected_file != file) {
    // The build folder: DEMSA_BINARY is BUILD/orchestrator/demsa.
    const fs::path out = fs::path(DEMSA_BINARY).parent_path().parent_path() / "study-file.expected.md";
    std::ofstream(out) << expected_file;
    FAIL() << docs << " differs from the settings table (orchestrator/study/settings.cpp) between its markers.\n"
           << "A build regenerates it (target study_file_docs), or: cp " << out << " " << docs;
  }
}

}  // namespace
}  // namespace demsa
