// The study runner's RunQueue (exec/run_queue.hpp) on its own: what is started next, with which attempt number, and
// what becomes of a sample that was requeued, failed or done.
#include "orchestrator/exec/run_queue.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <vector>

namespace demsa {

using namespace demsa::study;
using namespace demsa::exec;
namespace {

/// The samples next() returns until the queue is empty, in order.
std::vector<int> drain(RunQueue& queue) {
  std::vector<int> samples;
  while (const std::optional<QueuedCase> next = queue.next()) samples.push_back(next->sample);
  return samples;
}

RunRow past_run(int sample, int attempt, RunState state) {
  RunRow row;
  row.sample = sample;
  row.attempt = attempt;
  row.state = state;
  return row;
}

TEST(RunQueue, QueuesTheSamplesInOrderWithFirstAttempts) {
  RunQueue queue(RunQueueOptions{.retries = 0, .collect_only = false});
  queue.queue_remaining({0, 1, 2});
  EXPECT_TRUE(queue.has_queued());
  for (int sample = 0; sample < 3; ++sample) {
    const std::optional<QueuedCase> next = queue.next();
    ASSERT_TRUE(next.has_value());
    EXPECT_EQ(next->sample, sample);
    EXPECT_EQ(next->attempt, 1);
  }
  EXPECT_FALSE(queue.next().has_value());
  EXPECT_FALSE(queue.has_queued());
}

TEST(RunQueue, RetriesAFailedSampleUpToTheBudgetThenGivesUp) {
  RunQueue queue(RunQueueOptions{.retries = 2, .collect_only = false});
  queue.queue_remaining({7});
  for (int attempt = 1; attempt <= 3; ++attempt) {
    const std::optional<QueuedCase> next = queue.next();
    ASSERT_TRUE(next.has_value());
    EXPECT_EQ(next->sample, 7);
    EXPECT_EQ(next->attempt, attempt);
    EXPECT_EQ(queue.retry_or_give_up(7, attempt, false), attempt < 3) << "attempt " << attempt;
  }
  EXPECT_FALSE(queue.has_queued());
  EXPECT_EQ(queue.failed_samples(), std::vector<int>{7});
  EXPECT_EQ(queue.failed_count(), 1);
}

TEST(RunQueue, NegativeRetriesGiveOneStart) {
  RunQueue queue(RunQueueOptions{.retries = -3, .collect_only = false});
  queue.queue_remaining({0});
  ASSERT_TRUE(queue.next().has_value());
  EXPECT_FALSE(queue.retry_or_give_up(0, 1, false));
  EXPECT_EQ(queue.failed_samples(), std::vector<int>{0});
}

TEST(RunQueue, StoppingGivesUpInsteadOfRetryingAndRequeuesNothing) {
  RunQueue queue(RunQueueOptions{.retries = 5, .collect_only = false});
  queue.queue_remaining({0, 1});
  ASSERT_EQ(drain(queue), (std::vector<int>{0, 1}));
  EXPECT_FALSE(queue.retry_or_give_up(0, 1, true));
  queue.requeue(1, true);
  EXPECT_FALSE(queue.has_queued());
  EXPECT_EQ(queue.failed_samples(), std::vector<int>{0});
}

TEST(RunQueue, ARequeuedSampleGoesFirstAndARetryGoesLast) {
  RunQueue queue(RunQueueOptions{.retries = 1, .collect_only = false});
  queue.queue_remaining({0, 1, 2, 3});
  ASSERT_EQ(queue.next()->sample, 0);
  ASSERT_EQ(queue.next()->sample, 1);
  EXPECT_TRUE(queue.retry_or_give_up(0, 1, false));  // failed: to the back
  queue.requeue(1, false);                           // cancelled: to the front
  EXPECT_EQ(drain(queue), (std::vector<int>{1, 2, 3, 0}));
  EXPECT_TRUE(queue.failed_samples().empty());
}

TEST(RunQueue, DoneSamplesNeverComeBack) {
  RunQueue queue(RunQueueOptions{.retries = 3, .collect_only = false});
  queue.add_past_run(past_run(1, 1, RunState::done));
  queue.queue_remaining({0, 1, 2});
  EXPECT_TRUE(queue.is_done(1));
  const std::optional<QueuedCase> first = queue.next();
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->sample, 0);
  queue.mark_done(0, first->attempt);
  // A done sample that is requeued or retried (cannot happen in a run, must not matter) is skipped.
  queue.requeue(0, false);
  queue.retry_or_give_up(1, 1, false);
  EXPECT_EQ(drain(queue), std::vector<int>{2});
  EXPECT_EQ(queue.done_count(), 2);
  EXPECT_TRUE(queue.failed_samples().empty());
}

TEST(RunQueue, AttemptsContinueTheStoreHistoryWithoutRequeuedRuns) {
  RunQueue queue(RunQueueOptions{.retries = 0, .collect_only = false});
  queue.add_past_run(past_run(0, 1, RunState::failed));
  queue.add_past_run(past_run(0, 2, RunState::failed));
  queue.add_past_run(past_run(1, 1, RunState::failed));
  queue.add_past_run(past_run(1, 2, RunState::requeued));
  queue.queue_remaining({0, 1, 2});
  const std::optional<QueuedCase> a = queue.next();
  const std::optional<QueuedCase> b = queue.next();
  const std::optional<QueuedCase> c = queue.next();
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(a->attempt, 3);
  EXPECT_EQ(b->attempt, 2);
  EXPECT_EQ(c->attempt, 1);
}

TEST(RunQueue, AdoptedAndLeftSubmittedSamplesAreNotQueued) {
  RunQueue queue(RunQueueOptions{.retries = 1, .collect_only = false});
  queue.add_past_run(past_run(0, 1, RunState::submitted));
  queue.add_past_run(past_run(2, 1, RunState::submitted));
  queue.adopt(0);
  queue.leave_submitted(2);
  queue.queue_remaining({0, 1, 2, 3});
  EXPECT_EQ(drain(queue), (std::vector<int>{1, 3}));
  EXPECT_EQ(queue.left_submitted_count(), 1);
  // The adopted run fails: its retry is the sample's next attempt.
  EXPECT_TRUE(queue.retry_or_give_up(0, 1, false));
  const std::optional<QueuedCase> retry = queue.next();
  ASSERT_TRUE(retry.has_value());
  EXPECT_EQ(retry->sample, 0);
  EXPECT_EQ(retry->attempt, 2);
}

TEST(RunQueue, CollectOnlyQueuesNothingRetriesNothingAndGivesUpNothing) {
  RunQueue queue(RunQueueOptions{.retries = 2, .collect_only = true});
  queue.add_past_run(past_run(0, 1, RunState::submitted));
  queue.add_past_run(past_run(1, 1, RunState::submitted));
  queue.adopt(0);
  queue.adopt(1);
  queue.queue_remaining({0, 1, 2, 3});
  EXPECT_FALSE(queue.has_queued());
  EXPECT_FALSE(queue.next().has_value());
  EXPECT_FALSE(queue.retry_or_give_up(0, 1, false));
  queue.requeue(1, false);
  EXPECT_FALSE(queue.has_queued());
  EXPECT_TRUE(queue.failed_samples().empty());
  queue.mark_done(1, 1);
  EXPECT_EQ(queue.done_count(), 1);
}

}  // namespace
}  // namespace demsa
