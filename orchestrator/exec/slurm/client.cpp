#include "orchestrator/exec/slurm/client.hpp"

#include "orchestrator/util/process.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace demsa::exec {

using namespace demsa::study;

namespace fs = std::filesystem;

using util::parse_long;
using util::trim;

namespace {

std::optional<double> parse_double(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  if (errno != 0 || end == text.c_str() || *end != '\0') return std::nullopt;
  return value;
}

// bash `times` prints durations as "1m2.345s".
std::optional<double> parse_bash_duration(const std::string& text) {
  const auto m = text.find('m');
  if (m == std::string::npos || text.empty() || text.back() != 's') return std::nullopt;
  const auto minutes = parse_double(text.substr(0, m));
  const auto seconds = parse_double(text.substr(m + 1, text.size() - m - 2));
  if (!minutes || !seconds) return std::nullopt;
  return *minutes * 60.0 + *seconds;
}

// sbatch file name patterns treat '%' as special; "%%" is a literal '%'.
std::string escape_percent(const std::string& text) {
  std::string out;
  for (const char c : text) {
    out += c;
    if (c == '%') out += '%';
  }
  return out;
}

/// Runs one SLURM program (util/process.hpp: stdin from /dev/null, in a process group of its own, so that a Ctrl-C
/// meant for demsa cannot kill an sbatch half-way and leave a job submitted whose id demsa never learns).
util::CaptureResult run_slurm(const std::vector<std::string>& argv, std::chrono::milliseconds timeout) {
  util::CaptureOptions options;
  options.timeout = timeout;
  return util::run_capture(argv, options);
}

/// What a failed SLURM program said, for an error message: its stderr, else its stdout, or that it was killed.
std::string complaint(const util::CaptureResult& r, std::chrono::milliseconds timeout) {
  if (r.timed_out) return fmt::format("killed after {} s", timeout.count() / 1000.0);
  return trim(r.err.empty() ? r.out : r.err);
}

}  // namespace

fs::path sentinel_dir(const fs::path& work_dir) { return work_dir / "sentinels"; }

fs::path sentinel_path(const fs::path& work_dir, const std::string& job, int task) {
  return sentinel_dir(work_dir) / fmt::format("{}_{}", job, task);
}

std::string render_batch_script(const ArraySubmission& submission) {
  assert(!submission.case_folders.empty());
  std::string s;
  s += "#!/bin/bash\n";
  s += "# demsa job array: task i runs ./run.sh in the i-th case folder (output to run.out there) and, when it\n";
  s += "# ends, writes its sentinel SENTINELS/JOB_TASK atomically: \"exit N\", or \"signal TERM\" when SLURM\n";
  s += "# stops it (scancel, time limit). The submitting options are on the sbatch command line.\n";
  s += "cases=(\n";
  for (const auto& folder : submission.case_folders) s += "  " + util::shell_quote(folder.string()) + "\n";
  s += ")\n";
  s += "sentinels=" + util::shell_quote(sentinel_dir(submission.work_dir).string()) + "\n";
  s += R"SH(task=${SLURM_ARRAY_TASK_ID:?not started as a SLURM array task}
case_dir=${cases[$task]}
sentinel="$sentinels/${SLURM_ARRAY_JOB_ID}_$task"
start=$(date +%s.%N)
child=
finish() {  # $1: "exit N" or "signal TERM"
  local end
  end=$(date +%s.%N)
  { echo "$1 host=${SLURMD_NODENAME:-$(hostname)} start=$start end=$end"; times; } > "$sentinel.tmp" \
    && mv -f "$sentinel.tmp" "$sentinel"
}
on_term() {
  [ -n "$child" ] && kill -TERM "$child" 2>/dev/null
  finish "signal TERM"
  exit 143
}
trap on_term TERM
if [ -z "$case_dir" ] || ! cd "$case_dir"; then
  echo "demsa: no case folder for array task $task" >&2
  finish "exit 126"
  exit 126
fi
# mpirun refuses to run as root unless told (a local test cluster runs everything as root)
if [ "$(id -u)" = 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
)SH";
  s += "# ---- prologue ([run.slurm] prologue)\n";
  if (!submission.settings.prologue.empty()) {
    s += submission.settings.prologue;
    if (submission.settings.prologue.back() != '\n') s += "\n";
  }
  s += R"SH(# ---- the case
./run.sh > run.out 2>&1 &
child=$!
wait "$child"
rc=$?
child=
finish "exit $rc"
exit "$rc"
)SH";
  return s;
}

