// The one list of experiments: every descriptor is complete, owns its sections, and the settings table, the parser
// and case.json find experiments through it.
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/setting_row.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace demsa {
namespace {

using namespace demsa::experiments;
namespace fs = std::filesystem;

TEST(Registry, EveryDescriptorIsCompleteAndOwnsItsSections) {
  std::set<std::string> names;
  std::set<std::string> sections;
  for (const Experiment* e : all()) {
    const std::string name(e->name);
    EXPECT_TRUE(names.insert(name).second) << "two experiments named " << name;
    EXPECT_EQ(find(name), e);
    EXPECT_FALSE(e->summary.empty()) << name;
    EXPECT_FALSE(e->final_dump.empty()) << name;
    // The hooks every experiment must have (the optional ones may be null).
    EXPECT_TRUE(e->sections && e->settings && e->retired_keys && e->draft && e->driver_command && e->drivers &&
                e->particles && e->largest_radius && e->run_outputs && e->measure && e->observables && e->describe &&
                e->removed_particles && e->default_targets && e->lab_observables && e->report_focus && e->case_report &&
                e->vtk_surfaces)
        << name;
    const auto own = e->sections();
    ASSERT_FALSE(own.empty()) << name;
    for (const study::SettingSection& s : own) {
      EXPECT_TRUE(sections.insert(s.name).second) << "section [" << s.name << "] of two experiments";
      const study::ExperimentSchema* owner = settings_table().owner(s.name);
      ASSERT_NE(owner, nullptr) << s.name;
      EXPECT_EQ(owner->name, name);
    }
    for (const study::Setting& row : e->settings()) {
      bool own_section = false;
      for (const study::SettingSection& s : own) own_section = own_section || s.name == row.section;
      EXPECT_TRUE(own_section) << name << ": row [" << row.section << "] " << row.key;
    }
  }
  EXPECT_GE(all().size(), 2u);
  EXPECT_EQ(find("no such experiment"), nullptr);
}

TEST(Registry, StudyExperimentIsAChoiceOfTheRegistry) {
  const study::Setting* row = settings_table().find("study", "experiment");
  ASSERT_NE(row, nullptr);
  std::vector<std::string> names;
  for (const Experiment* e : all()) names.emplace_back(e->name);
  EXPECT_EQ(row->choices, names);
  const std::string message = test::message_of<util::UserError>([] {
    parse_study("[study]\nname = \"s\"\nexperiment = \"heap\"\n[parameters]\nE = { low = 1e8, high = 1e9 }\n",
                "study.toml");
  });
  EXPECT_NE(message.find("study.toml:3: [study] experiment: unknown value 'heap' (valid: pile, oedometer"),
            std::string::npos)
      << message;
}

TEST(Registry, ASectionOfAnotherExperimentIsRefused) {
  for (const Experiment* e : all())
    for (const Experiment* other : all()) {
      if (e == other) continue;
      const std::string section = other->sections().front().name;
      const std::string text = "[study]\nname = \"s\"\nexperiment = \"" + std::string(e->name) +
                               "\"\n[parameters]\nE = { low = 1e8, high = 1e9 }\n[" + section + "]\n";
      const std::string message = test::message_of<util::UserError>([&] { parse_study(text, "study.toml"); });
      EXPECT_NE(message.find("study.toml:6: [" + section + "] does not apply to this study: [study] experiment = \"" +
                             std::string(e->name) + "\" (line 3)"),
                std::string::npos)
          << message;
    }
}

TEST(Registry, CaseJsonNamesAKnownExperiment) {
  test::TempDir tmp;
  test::write_file(tmp / "case.json", "{\"experiment\": \"heap\"}\n");
  const nlohmann::json doc = read_case_json(tmp.path());
  const std::string message = test::message_of<util::UserError>([&] { of_case(doc, tmp / "case.json"); });
  EXPECT_NE(message.find("experiment = \"heap\": not an experiment this demsa knows (known: pile, oedometer"),
            std::string::npos)
      << message;
  test::write_file(tmp / "case.json", "{\"sample\": 3}\n");
  EXPECT_NE(test::message_of<util::UserError>([&] {
              of_case(read_case_json(tmp.path()), tmp / "case.json");
            }).find("names no experiment"),
            std::string::npos);
  EXPECT_EQ(&of_case(nlohmann::json{{"experiment", "pile"}}, tmp / "case.json"), find("pile"));
}

TEST(CaseRecord, ValuesAreRangeCheckedNotNarrowed) {
  test::TempDir tmp;
  const fs::path file = tmp / "case.json";
  const nlohmann::json doc = nlohmann::json::parse(
      R"({"pile": {"angle_measurement": {"directions": 1000000000000, "levels": 2.5}, "pedestal_radius_m": -1}})");
  EXPECT_NE(test::message_of<util::UserError>([&] {
              case_integer(doc, file, "pile.angle_measurement.directions", 1, 100000);
            }).find("pile.angle_measurement.directions = 1000000000000: must lie in [1, 100000]"),
            std::string::npos);
  EXPECT_NE(test::message_of<util::UserError>([&] {
              case_integer(doc, file, "pile.angle_measurement.levels", 2, 100000);
            }).find("pile.angle_measurement.levels = 2.5: not an integer"),
            std::string::npos);
  EXPECT_NE(test::message_of<util::UserError>([&] {
              case_number(doc, file, "pile.pedestal_radius_m", 1e-9, 1e3);
            }).find("pile.pedestal_radius_m = -1: must lie in"),
            std::string::npos);
  EXPECT_FALSE(case_number(doc, file, "pile.pedestal_height_m", 0, 1).has_value());
  // A number beyond double's range is not valid JSON for the reader: refused naming the file.
  test::write_file(file, "{\"experiment\": \"pile\", \"dt\": 1e999}\n");
  const std::string message = test::message_of<util::UserError>([&] { read_case_json(tmp.path()); });
  EXPECT_NE(message.find(file.string()), std::string::npos) << message;
  EXPECT_NE(message.find("not valid JSON"), std::string::npos) << message;
}

}  // namespace
}  // namespace demsa
