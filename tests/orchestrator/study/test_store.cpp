#include "orchestrator/study/store.hpp"

#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace demsa {

using namespace demsa::study;
namespace {

std::vector<SampleRow> three_samples() {
  return {{0, {0.1, 0.2}, {1.0, 2.0}}, {1, {0.5, 0.6}, {5.0, 6.0}}, {2, {0.9, 0.7}, {9.0, 7.0}}};
}

TEST(Store, NewStoreHasNoDesignHashAndIntegrityOk) {
  test::TempDir tmp;
  Store store((tmp / "study.db").string());
  EXPECT_FALSE(store.design_hash().has_value());
  EXPECT_EQ(store.integrity_check(), "ok");
  EXPECT_EQ(store.counts().samples, 0);
}

TEST(Store, InitializeKeepsHashNameAndSamples) {
  test::TempDir tmp;
  {
    Store store((tmp / "study.db").string());
    store.initialize("abc123", "pile-test", three_samples());
  }
  Store store((tmp / "study.db").string());
  ASSERT_TRUE(store.design_hash().has_value());
  EXPECT_EQ(*store.design_hash(), "abc123");
  EXPECT_EQ(store.study_name(), "pile-test");
  const std::vector<SampleRow> rows = store.samples();
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1].sample, 1);
  EXPECT_DOUBLE_EQ(rows[1].unit[1], 0.6);
  EXPECT_DOUBLE_EQ(rows[2].physical[0], 9.0);
  EXPECT_THROW(store.initialize("other", "x", three_samples()), std::logic_error);
}

TEST(Store, DoneRunCommitsObservablesAndCountsOnce) {
  test::TempDir tmp;
  Store store((tmp / "study.db").string());
  store.initialize("h", "s", three_samples());
  const long run = store.add_run(1, 1);
  store.set_job_id(run, "123:456");
  RunOutcome outcome;
  outcome.exit_code = 0;
  outcome.wall_seconds = 2.5;
  outcome.cpu_seconds = 2.0;
  outcome.host = "node1";
  store.record_done(run, outcome, {{"angle", 31.5}, {"pile_height", 0.04}});
  const auto values = store.observables();
  ASSERT_EQ(values.size(), 1u);
  EXPECT_DOUBLE_EQ(values.at(1).at("angle"), 31.5);
  const std::optional<RunRow> row = store.run(run);
  ASSERT_TRUE(row.has_value());
  EXPECT_EQ(row->state, RunState::done);
  EXPECT_EQ(row->job_id, "123:456");
  EXPECT_EQ(row->host, "node1");
  EXPECT_DOUBLE_EQ(row->wall_seconds, 2.5);
  // A second done run of the same sample is refused by the schema (and by the state check).
  const long again = store.add_run(1, 2);
  EXPECT_ANY_THROW(store.record_done(again, outcome, {{"angle", 1.0}}));
  EXPECT_DOUBLE_EQ(store.observables().at(1).at("angle"), 31.5);
  // Committing the same run twice is refused.
  EXPECT_THROW(store.record_done(run, outcome, {}), std::logic_error);
  EXPECT_EQ(store.integrity_check(), "ok");
}

TEST(Store, CountsFollowTheLatestRunOfEachSample) {
  test::TempDir tmp;
  Store store((tmp / "study.db").string());
  store.initialize("h", "s", three_samples());
  const long r0 = store.add_run(0, 1);
  RunOutcome failed;
  failed.failure = FailureClass::timeout;
  failed.message = "time limit exceeded";
  failed.log_tail = "Step KinEng\n";
  store.record_failed(r0, failed);
  const long r1 = store.add_run(1, 1);
  store.record_done(r1, RunOutcome{}, {{"angle", 30.0}});
  const long r2 = store.add_run(2, 1);
  StoreCounts c = store.counts();
  EXPECT_EQ(c.samples, 3);
  EXPECT_EQ(c.failed, 1);
  EXPECT_EQ(c.done, 1);
  EXPECT_EQ(c.running, 1);
  EXPECT_EQ(c.pending, 0);
  EXPECT_EQ(c.attempts, 3);
  store.record_requeued(r2, "cancelled");
  c = store.counts();
  EXPECT_EQ(c.running, 0);
  EXPECT_EQ(c.pending, 1);
  ASSERT_EQ(store.runs_in_state(RunState::failed).size(), 1u);
  EXPECT_EQ(store.runs_in_state(RunState::failed)[0].failure, FailureClass::timeout);
  EXPECT_EQ(store.runs_in_state(RunState::failed)[0].log_tail, "Step KinEng\n");
  EXPECT_THROW(store.record_failed(r0, failed), std::logic_error);  // already failed
}