std::vector<std::string> sbatch_arguments(const ArraySubmission& submission) {
  assert(!submission.case_folders.empty());
  assert(submission.ranks >= 1);
  const SlurmSettings& settings = submission.settings;
  std::string array = fmt::format("--array=0-{}", submission.case_folders.size() - 1);
  if (settings.throttle > 0) array += fmt::format("%{}", settings.throttle);
  std::vector<std::string> args{"--parsable",
                                array,
                                "--job-name=" + submission.job_name,
                                fmt::format("--ntasks={}", submission.ranks),
                                "--chdir=" + submission.work_dir.string(),
                                "--output=" + escape_percent((submission.work_dir / "logs").string()) + "/%A_%a.out"};
  if (!submission.comment.empty()) args.push_back("--comment=" + submission.comment);
  if (!settings.time_limit.empty()) args.push_back("--time=" + settings.time_limit);
  if (!settings.partition.empty()) args.push_back("--partition=" + settings.partition);
  if (!settings.account.empty()) args.push_back("--account=" + settings.account);
  // after ours, so that the user's options win where sbatch takes the last one
  for (const auto& option : settings.sbatch_options) args.push_back(option);
  return args;
}

std::optional<Sentinel> parse_sentinel(const std::string& text) {
  std::istringstream lines(text);
  std::string first;
  if (!std::getline(lines, first)) return std::nullopt;
  std::istringstream words(first);
  std::string kind;
  std::string value;
  words >> kind >> value;
  Sentinel sentinel;
  if (kind == "exit") {
    const auto code = parse_long(value);
    if (!code || *code < 0 || *code > 255) return std::nullopt;
    sentinel.exit_code = static_cast<int>(*code);
  } else if (kind == "signal") {
    if (value.empty()) return std::nullopt;
    sentinel.signalled = true;
  } else {
    return std::nullopt;
  }
  std::optional<double> start;
  std::optional<double> end;
  std::string word;
  while (words >> word) {
    const auto eq = word.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = word.substr(0, eq);
    const std::string val = word.substr(eq + 1);
    if (key == "host") sentinel.host = val;
    if (key == "start") start = parse_double(val);
    if (key == "end") end = parse_double(val);
  }
  if (start && end && *end >= *start) sentinel.wall_seconds = *end - *start;
  // bash `times`: the shell's own user/system time, then that of its children (run.sh and its descendants)
  std::string own;
  std::string children;
  if (std::getline(lines, own) && std::getline(lines, children)) {
    std::istringstream cw(children);
    std::string user;
    std::string system;
    cw >> user >> system;
    const auto u = parse_bash_duration(user);
    const auto sy = parse_bash_duration(system);
    if (u && sy) sentinel.cpu_seconds = *u + *sy;
  }
  return sentinel;
}

std::optional<Sentinel> read_sentinel(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_sentinel(ss.str());
}

bool is_terminal_state(const std::string& state) {
  static const std::vector<std::string> terminal{"COMPLETED",     "FAILED",      "CANCELLED", "TIMEOUT",
                                                 "NODE_FAIL",     "PREEMPTED",   "BOOT_FAIL", "DEADLINE",
                                                 "OUT_OF_MEMORY", "SPECIAL_EXIT"};
  for (const auto& t : terminal)
    if (state == t) return true;
  return false;
}

std::map<int, SqueueTask> parse_squeue(const std::string& text) {
  std::map<int, SqueueTask> tasks;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string id;
    std::string state;
    std::string code;
    if (!(words >> id >> state)) continue;
    words >> code;
    const auto task = parse_long(id);
    if (!task || *task < 0) continue;
    SqueueTask entry;
    entry.state = state;
    if (const auto status = parse_long(code)) entry.wait_status = static_cast<int>(*status);
    tasks[static_cast<int>(*task)] = entry;
  }
  return tasks;
}

std::map<std::string, std::vector<std::string>> parse_comment_lines(const std::string& text) {
  std::map<std::string, std::set<std::string>> found;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const std::string trimmed = trim(line);
    const auto space = trimmed.find_first_of(" \t");
    if (space == std::string::npos) continue;
    const std::string job = trimmed.substr(0, space);
    if (!parse_long(job) || job.front() == '-' || job.front() == '+') continue;
    found[trim(trimmed.substr(space))].insert(job);
  }
  std::map<std::string, std::vector<std::string>> jobs;
  for (const auto& [comment, ids] : found) {
    std::vector<std::string> sorted(ids.begin(), ids.end());
    std::sort(sorted.begin(), sorted.end(), [](const std::string& a, const std::string& b) {
      return a.size() != b.size() ? a.size() < b.size() : a < b;
    });
    jobs[comment] = std::move(sorted);
  }
  return jobs;
}

