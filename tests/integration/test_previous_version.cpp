// A study folder written by the previous demsa (tests/data/previous_version: store schema version 1) still works:
// `demsa status` reads it without writing to it, and `demsa run` migrates the store and finishes only the samples
// that were not done, with the fake LIGGGHTS of tests/integration/fake_liggghts.
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/store.hpp"

#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>

namespace demsa {

using namespace demsa::study;
namespace {

namespace fs = std::filesystem;
using test::starts_per_sample;

/// TMP/study, a copy of the fixture folder.
fs::path copy_previous_version_study(const test::TempDir& tmp) {
  const fs::path dir = tmp / "study";
  fs::create_directories(dir);
  for (const char* name : {"study.toml", "study.db", "design.csv"})
    fs::copy_file(test::data_path("previous_version") / name, dir / name);
  return dir;
}

TEST(PreviousVersion, StatusReadsTheStudyWithoutWritingToIt) {
  test::TempDir tmp;
  const fs::path dir = copy_previous_version_study(tmp);
  const std::string before = test::read_file(dir / k_store_file);

  const test::CommandResult status = test::run_demsa({"status", dir.string()});
  EXPECT_EQ(status.exit_code, 0) << status.out << status.err;
  EXPECT_NE(status.out.find("study previous-version in"), std::string::npos) << status.out;
  EXPECT_NE(status.out.find("samples 12: done 6, running 0, failed 2, pending 4 (9 attempts)"), std::string::npos)
      << status.out;
  EXPECT_NE(status.out.find("sample 2 attempt 1: liggghts-error: ERROR: Fake failure of sample 2"), std::string::npos)
      << status.out;
  EXPECT_NE(status.out.find("sample 5 attempt 1: timeout: time limit exceeded"), std::string::npos) << status.out;

  const test::CommandResult json = test::run_demsa({"status", dir.string(), "--json"});
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const nlohmann::json j = nlohmann::json::parse(json.out);
  std::map<int, std::string> classes;
  for (const nlohmann::json& f : j.at("failures")) classes[f.at("sample").get<int>()] = f.at("class");
  EXPECT_EQ(classes, (std::map<int, std::string>{{2, "liggghts-error"}, {5, "timeout"}}));

  EXPECT_EQ(test::read_file(dir / k_store_file), before) << "status wrote to the store";
  EXPECT_EQ(Store::open_read_only((dir / k_store_file).string()).schema_version(), 1);
}

TEST(PreviousVersion, RunMigratesTheStoreAndFinishesOnlyTheMissingSamples) {
  test::TempDir tmp;
  const fs::path dir = copy_previous_version_study(tmp);
  // The fixture's [run] names no LIGGGHTS (machine paths); [run] may change in an existing study.
  std::string toml = test::read_file(dir / k_frozen_study);
  const std::size_t at = toml.find("[run]\n");
  ASSERT_NE(at, std::string::npos);
  toml.insert(at + 6, test::fake_liggghts_run_lines());
  test::write_file(dir / k_frozen_study, toml);
  const fs::path state = tmp / "state";
  fs::create_directories(state);
  const test::FakeLiggghtsEnvironment env("", state, 0);

  const test::CommandResult run =
      test::run_demsa({"run", (dir / k_frozen_study).string(), "--dir", dir.string(), "--quiet"});
  EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("12 of 12 samples done (6 now, 0 recovered), 0 failed"), std::string::npos) << run.out;

  // Only the samples that were not done ran, once each: the two failed, the requeued one and the three never run.
  EXPECT_EQ(starts_per_sample(state), (std::map<int, int>{{2, 1}, {5, 1}, {8, 1}, {9, 1}, {10, 1}, {11, 1}}));
  for (int k : {0, 1, 3, 4, 6, 7}) EXPECT_FALSE(fs::exists(case_dir(dir, k))) << "sample " << k << " ran again";

  const Store store = Store::open_read_only((dir / k_store_file).string());
  EXPECT_EQ(store.schema_version(), k_store_schema_version);
  EXPECT_EQ(store.counts().done, 12);
  EXPECT_EQ(store.observables().size(), 12u);
  EXPECT_EQ(store.integrity_check(), "ok");
  // The old runs kept their ids, states and failure classes; the new ones came after them.
  EXPECT_EQ(store.run(1)->state, RunState::done);
  EXPECT_EQ(store.run(3)->failure, FailureClass::liggghts_error);
  EXPECT_EQ(store.run(6)->failure, FailureClass::timeout);
  EXPECT_EQ(store.run(9)->state, RunState::requeued);
  for (const RunRow& r : store.runs()) {
    if (r.id <= 9) continue;
    EXPECT_EQ(r.state, RunState::done);
    EXPECT_EQ(r.failure, FailureClass::none);
    EXPECT_TRUE(r.sample == 2 || r.sample == 5 || r.sample >= 8) << "sample " << r.sample;
    EXPECT_EQ(r.attempt, r.sample == 2 || r.sample == 5 ? 2 : 1) << "sample " << r.sample;
  }
  int migrated = 0;
  for (const EventRow& e : store.events()) migrated += e.kind == "migrated";
  EXPECT_EQ(migrated, 1);
}

}  // namespace
}  // namespace demsa
