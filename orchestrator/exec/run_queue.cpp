#include "orchestrator/exec/run_queue.hpp"

#include <algorithm>

namespace demsa::exec {

RunQueue::RunQueue(const RunQueueOptions& options)
    : m_budget(1 + std::max(0, options.retries)), m_collect_only(options.collect_only) {}

void RunQueue::add_past_run(const study::RunRow& run) {
  if (run.state == study::RunState::done) m_done.insert(run.sample);
  if (run.state != study::RunState::requeued) m_attempts[run.sample] = std::max(m_attempts[run.sample], run.attempt);
}

void RunQueue::adopt(int sample) { m_adopted.insert(sample); }

void RunQueue::leave_submitted(int sample) { m_left_submitted.insert(sample); }

void RunQueue::queue_remaining(const std::vector<int>& samples) {
  if (m_collect_only) return;
  for (int sample : samples)
    if (!m_done.count(sample) && !m_adopted.count(sample) && !m_left_submitted.count(sample)) m_queue.push_back(sample);
}

std::optional<QueuedCase> RunQueue::next() {
  while (!m_queue.empty()) {
    const int sample = m_queue.front();
    m_queue.pop_front();
    if (m_done.count(sample)) continue;
    const int attempt = ++m_attempts[sample];
    ++m_starts[sample];
    return QueuedCase{sample, attempt};
  }
  return std::nullopt;
}

void RunQueue::requeue(int sample, bool stopping) {
  // Not the case's fault: it runs again before the samples still waiting and before the retries of failed ones.
  if (!stopping && !m_collect_only) m_queue.push_front(sample);
}

bool RunQueue::retry_or_give_up(int sample, int attempt, bool stopping) {
  m_attempts[sample] = std::max(m_attempts[sample], attempt);
  if (m_collect_only) return false;
  if (m_starts[sample] < m_budget && !stopping) {
    m_queue.push_back(sample);
    return true;
  }
  m_failed.insert(sample);
  return false;
}

void RunQueue::give_up(int sample, int attempt) {
  m_attempts[sample] = std::max(m_attempts[sample], attempt);
  if (!m_collect_only) m_failed.insert(sample);
}

void RunQueue::mark_done(int sample, int attempt) {
  m_attempts[sample] = std::max(m_attempts[sample], attempt);
  m_done.insert(sample);
}

std::vector<int> RunQueue::failed_samples() const {
  std::vector<int> samples;
  for (int sample : m_failed)
    if (!m_done.count(sample)) samples.push_back(sample);
  return samples;
}

}  // namespace demsa::exec
