#include "orchestrator/exec/local_executor.hpp"

#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/process.hpp"

#include <signal.h>
#include <unistd.h>

#include <fmt/core.h>

#include <algorithm>
#include <stdexcept>
#include <thread>

namespace demsa::exec {

using namespace demsa::util;
using namespace demsa::study;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "localhost";
  return name;
}

}  // namespace

struct LocalExecutor::Child {
  Child(CaseTask task_, util::Child process_)
      : task(std::move(task_)), process(std::move(process_)), started(Clock::now()) {}
  CaseTask task;
  util::Child process;  ///< run.sh, leader of its process group
  Clock::time_point started;
  Clock::time_point term_sent;  ///< when SIGTERM went out (timeout or cancel)
  bool timed_out = false;
  bool cancelled = false;
  bool kill_sent = false;
};

void LocalExecutorOptions::validate() const {
  if (parallel < 1) throw std::invalid_argument(fmt::format("parallel = {}: must be >= 1", parallel));
  if (!(timeout >= 0)) throw std::invalid_argument(fmt::format("timeout = {}: must be >= 0", timeout));
  if (!(grace >= 0)) throw std::invalid_argument(fmt::format("grace = {}: must be >= 0", grace));
}

int machine_cores() { return std::max(1u, std::thread::hardware_concurrency()); }

int local_parallel(const RunSettings& run, int cores) {
  const int ranks = std::max(1, run.ranks);
  const int parallel = run.parallel > 0 ? run.parallel : std::max(1, cores / ranks);
  if (!run.oversubscribe && parallel * ranks > cores)
    throw UserError(
        fmt::format("[run] parallel = {} cases x ranks = {} needs {} cores, this machine has {}; lower them or set "
                    "oversubscribe = true",
                    parallel, ranks, parallel * ranks, cores));
  return parallel;
}

std::unique_ptr<Executor> make_local_executor(const RunSettings& run, const fs::path& /*study_dir*/) {
  LocalExecutorOptions options;
  options.parallel = local_parallel(run, machine_cores());
  options.timeout = run.timeout;
  return std::make_unique<LocalExecutor>(options);
}

LocalExecutor::LocalExecutor(LocalExecutorOptions options) : m_options(options), m_host(host_name()) {
  m_options.validate();
}

LocalExecutor::~LocalExecutor() {
  if (!m_children.empty()) cancel_all();
}

int LocalExecutor::free_slots() const { return std::max(0, m_options.parallel - static_cast<int>(m_children.size())); }

int LocalExecutor::in_flight() const { return static_cast<int>(m_children.size() + m_ready.size()); }

std::vector<std::string> LocalExecutor::submit(const std::vector<CaseTask>& tasks) {
  if (static_cast<int>(tasks.size()) > free_slots())
    throw std::logic_error(fmt::format("LocalExecutor::submit: {} tasks, {} free slots", tasks.size(), free_slots()));
  std::vector<std::string> ids;
  for (const CaseTask& task : tasks) {
    SpawnOptions options;
    options.output = task.folder / k_run_output_file;
    options.cwd = task.folder;
    auto child = std::make_unique<Child>(task, spawn({"./run.sh"}, options));
    ids.push_back(fmt::format("{}:{}", child->process.pid(), child->process.start_ticks()));
    m_children.push_back(std::move(child));
  }
  return ids;
}

bool end_leftover_group(const std::string& job_id, double grace) {
  const auto colon = job_id.find(':');
  if (colon == std::string::npos) return false;
  long pgid = 0;
  unsigned long long start = 0;
  try {
    pgid = std::stol(job_id.substr(0, colon));
    start = std::stoull(job_id.substr(colon + 1));
  } catch (const std::exception&) {
    return false;
  }
  return terminate_group(static_cast<int>(pgid), start, std::chrono::duration<double>(grace));
}

void LocalExecutor::adopt(const std::vector<SubmittedCase>& tasks) {
  for (const SubmittedCase& submitted : tasks) {
    const bool ended = end_leftover_group(submitted.job_id, m_options.grace);
    FinishedCase finished{submitted.task, {}};
    finished.exit.lost = true;
    finished.exit.host = m_host;
    finished.exit.detail = ended ? "left running by an earlier demsa; ended" : "not running any more";
    m_ready.push_back(std::move(finished));
  }
}

void LocalExecutor::enforce_timeouts() {
  const Clock::time_point now = Clock::now();
  for (auto& child : m_children) {
    const double age = std::chrono::duration<double>(now - child->started).count();
    if (m_options.timeout > 0 && age > m_options.timeout && !child->timed_out && !child->cancelled) {
      child->timed_out = true;
      child->term_sent = now;
      child->process.kill_group(SIGTERM);
    }
    if ((child->timed_out || child->cancelled) && !child->kill_sent &&
        std::chrono::duration<double>(now - child->term_sent).count() >= m_options.grace) {
      child->kill_sent = true;
      child->process.kill_group(SIGKILL);
    }
  }
}

void LocalExecutor::reap(std::vector<FinishedCase>& finished) {
  for (auto it = m_children.begin(); it != m_children.end();) {
    Child& child = **it;
    const std::optional<ChildExit> ended = child.process.try_wait();
    if (!ended) {
      ++it;
      continue;
    }
    FinishedCase done{child.task, {}};
    CaseExit& exit = done.exit;
    exit.wall_seconds = std::chrono::duration<double>(Clock::now() - child.started).count();
    exit.host = m_host;
    if (ended->error.empty()) {
      exit.cpu_seconds = ended->cpu_seconds;
      exit.exit_code = ended->exit_code;
      exit.signal = ended->signal;
    } else {
      exit.detail = ended->error;
    }
    if (child.timed_out || child.cancelled) {
      // Whatever the group leader did, ranks that outlive it are ended too.
      child.process.kill_group(SIGKILL);
      exit.timed_out = child.timed_out;
      exit.cancelled = child.cancelled && !child.timed_out;
      exit.exit_code = -1;
      exit.signal = 0;
    }
    finished.push_back(std::move(done));
    it = m_children.erase(it);
  }
}

std::vector<FinishedCase> LocalExecutor::poll(std::chrono::milliseconds wait) {
  std::vector<FinishedCase> finished = std::move(m_ready);
  m_ready.clear();
  const Clock::time_point deadline = Clock::now() + wait;
  while (true) {
    enforce_timeouts();
    reap(finished);
    if (!finished.empty() || m_children.empty() || Clock::now() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return finished;
}

void LocalExecutor::cancel_all() {
  const Clock::time_point now = Clock::now();
  for (auto& child : m_children) {
    if (child->cancelled || child->timed_out) continue;
    child->cancelled = true;
    child->term_sent = now;
    child->process.kill_group(SIGTERM);
  }
  std::vector<FinishedCase> finished;
  while (!m_children.empty()) {
    enforce_timeouts();
    reap(finished);
    if (!m_children.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  for (FinishedCase& f : finished) m_ready.push_back(std::move(f));
}

}  // namespace demsa::exec