TEST(Store, ReadOnlyOpenSeesCommitsOfAWriter) {
  test::TempDir tmp;
  const std::string path = (tmp / "study.db").string();
  Store writer(path);
  writer.initialize("h", "s", three_samples());
  const Store reader = Store::open_read_only(path);
  EXPECT_EQ(reader.counts().done, 0);
  const long run = writer.add_run(0, 1);
  writer.record_done(run, RunOutcome{}, {{"angle", 1.0}});
  EXPECT_EQ(reader.counts().done, 1);
  EXPECT_THROW(Store::open_read_only((tmp / "missing.db").string()), std::runtime_error);
}

TEST(Store, EventsAreKeptInOrder) {
  test::TempDir tmp;
  Store store((tmp / "study.db").string());
  store.add_event("created", "first");
  store.add_event("resume", "second", 4);
  const std::vector<EventRow> events = store.events();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, "created");
  EXPECT_EQ(events[1].sample, 4);
  EXPECT_EQ(events[1].message, "second");
}

TEST(Store, RunStateNamesRoundTripAndUnknownIsRefused) {
  for (RunState s : {RunState::submitted, RunState::done, RunState::failed, RunState::requeued})
    EXPECT_EQ(run_state_from_string(to_string(s)), s);
  EXPECT_THROW(run_state_from_string("finished"), std::invalid_argument);
}

// ------------------------------------------------------------------------------------ schema versions, migration

namespace fs = std::filesystem;

/// TMP/study.db, a copy of the store the previous demsa wrote (tests/data/previous_version/README.md).
std::string copy_previous_version_store(const test::TempDir& tmp) {
  const fs::path db = tmp / "study.db";
  fs::copy_file(test::data_path("previous_version/study.db"), db);
  return db.string();
}

std::string meta_value(const std::string& path, const std::string& key) {
  SQLite::Database db(path, SQLite::OPEN_READONLY);
  SQLite::Statement q(db, "SELECT value FROM meta WHERE key = ?");
  q.bind(1, key);
  return q.executeStep() ? q.getColumn(0).getString() : std::string{};
}

int migrated_events(const Store& store) {
  const std::vector<EventRow> events = store.events();
  return static_cast<int>(
      std::count_if(events.begin(), events.end(), [](const EventRow& e) { return e.kind == "migrated"; }));
}

/// The runs of the fixture, as the previous demsa left them: run id -> (sample, state, failure).
void expect_previous_version_runs(const Store& store) {
  const std::vector<RunRow> runs = store.runs();
  ASSERT_EQ(runs.size(), 9u);
  for (const RunRow& r : runs) {
    EXPECT_EQ(r.id, r.sample + 1);
    EXPECT_EQ(r.attempt, 1);
    if (r.sample == 2) {
      EXPECT_EQ(r.state, RunState::failed);
      EXPECT_EQ(r.failure, FailureClass::liggghts_error);
      EXPECT_NE(r.message.find("Fake failure of sample 2"), std::string::npos);
    } else if (r.sample == 5) {
      EXPECT_EQ(r.state, RunState::failed);
      EXPECT_EQ(r.failure, FailureClass::timeout);
    } else if (r.sample == 8) {
      EXPECT_EQ(r.state, RunState::requeued);
      EXPECT_EQ(r.failure, FailureClass::none);
    } else {
      EXPECT_EQ(r.state, RunState::done) << "sample " << r.sample;
      EXPECT_EQ(r.failure, FailureClass::none);
    }
  }
  const StoreCounts c = store.counts();
  EXPECT_EQ(c.samples, 12);
  EXPECT_EQ(c.done, 6);
  EXPECT_EQ(c.failed, 2);
  EXPECT_EQ(c.pending, 4);
  EXPECT_EQ(c.attempts, 9);
  EXPECT_EQ(store.observables().size(), 6u);
  EXPECT_EQ(store.design_hash().value_or(""), "ce60b7c194008e95");
}

TEST(StoreSchema, ReadOnlyOpenReadsAVersion1StoreAndWritesNothing) {
  test::TempDir tmp;
  const std::string path = copy_previous_version_store(tmp);
  const std::string before = test::read_file(path);
  {
    const Store store = Store::open_read_only(path);
    EXPECT_EQ(store.schema_version(), 1);
    expect_previous_version_runs(store);
    EXPECT_EQ(migrated_events(store), 0);
  }
  EXPECT_EQ(test::read_file(path), before);
  EXPECT_EQ(meta_value(path, "schema_version"), "1");
}

