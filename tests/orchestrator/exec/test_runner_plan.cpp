// The study runner's Plan (exec/plan.hpp) on its own: what is started next, with which attempt number, and what
// becomes of a sample that was requeued, failed or done.
#include "orchestrator/exec/plan.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <vector>

namespace demsa {

using namespace demsa::study;
using namespace demsa::exec;
namespace {

/// The samples next() returns until the queue is empty, in order.
std::vector<int> drain(Plan& plan) {
  std::vector<int> samples;
  while (const std::optional<PlannedCase> next = plan.next()) samples.push_back(next->sample);
  return samples;
}

RunRow past_run(int sample, int attempt, RunState state) {
  RunRow row;
  row.sample = sample;
  row.attempt = attempt;
  row.state = state;
  return row;
}

TEST(RunnerPlan, QueuesTheSamplesInOrderWithFirstAttempts) {
  Plan plan(PlanOptions{.retries = 0, .collect_only = false});
  plan.queue_remaining({0, 1, 2});
  EXPECT_TRUE(plan.has_queued());
  for (int sample = 0; sample < 3; ++sample) {
    const std::optional<PlannedCase> next = plan.next();
    ASSERT_TRUE(next.has_value());
    EXPECT_EQ(next->sample, sample);
    EXPECT_EQ(next->attempt, 1);
  }
  EXPECT_FALSE(plan.next().has_value());
  EXPECT_FALSE(plan.has_queued());
}

TEST(RunnerPlan, RetriesAFailedSampleUpToTheBudgetThenGivesUp) {
  Plan plan(PlanOptions{.retries = 2, .collect_only = false});
  plan.queue_remaining({7});
  for (int attempt = 1; attempt <= 3; ++attempt) {
    const std::optional<PlannedCase> next = plan.next();
    ASSERT_TRUE(next.has_value());
    EXPECT_EQ(next->sample, 7);
    EXPECT_EQ(next->attempt, attempt);
    EXPECT_EQ(plan.retry_or_give_up(7, attempt, false), attempt < 3) << "attempt " << attempt;
  }
  EXPECT_FALSE(plan.has_queued());
  EXPECT_EQ(plan.failed_samples(), std::vector<int>{7});
  EXPECT_EQ(plan.failed_count(), 1);
}

TEST(RunnerPlan, NegativeRetriesGiveOneStart) {
  Plan plan(PlanOptions{.retries = -3, .collect_only = false});
  plan.queue_remaining({0});
  ASSERT_TRUE(plan.next().has_value());
  EXPECT_FALSE(plan.retry_or_give_up(0, 1, false));
  EXPECT_EQ(plan.failed_samples(), std::vector<int>{0});
}

TEST(RunnerPlan, StoppingGivesUpInsteadOfRetryingAndRequeuesNothing) {
  Plan plan(PlanOptions{.retries = 5, .collect_only = false});
  plan.queue_remaining({0, 1});
  ASSERT_EQ(drain(plan), (std::vector<int>{0, 1}));
  EXPECT_FALSE(plan.retry_or_give_up(0, 1, true));
  plan.requeue(1, true);
  EXPECT_FALSE(plan.has_queued());
  EXPECT_EQ(plan.failed_samples(), std::vector<int>{0});
}

TEST(RunnerPlan, ARequeuedSampleGoesFirstAndARetryGoesLast) {
  Plan plan(PlanOptions{.retries = 1, .collect_only = false});
  plan.queue_remaining({0, 1, 2, 3});
  ASSERT_EQ(plan.next()->sample, 0);
  ASSERT_EQ(plan.next()->sample, 1);
  EXPECT_TRUE(plan.retry_or_give_up(0, 1, false));  // failed: to the back
  plan.requeue(1, false);                           // cancelled: to the front
  EXPECT_EQ(drain(plan), (std::vector<int>{1, 2, 3, 0}));
  EXPECT_TRUE(plan.failed_samples().empty());
}

TEST(RunnerPlan, DoneSamplesNeverComeBack) {
  Plan plan(PlanOptions{.retries = 3, .collect_only = false});
  plan.add_past_run(past_run(1, 1, RunState::done));
  plan.queue_remaining({0, 1, 2});
  EXPECT_TRUE(plan.is_done(1));
  const std::optional<PlannedCase> first = plan.next();
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->sample, 0);
  plan.mark_done(0, first->attempt);
  // A done sample that is requeued or retried (cannot happen in a run, must not matter) is skipped.
  plan.requeue(0, false);
  plan.retry_or_give_up(1, 1, false);
  EXPECT_EQ(drain(plan), std::vector<int>{2});
  EXPECT_EQ(plan.done_count(), 2);
  EXPECT_TRUE(plan.failed_samples().empty());
}

TEST(RunnerPlan, AttemptsContinueTheStoreHistoryWithoutRequeuedRuns) {
  Plan plan(PlanOptions{.retries = 0, .collect_only = false});
  plan.add_past_run(past_run(0, 1, RunState::failed));
  plan.add_past_run(past_run(0, 2, RunState::failed));
  plan.add_past_run(past_run(1, 1, RunState::failed));
  plan.add_past_run(past_run(1, 2, RunState::requeued));
  plan.queue_remaining({0, 1, 2});
  const std::optional<PlannedCase> a = plan.next();
  const std::optional<PlannedCase> b = plan.next();
  const std::optional<PlannedCase> c = plan.next();
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(a->attempt, 3);
  EXPECT_EQ(b->attempt, 2);
  EXPECT_EQ(c->attempt, 1);
}

TEST(RunnerPlan, AdoptedAndLeftSubmittedSamplesAreNotQueued) {
  Plan plan(PlanOptions{.retries = 1, .collect_only = false});
  plan.add_past_run(past_run(0, 1, RunState::submitted));
  plan.add_past_run(past_run(2, 1, RunState::submitted));
  plan.adopt(0);
  plan.leave_submitted(2);
  plan.queue_remaining({0, 1, 2, 3});
  EXPECT_EQ(drain(plan), (std::vector<int>{1, 3}));
  EXPECT_EQ(plan.left_submitted_count(), 1);
  // The adopted run fails: its retry is the sample's next attempt.
  EXPECT_TRUE(plan.retry_or_give_up(0, 1, false));
  const std::optional<PlannedCase> retry = plan.next();
  ASSERT_TRUE(retry.has_value());
  EXPECT_EQ(retry->sample, 0);
  EXPECT_EQ(retry->attempt, 2);
}

TEST(RunnerPlan, CollectOnlyQueuesNothingRetriesNothingAndGivesUpNothing) {
  Plan plan(PlanOptions{.retries = 2, .collect_only = true});
  plan.add_past_run(past_run(0, 1, RunState::submitted));
  plan.add_past_run(past_run(1, 1, RunState::submitted));
  plan.adopt(0);
  plan.adopt(1);
  plan.queue_remaining({0, 1, 2, 3});
  EXPECT_FALSE(plan.has_queued());
  EXPECT_FALSE(plan.next().has_value());
  EXPECT_FALSE(plan.retry_or_give_up(0, 1, false));
  plan.requeue(1, false);
  EXPECT_FALSE(plan.has_queued());
  EXPECT_TRUE(plan.failed_samples().empty());
  plan.mark_done(1, 1);
  EXPECT_EQ(plan.done_count(), 1);
}

}  // namespace
}  // namespace demsa
