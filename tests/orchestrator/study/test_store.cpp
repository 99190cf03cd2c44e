#include "orchestrator/study/store.hpp"

#include "support/test_support.hpp"

#include <gtest/gtest.h>

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
  failed.failure = "timeout";
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
  EXPECT_EQ(store.runs_in_state(RunState::failed)[0].failure, "timeout");
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

}  // namespace
}  // namespace demsa