TEST(StoreSchema, Version1StoreIsMigratedOnceAndKeepsItsRuns) {
  test::TempDir tmp;
  const std::string path = copy_previous_version_store(tmp);
  {
    Store store(path);
    EXPECT_EQ(store.schema_version(), k_store_schema_version);
    expect_previous_version_runs(store);
    EXPECT_EQ(migrated_events(store), 1);
    EXPECT_EQ(store.integrity_check(), "ok");
    // Run ids go on after the old ones, and the invariants of the schema hold on the migrated table.
    EXPECT_EQ(store.add_run(9, 1), 10);
    RunOutcome done;
    EXPECT_ANY_THROW(store.record_done(store.add_run(0, 2), done, {{"angle", 1.0}}));  // sample 0 is done
  }
  EXPECT_EQ(meta_value(path, "schema_version"), std::to_string(k_store_schema_version));
  {
    SQLite::Database db(path, SQLite::OPEN_READWRITE);
    // The CHECK constraints: only known names, and none for a run that did not fail.
    EXPECT_ANY_THROW(db.exec("UPDATE runs SET failure = 'bogus' WHERE id = 3"));
    EXPECT_ANY_THROW(db.exec("UPDATE runs SET failure = 'timeout' WHERE id = 1"));
    EXPECT_ANY_THROW(db.exec("UPDATE runs SET failure = '' WHERE id = 1"));
  }
  // A second open changes nothing.
  const std::string after_first = test::read_file(path);
  {
    Store again(path);
    EXPECT_EQ(again.schema_version(), k_store_schema_version);
    EXPECT_EQ(migrated_events(again), 1);
    EXPECT_EQ(again.runs().size(), 11u);
    EXPECT_EQ(again.run(3)->failure, FailureClass::liggghts_error);
    EXPECT_EQ(again.run(6)->failure, FailureClass::timeout);
  }
  EXPECT_EQ(test::read_file(path), after_first);
}

TEST(StoreSchema, Version1StoreWithAnUnknownFailureNameIsRefusedAndLeftAsItWas) {
  test::TempDir tmp;
  const std::string path = copy_previous_version_store(tmp);
  {
    SQLite::Database db(path, SQLite::OPEN_READWRITE);
    db.exec("UPDATE runs SET failure = 'gremlins' WHERE id = 3");
  }
  const std::string message = test::message_of<util::UserError>([&] { Store store(path); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("'gremlins'"), std::string::npos) << message;
  EXPECT_NE(message.find("liggghts-error"), std::string::npos) << message;  // lists the valid names
  EXPECT_EQ(meta_value(path, "schema_version"), "1");
  SQLite::Database db(path, SQLite::OPEN_READONLY);
  SQLite::Statement q(db, "SELECT failure FROM runs WHERE id = 3");
  ASSERT_TRUE(q.executeStep());
  EXPECT_EQ(q.getColumn(0).getString(), "gremlins");
}

TEST(StoreSchema, NewerSchemaVersionIsRefusedNamingTheFile) {
  test::TempDir tmp;
  const std::string path = (tmp / "study.db").string();
  { Store store(path); }
  {
    SQLite::Database db(path, SQLite::OPEN_READWRITE);
    SQLite::Statement q(db, "UPDATE meta SET value = ? WHERE key = 'schema_version'");
    q.bind(1, std::to_string(k_store_schema_version + 1));
    q.exec();
  }
  for (const bool read_only : {false, true}) {
    const std::string message = test::message_of<util::UserError>([&] {
      if (read_only)
        (void)Store::open_read_only(path);
      else
        Store store(path);
    });
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(fmt::format("schema version {}", k_store_schema_version + 1)), std::string::npos) << message;
    EXPECT_NE(message.find("newer demsa"), std::string::npos) << message;
  }
}

TEST(StoreSchema, EveryFailureClassIsStoredAndReadBack) {
  test::TempDir tmp;
  Store store((tmp / "study.db").string());
  store.initialize("h", "s", three_samples());
  // Every class after none (the enum is contiguous; to_string says "unknown" past its end): a class added without
  // a new schema version fails here, on the CHECK constraint of runs.failure.
  for (int i = 1; to_string(static_cast<FailureClass>(i)) != "unknown"; ++i) {
    const auto cls = static_cast<FailureClass>(i);
    RunOutcome outcome;
    outcome.failure = cls;
    const long run = store.add_run(0, i);
    ASSERT_NO_THROW(store.record_failed(run, outcome)) << to_string(cls);
    EXPECT_EQ(store.run(run)->failure, cls);
  }
  EXPECT_EQ(store.runs_in_state(RunState::failed).size(), 9u);
  const long run = store.add_run(1, 1);
  EXPECT_THROW(store.record_failed(run, RunOutcome{}), std::logic_error);  // failed needs a class
  RunOutcome timed_out;
  timed_out.failure = FailureClass::timeout;
  EXPECT_THROW(store.record_done(run, timed_out, {}), std::logic_error);  // done has none
  EXPECT_EQ(store.run(run)->state, RunState::submitted);
}

}  // namespace
}  // namespace demsa
