#pragma once
// What is left of a study in one `demsa run` (runner.hpp), in the shape of ninja's Plan (src/build.h): the samples
// to start, in order, and what became of those that ended. It knows nothing of executors, folders or the store: the
// runner tells it what the store holds, asks it what to start next, and tells it how each case ended.
//
//   queue: samples to start, front first. A case that was cancelled or lost goes back to the front (requeue); a
//          failed attempt with tries left goes to the back (retry_or_give_up).
//   attempts: the attempt number of the sample's latest run (in the store's history, runs that were requeued do
//          not count; in this invocation, every start does); the next start of the sample gets the next number.
//   budget: this invocation gives every sample 1 + retries starts; a sample that fails after the last of them (or
//          while the run is stopping) is failed for good.
//   done: samples with a committed result; they are never started again.
//   left submitted (submit_only): runs an earlier invocation left on the cluster; they stay out of the queue.
// collect_only (`demsa status`): nothing is queued, nothing is retried, nothing is given up.
#include "orchestrator/study/store.hpp"

#include <deque>
#include <map>
#include <optional>
#include <set>
#include <vector>

namespace demsa::exec {

struct RunQueueOptions {
  int retries = 0;            ///< starts per sample in this invocation beyond the first (< 0 counts as 0)
  bool collect_only = false;  ///< queue nothing, retry nothing: only commit what ends
};

/// One start of one sample.
struct QueuedCase {
  int sample = 0;
  int attempt = 1;  ///< 1 for the sample's first run, then one more per run that counted
};

class RunQueue {
 public:
  explicit RunQueue(const RunQueueOptions& options);

  /// A run of an earlier invocation, as the store holds it: done samples are done; every run that was not requeued
  /// numbers an attempt.
  void add_past_run(const study::RunRow& run);
  /// A run an earlier invocation left submitted that is followed again (adopted): kept out of the queue, it ends
  /// through mark_done / retry_or_give_up / requeue like any other.
  void adopt(int sample);
  /// submit_only: a run an earlier invocation left submitted stays on the cluster; kept out of the queue.
  void leave_submitted(int sample);
  /// Queues, in order, every sample of `samples` that is not done, adopted or left submitted (none when
  /// collect_only). Called once, after the history and the recovery.
  void queue_remaining(const std::vector<int>& samples);

  /// The next sample to start, with its attempt number, or nothing when the queue is empty. Done samples in the
  /// queue are skipped. Counts one start against the sample's budget.
  std::optional<QueuedCase> next();

  /// A case that was cancelled or lost (not the case's fault): it goes first, unless `stopping` or collect_only.
  void requeue(int sample, bool stopping);
  /// A failed attempt: back of the queue when the sample has starts left and the run is not `stopping`, failed for
  /// good otherwise. collect_only: neither (the next `demsa run` retries it). Returns whether it was queued.
  bool retry_or_give_up(int sample, int attempt, bool stopping);
  /// A failed attempt that a retry cannot change (FailureReport::final): failed now, whatever its budget left
  /// (collect_only: neither; the next `demsa run` decides).
  void give_up(int sample, int attempt);
  /// A committed result: the sample is done and never comes back.
  void mark_done(int sample, int attempt);

  bool has_queued() const { return !m_queue.empty(); }
  bool is_done(int sample) const { return m_done.count(sample) > 0; }
  int done_count() const { return static_cast<int>(m_done.size()); }
  /// Samples failed for good in this invocation (done ones excluded), ascending.
  std::vector<int> failed_samples() const;
  int failed_count() const { return static_cast<int>(m_failed.size()); }
  int left_submitted_count() const { return static_cast<int>(m_left_submitted.size()); }

 private:
  int m_budget;
  bool m_collect_only;
  std::deque<int> m_queue;
  std::map<int, int> m_attempts;  ///< sample -> attempt number of its latest run
  std::map<int, int> m_starts;    ///< sample -> starts in this invocation (next())
  std::set<int> m_done;
  std::set<int> m_failed;  ///< failed for good in this invocation
  std::set<int> m_adopted;
  std::set<int> m_left_submitted;
};

}  // namespace demsa::exec