std::optional<std::string> parse_sbatch_job_id(const std::string& text) {
  const std::string line = trim(text.substr(0, text.find_first_of(";\n")));
  if (line.empty()) return std::nullopt;
  for (const char c : line)
    if (c < '0' || c > '9') return std::nullopt;
  return line;
}

SlurmClient::SlurmClient(SlurmCommands commands) : m_commands(std::move(commands)) {}

std::string SlurmClient::submit(const ArraySubmission& submission) const {
  if (submission.case_folders.empty()) throw std::invalid_argument("SlurmClient::submit: no case folders");
  fs::create_directories(submission.work_dir / "logs");
  fs::create_directories(sentinel_dir(submission.work_dir));

  // a new script per submission, never overwritten: it is what each task of that job reads
  const std::time_t now = std::time(nullptr);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::gmtime(&now));
  fs::path script;
  for (int n = 0;; ++n) {
    script = submission.work_dir / fmt::format("batch-{}-{}.sh", stamp, n);
    if (!fs::exists(script)) break;
  }
  {
    std::ofstream out(script);
    out << render_batch_script(submission);
    if (!out) throw std::runtime_error(fmt::format("cannot write the batch script {}", script.string()));
  }
  fs::permissions(script, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                  fs::perm_options::add);

  std::vector<std::string> argv{m_commands.sbatch};
  for (auto& a : sbatch_arguments(submission)) argv.push_back(std::move(a));
  argv.push_back(script.string());
  const util::CaptureResult r = run_slurm(argv, m_commands.timeout);
  if (r.exit_code != 0)
    throw std::runtime_error(fmt::format("sbatch failed (exit status {}) for {}: {}", r.exit_code, script.string(),
                                         complaint(r, m_commands.timeout)));
  const auto job = parse_sbatch_job_id(r.out);
  if (!job)
    throw std::runtime_error(
        fmt::format("sbatch printed no job id for {} (output: '{}')", script.string(), trim(r.out)));
  return *job;
}

SqueueResult SlurmClient::query(const std::string& job) const {
  const util::CaptureResult r =
      run_slurm({m_commands.squeue, "-h", "-r", "-t", "all", "-j", job, "-O", "ArrayTaskID:16,State:24,exit_code:16"},
                m_commands.timeout);
  SqueueResult result;
  if (r.exit_code != 0) {
    // the controller has forgotten the job (older than MinJobAge): it knows no task of it
    if (r.err.find("Invalid job id") != std::string::npos) {
      result.ok = true;
      return result;
    }
    result.error = fmt::format("squeue failed (exit status {}): {}", r.exit_code, complaint(r, m_commands.timeout));
    return result;
  }
  result.ok = true;
  result.tasks = parse_squeue(r.out);
  return result;
}

CommentLookup SlurmClient::jobs_by_comment() const {
  // %F: the array job id (also for each task of it), %k: the comment. Without -r a pending range is one line,
  // which is all that is needed here; -t all keeps the jobs that ended within MinJobAge.
  const util::CaptureResult r =
      run_slurm({m_commands.squeue, "-h", "-t", "all", "--me", "-o", "%F %k"}, m_commands.timeout);
  CommentLookup result;
  if (r.exit_code != 0) {
    result.error = fmt::format("squeue failed (exit status {}): {}", r.exit_code, complaint(r, m_commands.timeout));
    return result;
  }
  result.ok = true;
  result.jobs = parse_comment_lines(r.out);
  return result;
}

bool SlurmClient::cancel(const std::string& job, std::optional<int> task, std::string* error) const {
  const std::string target = task ? fmt::format("{}_{}", job, *task) : job;
  const util::CaptureResult r = run_slurm({m_commands.scancel, target}, m_commands.timeout);
  if (r.exit_code != 0 && error != nullptr)
    *error =
        fmt::format("scancel {} failed (exit status {}): {}", target, r.exit_code, complaint(r, m_commands.timeout));
  return r.exit_code == 0;
}

}  // namespace demsa::exec
