#include "orchestrator/exec/slurm/executor.hpp"

#include "orchestrator/exec/liggghts_locator.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <csignal>
#include <istream>
#include <limits>
#include <ostream>
#include <random>
#include <set>
#include <stdexcept>
#include <thread>

namespace demsa::exec {

using namespace demsa::util;
using namespace demsa::study;

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

void SlurmExecutorOptions::validate() const {
  auto fail = [](const std::string& field, const std::string& value, const std::string& rule) {
    throw std::invalid_argument(fmt::format("SlurmExecutorOptions.{} = {}: {}", field, value, rule));
  };
  if (query_interval.count() <= 0)
    fail("query_interval", std::to_string(query_interval.count()) + " ms", "must be > 0");
  if (sentinel_interval.count() <= 0)
    fail("sentinel_interval", std::to_string(sentinel_interval.count()) + " ms", "must be > 0");
  if (absent_confirmations < 1) fail("absent_confirmations", std::to_string(absent_confirmations), "must be >= 1");
  if (sentinel_grace.count() < 0)
    fail("sentinel_grace", std::to_string(sentinel_grace.count()) + " ms", "must be >= 0");
  if (squeue_outage_limit.count() <= 0)
    fail("squeue_outage_limit", std::to_string(squeue_outage_limit.count()) + " ms", "must be > 0");
  if (cancel_wait.count() < 0) fail("cancel_wait", std::to_string(cancel_wait.count()) + " ms", "must be >= 0");
  if (max_array_size < 1) fail("max_array_size", std::to_string(max_array_size), "must be >= 1");
  if (max_pack_size < 1) fail("max_pack_size", std::to_string(max_pack_size), "must be >= 1");
  if (settings.mode == SlurmMode::pack && !parse_slurm_time(settings.time_limit))
    fail("settings.time_limit", "\"" + settings.time_limit + "\"",
         "must be a SLURM time (MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM, D-HH:MM:SS) in pack mode");
  if (ranks < 1) fail("ranks", std::to_string(ranks), "must be >= 1");
  if (job_name.empty()) fail("job_name", "\"\"", "must not be empty");
  if (settings.throttle < 0) fail("settings.throttle", std::to_string(settings.throttle), "must be >= 0 (0 = none)");
  for (const auto& option : settings.sbatch_options)
    if (option.rfind("--comment", 0) == 0)
      fail("settings.sbatch_options", "\"" + option + "\"",
           "must not set --comment (demsa marks each submission with it, to find it again after a restart)");
}

SlurmExecutorOptions slurm_executor_options(const RunSettings& run, const fs::path& study_dir) {
  SlurmExecutorOptions options;
  options.settings = run.slurm;
  options.ranks = run.ranks;
  const double interval = run.slurm.poll_interval > 0 ? run.slurm.poll_interval : 5.0;
  options.query_interval = milliseconds(std::max<long>(1, static_cast<long>(interval * 1000.0)));
  options.sentinel_interval = std::min(options.query_interval, milliseconds(500));
  std::string name = fs::absolute(study_dir).lexically_normal().filename().string();
  if (name.empty()) name = fs::absolute(study_dir).lexically_normal().parent_path().filename().string();
  for (char& c : name)
    if (std::isspace(static_cast<unsigned char>(c))) c = '_';
  options.job_name = name.empty() ? "demsa" : "demsa-" + name;
  return options;
}

std::optional<std::pair<std::string, int>> parse_slurm_task_id(const std::string& id) {
  const auto underscore = id.find('_');
  if (underscore == std::string::npos || underscore == 0 || underscore + 1 >= id.size()) return std::nullopt;
  const std::string job = id.substr(0, underscore);
  const std::string task = id.substr(underscore + 1);
  auto digits = [](const std::string& s) {
    return std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!digits(job) || !digits(task) || task.size() > 9) return std::nullopt;
  return std::make_pair(job, std::stoi(task));
}

std::optional<PendingSlurmId> parse_pending_slurm_id(const std::string& id) {
  const std::string prefix = "pending:";
  if (id.rfind(prefix, 0) != 0) return std::nullopt;
  const auto colon = id.rfind(':');
  if (colon <= prefix.size()) return std::nullopt;
  const std::string token = id.substr(prefix.size(), colon - prefix.size());
  const std::string index = id.substr(colon + 1);
  if (index.empty() || index.size() > 9 ||
      !std::all_of(index.begin(), index.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  if (token.find_first_of(" \t\n:") != std::string::npos) return std::nullopt;
  return PendingSlurmId{token, std::stoi(index)};
}

std::string make_submission_token(double now) {
  std::random_device random;
  const auto seconds = static_cast<unsigned long long>(std::max(0.0, now));
  return fmt::format("{:x}-{:08x}", seconds, static_cast<unsigned>(random()));
}

std::optional<double> submission_token_time(const std::string& token) {
  const auto dash = token.find('-');
  if (dash == 0 || dash == std::string::npos || dash > 15) return std::nullopt;
  unsigned long long seconds = 0;
  for (size_t i = 0; i < dash; ++i) {
    const char c = static_cast<char>(std::tolower(static_cast<unsigned char>(token[i])));
    if (c >= '0' && c <= '9')
      seconds = seconds * 16 + static_cast<unsigned>(c - '0');
    else if (c >= 'a' && c <= 'f')
      seconds = seconds * 16 + static_cast<unsigned>(c - 'a' + 10);
    else
      return std::nullopt;
  }
  return static_cast<double>(seconds);
}

std::string submission_comment(const std::string& token) { return "demsa:" + token; }

namespace {
double unix_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
}  // namespace

SlurmExecutor::SlurmExecutor(SlurmExecutorOptions options, const fs::path& study_dir)
    : m_options(std::move(options)),
      m_client(m_options.commands),
      m_work_dir(fs::absolute(study_dir).lexically_normal() / "slurm") {
  m_options.validate();
}

int SlurmExecutor::free_slots() const {
  if (m_options.settings.mode != SlurmMode::pack) return m_options.max_array_size;
  // One allocation at a time: the next one (the cases that failed or were cancelled meanwhile, and those a restart
  // found missing) waits until nothing is in flight. Without a bound otherwise: submit() splits what it gets into
  // allocations of at most max_pack_size cases.
  return in_flight() > 0 ? 0 : std::numeric_limits<int>::max();
}

size_t SlurmExecutor::chunk_size() const {
  return static_cast<size_t>(m_options.settings.mode == SlurmMode::pack ? m_options.max_pack_size
                                                                        : m_options.max_array_size);
}

int SlurmExecutor::in_flight() const { return static_cast<int>(m_tasks.size() + m_ready.size()); }

std::vector<std::string> SlurmExecutor::reserve_ids(const std::vector<CaseTask>& tasks) {
  Reservation reservation;
  std::vector<std::string> ids;
  const size_t chunk = chunk_size();
  for (size_t begin = 0; begin < tasks.size(); begin += chunk) {
    const size_t end = std::min(tasks.size(), begin + chunk);
    std::string token = make_submission_token(unix_seconds());
    while (std::find(reservation.tokens.begin(), reservation.tokens.end(), token) != reservation.tokens.end())
      token = make_submission_token(unix_seconds());
    for (size_t i = begin; i < end; ++i) ids.push_back(fmt::format("pending:{}:{}", token, i - begin));
    reservation.tokens.push_back(std::move(token));
  }
  for (const auto& t : tasks) reservation.folders.push_back(fs::absolute(t.folder));
  m_reserved = std::move(reservation);
  return ids;
}

std::vector<std::string> SlurmExecutor::submit(const std::vector<CaseTask>& tasks) {
  // the tokens reserve_ids() gave out for exactly these tasks (the runner has stored them), or new ones
  std::vector<std::string> tokens;
  if (m_reserved) {
    std::vector<fs::path> folders;
    for (const auto& t : tasks) folders.push_back(fs::absolute(t.folder));
    if (folders == m_reserved->folders) tokens = m_reserved->tokens;
    m_reserved.reset();
  }
  std::vector<std::string> ids;
  std::vector<std::string> jobs;
  std::vector<Tracked> added;
  const size_t chunk = chunk_size();
  for (size_t begin = 0; begin < tasks.size(); begin += chunk) {
    const size_t end = std::min(tasks.size(), begin + chunk);
    SlurmSubmission submission;
    submission.work_dir = m_work_dir;
    submission.job_name = m_options.job_name;
    submission.ranks = m_options.ranks;
    submission.settings = m_options.settings;
    const size_t array = begin / chunk;
    submission.comment =
        submission_comment(array < tokens.size() ? tokens[array] : make_submission_token(unix_seconds()));
    for (size_t i = begin; i < end; ++i) submission.case_folders.push_back(fs::absolute(tasks[i].folder));
    const auto submitted_at = fs::file_time_type::clock::now();
    std::string job;
    try {
      job = m_client.submit(submission);
    } catch (const std::exception&) {
      // all or nothing: take back the arrays this call already submitted
      for (const auto& j : jobs) m_client.cancel(j);
      throw;
    }
    jobs.push_back(job);
    for (size_t i = begin; i < end; ++i) {
      const int index = static_cast<int>(i - begin);
      // A sentinel of the same name that is older than this submission belongs to an earlier SLURM instance
      // whose job ids started again at 1; it says nothing about this task.
      for (const fs::path& sentinel :
           {sentinel_path(m_work_dir, job, index), launch_failure_path(m_work_dir, job, index)}) {
        std::error_code ec;
        const auto written = fs::last_write_time(sentinel, ec);
        if (!ec && written < submitted_at - std::chrono::seconds(2)) fs::remove(sentinel, ec);
      }
      Tracked t;
      t.task = tasks[i];
      t.job = job;
      t.index = index;
      t.pack = m_options.settings.mode == SlurmMode::pack;
      added.push_back(t);
      ids.push_back(fmt::format("{}_{}", job, index));
    }
    if (m_options.settings.mode == SlurmMode::pack)
      util::log::info("slurm: submitted {} case(s) as pack allocation {} ({} at a time)", end - begin, job,
                      pack_parallel(submission));
    else
      util::log::info("slurm: submitted {} case(s) as array job {}", end - begin, job);
  }
  m_tasks.insert(m_tasks.end(), added.begin(), added.end());
  return ids;
}

void SlurmExecutor::adopt(const std::vector<SubmittedCase>& tasks) {
  for (const auto& submitted : tasks) {
    if (const auto pending = parse_pending_slurm_id(submitted.job_id)) {
      // demsa died inside submit(): the array may exist; squeue finds it by its comment (resolve_tokens)
      Tracked t;
      t.task = submitted.task;
      t.token = pending->token;
      t.index = pending->index;
      m_tasks.push_back(t);
      continue;
    }
    const auto id = parse_slurm_task_id(submitted.job_id);
    if (!id) {
      CaseExit exit;
      exit.lost = true;
      exit.detail = fmt::format("job id '{}' is not a SLURM array task (JOB_TASK): outcome unknown", submitted.job_id);
      m_ready.push_back({submitted.task, exit});
      continue;
    }
    Tracked t;
    t.task = submitted.task;
    t.job = id->first;
    t.index = id->second;
    m_tasks.push_back(t);
  }
}

std::vector<SubmittedCase> SlurmExecutor::take_learned_ids() {
  std::vector<SubmittedCase> learned = std::move(m_learned);
  m_learned.clear();
  return learned;
}

bool SlurmExecutor::resolve_tokens() {
  if (std::none_of(m_tasks.begin(), m_tasks.end(), [](const Tracked& t) { return t.job.empty(); })) return true;
  const CommentLookup lookup = m_client.jobs_by_comment();
  if (!lookup.ok) {
    m_last_query_error = lookup.error;
    return false;
  }
  for (auto& t : m_tasks) {
    if (!t.job.empty()) continue;
    const auto it = lookup.jobs.find(submission_comment(t.token));
    if (it == lookup.jobs.end() || it->second.empty()) {
      ++t.absent;
      continue;
    }
    if (it->second.size() > 1) {
      std::string all;
      for (const auto& job : it->second) all += (all.empty() ? "" : ", ") + job;
      util::log::warn("slurm: submission {} is in squeue as {} array jobs ({}); following the first", t.token,
                      it->second.size(), all);
    }
    t.job = it->second.front();
    t.absent = 0;
    // no log line: `demsa status --json` collects through here, and the runner records it in the event log
    m_learned.push_back({t.task, fmt::format("{}_{}", t.job, t.index)});
  }
  return true;
}

void SlurmExecutor::query_jobs() {
  bool failed = !resolve_tokens();
  std::set<std::string> jobs;
  for (const auto& t : m_tasks)
    if (!t.job.empty()) jobs.insert(t.job);
  for (const auto& job : jobs) {
    const SqueueResult result = m_client.query(job);
    if (!result.ok) {
      failed = true;
      m_last_query_error = result.error;
      continue;
    }
    for (auto& t : m_tasks) {
      if (t.job != job) continue;
      if (result.job) {  // a pack allocation: its one state is every case's
        t.pack = true;
        t.absent = 0;
        t.state = result.job->state;
        t.wait_status = result.job->wait_status;
        continue;
      }
      const auto it = result.tasks.find(t.index);
      if (it == result.tasks.end()) {
        ++t.absent;
      } else {
        t.absent = 0;
        t.state = it->second.state;
        t.wait_status = it->second.wait_status;
      }
    }
  }
  const auto now = Clock::now();
  m_last_query = now;
  if (!failed) {
    if (m_outage_since) util::log::info("slurm: squeue answers again");
    m_outage_since.reset();
    return;
  }
  if (!m_outage_since) {
    m_outage_since = now;
    util::log::warn("slurm: {} (retrying; sentinels are still collected)", m_last_query_error);
  }
  if (now - *m_outage_since >= m_options.squeue_outage_limit) {
    const double seconds = std::chrono::duration<double>(now - *m_outage_since).count();
    throw std::runtime_error(
        fmt::format("squeue has failed for {:.0f} s ({}); the {} task(s) in flight stay submitted: run `demsa run` or "
                    "`demsa status` again to collect them",
                    seconds, m_last_query_error, m_tasks.size()));
  }
}

std::optional<CaseExit> SlurmExecutor::decide(Tracked& t, Clock::time_point now,
                                              const std::set<std::string>& sentinels) const {
  CaseExit exit;
  if (t.job.empty()) {
    // Only the token is known. Not found: sbatch never created the job, or it ended longer ago than the
    // controller keeps jobs. Not before an sbatch started by the killed demsa must have ended, though: it runs in
    // a process group of its own and may still submit the array.
    const auto made = submission_token_time(t.token);
    const double age = made ? unix_seconds() - *made : std::numeric_limits<double>::infinity();
    const double sbatch_limit = std::chrono::duration<double>(m_options.commands.timeout).count();
    if (t.absent < m_options.absent_confirmations || age < sbatch_limit) return std::nullopt;
    exit.lost = true;
    exit.detail = fmt::format(
        "SLURM submission {} (task {}): no job with comment '{}' in squeue: sbatch never submitted it, or it ended "
        "before the controller's MinJobAge; it runs again",
        t.token, t.index, submission_comment(t.token));
    return exit;
  }
  const std::string where = fmt::format("SLURM task {}_{}", t.job, t.index);
  const fs::path file = sentinel_path(m_work_dir, t.job, t.index);
  std::optional<Sentinel> sentinel;
  if (sentinels.count(file.filename().string())) sentinel = read_sentinel(file);
  if (sentinel) {
    exit.host = sentinel->host;
    exit.wall_seconds = sentinel->wall_seconds;
    exit.cpu_seconds = sentinel->cpu_seconds;
    if (sentinel->timed_out) {
      exit.timed_out = true;
      exit.detail = fmt::format("{}: stopped at its time limit ({})", where, m_options.settings.time_limit);
      return exit;
    }
    if (!sentinel->signalled) {
      exit.exit_code = sentinel->exit_code;
      exit.detail = fmt::format("{}: run.sh exited with status {}", where, sentinel->exit_code);
      return exit;
    }
    // SIGTERM: squeue's state says whether it was the time limit or a cancellation
    if (t.state == "TIMEOUT") {
      exit.timed_out = true;
      exit.detail = fmt::format("{}: stopped at the time limit ({})", where, m_options.settings.time_limit);
      return exit;
    }
    if (t.state == "CANCELLED" || t.cancel_requested || t.absent >= m_options.absent_confirmations) {
      exit.cancelled = true;
      exit.detail = fmt::format("{}: cancelled (scancel)", where);
      return exit;
    }
    if (!t.signalled_since) t.signalled_since = now;
    if (is_terminal_state(t.state) || now - *t.signalled_since >= m_options.sentinel_grace) {
      exit.signal = SIGTERM;
      exit.detail = fmt::format("{}: ended by SIGTERM (SLURM state {})", where, t.state.empty() ? "?" : t.state);
      return exit;
    }
    return std::nullopt;
  }
  if (t.pack || sentinels.count(launch_failure_path(m_work_dir, t.job, t.index).filename().string()))
    return decide_pack(t, now, sentinels);

  if (t.absent >= m_options.absent_confirmations) {
    if (t.cancel_requested) {
      exit.cancelled = true;
      exit.detail = fmt::format("{}: cancelled (scancel) before it wrote a sentinel", where);
    } else {
      exit.lost = true;
      exit.detail = fmt::format(
          "{}: gone from squeue and no sentinel (cancelled while pending, or purged by the controller)", where);
    }
    return exit;
  }
  if (!is_terminal_state(t.state)) return std::nullopt;

  const std::string state = t.state;
  if (state == "TIMEOUT") {
    exit.timed_out = true;
    exit.detail = fmt::format("{}: TIMEOUT at the time limit ({})", where, m_options.settings.time_limit);
    return exit;
  }
  if (state == "CANCELLED" || (t.cancel_requested && state != "COMPLETED")) {
    exit.cancelled = true;
    exit.detail = fmt::format("{}: {} (scancel)", where, state);
    return exit;
  }
  if (state == "NODE_FAIL" || state == "PREEMPTED" || state == "BOOT_FAIL" || state == "DEADLINE") {
    exit.lost = true;
    exit.detail = fmt::format("{}: {} (not the case's fault: it runs again)", where, state);
    return exit;
  }
  if (state == "OUT_OF_MEMORY") {
    exit.signal = SIGKILL;
    exit.detail = fmt::format("{}: OUT_OF_MEMORY (killed by SLURM)", where);
    return exit;
  }
  // COMPLETED, FAILED, SPECIAL_EXIT: the sentinel should be there; a shared filesystem may show it late
  if (!t.final_since) t.final_since = now;
  if (now - *t.final_since < m_options.sentinel_grace) return std::nullopt;
  const int status = t.wait_status;
  if ((status & 0x7f) != 0)
    exit.signal = status & 0x7f;
  else
    exit.exit_code = (status >> 8) & 0xff;
  exit.detail = fmt::format("{}: {} with wait status {}, but it wrote no sentinel ({})", where, state, status,
                            sentinel_path(m_work_dir, t.job, t.index).string());
  return exit;
}

std::optional<CaseExit> SlurmExecutor::decide_pack(Tracked& t, Clock::time_point now,
                                                   const std::set<std::string>& sentinels) const {
  CaseExit exit;
  const std::string where = fmt::format("SLURM pack allocation {}, case {}", t.job, t.index);
  // srun failed before the step wrote a sentinel: the step's own sentinel may still show up late on a shared
  // filesystem, so the driver's word counts only after the grace period.
  const fs::path launch = launch_failure_path(m_work_dir, t.job, t.index);
  if (sentinels.count(launch.filename().string())) {
    if (!t.launch_failed_since) t.launch_failed_since = now;
    if (now - *t.launch_failed_since >= m_options.sentinel_grace) {
      if (const auto failed = read_sentinel(launch); failed && !failed->signalled && !failed->timed_out) {
        exit.exit_code = failed->exit_code;
        exit.host = failed->host;
        exit.detail = fmt::format("{}: srun ended with status {} without starting the case (see {})", where,
                                  failed->exit_code, (m_work_dir / "logs" / (t.job + ".out")).string());
        return exit;
      }
    }
  }
  if (t.absent >= m_options.absent_confirmations) {
    exit.cancelled = t.cancel_requested;
    exit.lost = !t.cancel_requested;
    exit.detail = fmt::format("{}: gone from squeue and no sentinel ({}); it runs again", where,
                              t.cancel_requested ? "cancelled (scancel)" : "purged by the controller, or cancelled");
    return exit;
  }
  if (!is_terminal_state(t.state)) return std::nullopt;
  const std::string& state = t.state;
  if (state == "CANCELLED" || t.cancel_requested) {
    exit.cancelled = true;
    exit.detail = fmt::format("{}: allocation {} before the case wrote a sentinel (scancel)", where, state);
    return exit;
  }
  if (state == "TIMEOUT" || state == "NODE_FAIL" || state == "PREEMPTED" || state == "BOOT_FAIL" ||
      state == "DEADLINE") {
    exit.lost = true;
    exit.detail = fmt::format("{}: the allocation ended ({}) before the case started; it runs again", where, state);
    return exit;
  }
  // COMPLETED, FAILED, OUT_OF_MEMORY, SPECIAL_EXIT: the driver ended; a shared filesystem may show the sentinel late
  if (!t.final_since) t.final_since = now;
  if (now - *t.final_since < m_options.sentinel_grace) return std::nullopt;
  const int status = t.wait_status;
  if ((status & 0x7f) != 0)
    exit.signal = status & 0x7f;
  else
    exit.exit_code = (status >> 8) & 0xff;
  exit.detail = fmt::format("{}: the allocation ended ({}, wait status {}) without the case's sentinel ({}); see {}",
                            where, state, status, sentinel_path(m_work_dir, t.job, t.index).string(),
                            (m_work_dir / "logs" / (t.job + ".out")).string());
  return exit;
}

std::vector<FinishedCase> SlurmExecutor::sweep(bool force_query) {
  std::vector<FinishedCase> out;
  if (m_tasks.empty()) return out;
  const auto now = Clock::now();
  // squeue is asked every query_interval, and sooner while a "signal TERM" sentinel waits for its final state
  const bool waiting_for_state =
      std::any_of(m_tasks.begin(), m_tasks.end(), [](const Tracked& t) { return t.signalled_since.has_value(); });
  const bool due = !m_last_query || now - *m_last_query >= m_options.query_interval ||
                   (waiting_for_state && now - *m_last_query >= m_options.sentinel_interval);
  if (force_query || due) query_jobs();
  // One directory listing per sweep (after squeue, so that a task squeue no longer shows has had its chance to
  // write its sentinel), instead of one open() per task in flight: cheap on a network filesystem.
  std::set<std::string> sentinels;
  std::error_code ec;
  for (fs::directory_iterator it(sentinel_dir(m_work_dir), ec), end; !ec && it != end; it.increment(ec))
    sentinels.insert(it->path().filename().string());
  for (auto& t : m_tasks) {
    if (auto exit = decide(t, now, sentinels)) {
      out.push_back({t.task, *exit});
      t.index = -1;  // marks it done
    }
  }
  m_tasks.erase(std::remove_if(m_tasks.begin(), m_tasks.end(), [](const Tracked& t) { return t.index < 0; }),
                m_tasks.end());
  return out;
}

std::vector<FinishedCase> SlurmExecutor::poll(milliseconds wait) {
  std::vector<FinishedCase> out = std::move(m_ready);
  m_ready.clear();
  const auto deadline = Clock::now() + wait;
  for (;;) {
    auto ended = sweep(false);
    out.insert(out.end(), ended.begin(), ended.end());
    const auto now = Clock::now();
    if (!out.empty() || m_tasks.empty() || now >= deadline) return out;
    std::this_thread::sleep_for(
        std::min<milliseconds>(m_options.sentinel_interval, std::chrono::ceil<milliseconds>(deadline - now)));
  }
}

void SlurmExecutor::cancel_all() {
  // adopted tasks known only by their token: find their job first
  std::vector<Tracked> unfound;
  if (resolve_tokens()) {
    for (const auto& t : m_tasks) {
      if (!t.job.empty()) continue;
      CaseExit exit;
      exit.cancelled = true;
      exit.detail = fmt::format("SLURM submission {} (task {}): not in squeue, nothing to cancel", t.token, t.index);
      m_ready.push_back({t.task, exit});
    }
  } else {
    util::log::warn("slurm: {}; {} adopted task(s) without a job id cannot be cancelled and stay submitted",
                    m_last_query_error,
                    std::count_if(m_tasks.begin(), m_tasks.end(), [](const Tracked& t) { return t.job.empty(); }));
    for (const auto& t : m_tasks)
      if (t.job.empty()) unfound.push_back(t);
  }
  m_tasks.erase(std::remove_if(m_tasks.begin(), m_tasks.end(), [](const Tracked& t) { return t.job.empty(); }),
                m_tasks.end());
  std::set<std::string> jobs;
  for (auto& t : m_tasks) {
    t.cancel_requested = true;
    jobs.insert(t.job);
  }
  for (const auto& job : jobs) {
    std::string error;
    if (!m_client.cancel(job, std::nullopt, &error)) util::log::warn("slurm: {}", error);
  }
  const auto deadline = Clock::now() + m_options.cancel_wait;
  while (!m_tasks.empty()) {
    auto ended = sweep(true);
    m_ready.insert(m_ready.end(), ended.begin(), ended.end());
    if (m_tasks.empty() || Clock::now() >= deadline) break;
    std::this_thread::sleep_for(std::min<milliseconds>(m_options.sentinel_interval, milliseconds(200)));
  }
  for (const auto& t : m_tasks) {
    CaseExit exit;
    exit.cancelled = true;
    exit.detail = fmt::format("SLURM task {}_{}: scancel sent, its end was not seen within {} s", t.job, t.index,
                              m_options.cancel_wait.count() / 1000.0);
    m_ready.push_back({t.task, exit});
  }
  m_tasks = std::move(unfound);
}

std::unique_ptr<Executor> make_slurm_executor(const RunSettings& run, const fs::path& study_dir) {
  SlurmExecutorOptions options = slurm_executor_options(run, study_dir);
  if (!find_on_path(options.commands.sbatch))
    throw UserError(
        "[run] executor = \"slurm\", but `sbatch` is not on PATH: run demsa on a SLURM login node (or use "
        "executor = \"local\")");
  if (run.ranks < 1) throw UserError(fmt::format("[run] ranks = {}: must be >= 1", run.ranks));
  for (const auto& option : run.slurm.sbatch_options)
    if (option.rfind("--comment", 0) == 0)
      throw UserError(fmt::format(
          "[run.slurm] sbatch_options: \"{}\": demsa sets --comment itself (it marks each submission with it, so "
          "that a restarted demsa finds the array job again); remove it",
          option));
  if (run.slurm.throttle < 0)
    throw UserError(fmt::format("[run.slurm] throttle = {}: must be >= 0 (0 = no throttle)", run.slurm.throttle));
  if (run.slurm.mode == SlurmMode::pack && !parse_slurm_time(run.slurm.time_limit))
    throw UserError(fmt::format(
        "[run.slurm] time_limit = \"{}\": pack mode needs a SLURM time (MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM or "
        "D-HH:MM:SS; empty or UNLIMITED for none): it stops each case at it and sizes the allocation from it",
        run.slurm.time_limit));
  if (!(run.slurm.poll_interval > 0))
    throw UserError(fmt::format("[run.slurm] poll_interval = {}: must be > 0 seconds", run.slurm.poll_interval));
  return std::make_unique<SlurmExecutor>(std::move(options), study_dir);
}

bool ask_cancel_on_interrupt(int in_flight, std::istream& answer, std::ostream& prompt) {
  prompt << "\n"
         << in_flight
         << " SLURM task(s) are still queued or running. Cancel them with scancel? [y/N] (no: they keep running, "
            "and a later `demsa run` or `demsa status` collects them) ";
  prompt.flush();
  std::string line;
  if (!std::getline(answer, line)) return false;
  std::string word;
  for (const char c : line)
    if (!std::isspace(static_cast<unsigned char>(c)))
      word += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return word == "y" || word == "yes";
}

}  // namespace demsa::exec
