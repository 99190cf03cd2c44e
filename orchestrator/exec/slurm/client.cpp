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

fs::path launch_failure_path(const fs::path& work_dir, const std::string& job, int task) {
  return sentinel_dir(work_dir) / fmt::format("{}_{}.srun", job, task);
}

namespace {

/// The bash lines both scripts begin with: the array of case folders and the sentinel folder, quoted.
std::string case_list_lines(const SlurmSubmission& submission) {
  std::string s = "cases=(\n";
  for (const auto& folder : submission.case_folders) s += "  " + util::shell_quote(folder.string()) + "\n";
  s += ")\n";
  s += "sentinels=" + util::shell_quote(sentinel_dir(submission.work_dir).string()) + "\n";
  return s;
}

/// The user's [run.slurm] prologue under its heading comment, ending in a newline.
std::string prologue_lines(const SlurmSubmission& submission, std::string_view note) {
  const std::string& prologue = submission.settings.prologue;
  std::string s = fmt::format("# ---- prologue ([run.slurm] prologue){}\n", note);
  if (!prologue.empty()) {
    s += prologue;
    if (prologue.back() != '\n') s += "\n";
  }
  return s;
}

}  // namespace

std::string render_batch_script(const SlurmSubmission& submission) {
  assert(!submission.case_folders.empty());
  std::string s;
  s += "#!/bin/bash\n";
  s += "# demsa job array: task i runs ./run.sh in the i-th case folder (output to run.out there) and, when it\n";
  s += "# ends, writes its sentinel SENTINELS/JOB_TASK atomically: \"exit N\", or \"signal TERM\" when SLURM\n";
  s += "# stops it (scancel, time limit). The submitting options are on the sbatch command line.\n";
  s += case_list_lines(submission);
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
  s += prologue_lines(submission, "");
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

std::string render_pack_script(const SlurmSubmission& submission) {
  assert(!submission.case_folders.empty());
  assert(submission.ranks >= 1);
  const long limit = parse_slurm_time(submission.settings.time_limit).value_or(0);
  std::string s;
  s += "#!/bin/bash\n";
  s += "# demsa pack: this allocation runs the cases below as job steps, at most PARALLEL at a time. Case i runs\n";
  s += "# ./run.sh in its folder (output to run.out there) and, when it ends, writes its sentinel SENTINELS/JOB_i\n";
  s += "# atomically: \"exit N\", \"timeout\" (stopped at the time limit), or \"signal TERM\" when SLURM stops it\n";
  s += "# (scancel, the allocation's end). The submitting options are on the sbatch command line.\n";
  s += case_list_lines(submission);
  s += fmt::format("ranks={}\nparallel={}\ncase_seconds={}  # [run.slurm] time_limit per case; 0 = none\n",
                   submission.ranks, pack_parallel(submission), limit);
  s += R"SH(job=${SLURM_JOB_ID:?not started by sbatch}
# One case, run by each task of its job step: $1 case folder, $2 sentinel, $3 time limit [s] (0 = none).
step=$(cat <<'STEP'
# Task 0 runs the case; mpirun inside run.sh starts the ranks on the CPUs of this step. The other tasks only hold
# their CPUs (srun --wait=0 lets task 0 run on after they end).
[ "${SLURM_PROCID:-0}" = 0 ] || exit 0
case_dir=$1 sentinel=$2 limit=$3
start=$(date +%s.%N)
child= timer=
finish() {  # $1: "exit N", "timeout" or "signal TERM"
  local end
  end=$(date +%s.%N)
  { echo "$1 host=${SLURMD_NODENAME:-$(hostname)} start=$start end=$end"; times; } > "$sentinel.tmp" \
    && mv -f "$sentinel.tmp" "$sentinel"
}
on_term() {
  [ -n "$child" ] && kill -TERM "$child" 2>/dev/null
  [ -n "$timer" ] && kill "$timer" 2>/dev/null
  finish "signal TERM"
  exit 143
}
trap on_term TERM
if ! cd "$case_dir"; then
  echo "demsa: no case folder $case_dir" >&2
  finish "exit 126"
  exit 126
fi
./run.sh > run.out 2>&1 &
child=$!
if [ "$limit" -gt 0 ]; then
  sleep "$limit" &
  timer=$!
  wait -n  # the case or the time limit, whichever ends first
  rc=$?
  if kill -0 "$child" 2>/dev/null; then  # the time limit: SIGTERM, SIGKILL 30 s later if it is still there
    kill -TERM "$child" 2>/dev/null
    for _ in $(seq 300); do kill -0 "$child" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$child" 2>/dev/null
    wait "$child"
    child= timer=
    finish timeout
    exit 124
  fi
  kill "$timer" 2>/dev/null
  # the case's own status (bash keeps it for wait PID; 127: this bash no longer has it, keep the one wait -n gave)
  wait "$child"
  r=$?
  [ "$r" = 127 ] || rc=$r
else
  wait "$child"
  rc=$?
fi
child= timer=
finish "exit $rc"
exit "$rc"
STEP
)
stopping=
trap 'stopping=1' TERM
# mpirun refuses to run as root unless told (a local test cluster runs everything as root)
if [ "$(id -u)" = 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
)SH";
  s += prologue_lines(submission, ", once for every case");
  s += R"SH(# ---- the cases
launch() {  # $1: case index
  local i=$1 sentinel="$sentinels/${job}_$1" rc started ended
  started=$(date +%s.%N)
  srun --exclusive --wait=0 --nodes=1 --ntasks="$ranks" --cpus-per-task=1 --job-name="case-$i" \
    bash -c "$step" demsa-case "${cases[$i]}" "$sentinel" "$case_seconds"
  rc=$?
  ended=$(date +%s.%N)
  if [ "$rc" != 0 ] && [ ! -e "$sentinel" ]; then
    echo "demsa: srun ended with status $rc before case $i (${cases[$i]}) wrote its sentinel" >&2
    echo "exit $rc host=${SLURMD_NODENAME:-$(hostname)} start=$started end=$ended" > "$sentinel.srun.tmp" \
      && mv -f "$sentinel.srun.tmp" "$sentinel.srun"
  fi
}
for ((i = 0; i < ${#cases[@]}; i++)); do
  while [ -z "$stopping" ] && [ "$(jobs -rp | wc -l)" -ge "$parallel" ]; do wait -n; done
  [ -n "$stopping" ] && break
  launch "$i" &
done
# a signal interrupts wait: wait again until every step has ended
while [ -n "$(jobs -rp)" ]; do wait; done
[ -z "$stopping" ] || exit 143
)SH";
  return s;
}

int pack_parallel(const SlurmSubmission& submission) {
  const int cases = static_cast<int>(submission.case_folders.size());
  const int throttle = submission.settings.throttle;
  return throttle > 0 ? std::min(throttle, cases) : cases;
}

std::optional<long> parse_slurm_time(const std::string& text) {
  const std::string t = trim(text);
  if (t.empty() || t == "UNLIMITED" || t == "INFINITE" || t == "unlimited" || t == "infinite") return 0;
  auto number = [](const std::string& part) -> std::optional<long> {
    if (part.empty() || part.size() > 9) return std::nullopt;
    for (const char c : part)
      if (c < '0' || c > '9') return std::nullopt;
    return std::stol(part);
  };
  auto split = [](const std::string& part) {
    std::vector<std::string> fields;
    size_t begin = 0;
    for (;;) {
      const size_t colon = part.find(':', begin);
      fields.push_back(part.substr(begin, colon - begin));
      if (colon == std::string::npos) return fields;
      begin = colon + 1;
    }
  };
  long days = 0;
  std::string rest = t;
  const size_t dash = t.find('-');
  if (dash != std::string::npos) {
    const auto d = number(t.substr(0, dash));
    if (!d) return std::nullopt;
    days = *d;
    rest = t.substr(dash + 1);
  }
  std::vector<long> values;
  for (const std::string& field : split(rest)) {
    const auto v = number(field);
    if (!v) return std::nullopt;
    values.push_back(*v);
  }
  long seconds = 0;
  if (dash != std::string::npos) {  // D-HH, D-HH:MM, D-HH:MM:SS
    if (values.size() > 3) return std::nullopt;
    const long factors[] = {3600, 60, 1};
    for (size_t i = 0; i < values.size(); ++i) seconds += values[i] * factors[i];
    seconds += days * 86400;
  } else if (values.size() == 1) {  // MM
    seconds = values[0] * 60;
  } else if (values.size() == 2) {  // MM:SS
    seconds = values[0] * 60 + values[1];
  } else if (values.size() == 3) {  // HH:MM:SS
    seconds = values[0] * 3600 + values[1] * 60 + values[2];
  } else {
    return std::nullopt;
  }
  return seconds;
}

std::string format_slurm_time(long seconds) {
  assert(seconds > 0);
  const long minutes = (seconds + 59) / 60;
  return fmt::format("{}-{:02}:{:02}:00", minutes / 1440, minutes / 60 % 24, minutes % 60);
}

long pack_allocation_seconds(const SlurmSubmission& submission) {
  const auto limit = parse_slurm_time(submission.settings.time_limit);
  if (!limit)
    throw std::invalid_argument(fmt::format("time_limit \"{}\" is not a SLURM time", submission.settings.time_limit));
  if (*limit == 0) return 0;
  const long cases = static_cast<long>(submission.case_folders.size());
  const long parallel = pack_parallel(submission);
  const long waves = (cases + parallel - 1) / parallel;
  return waves * (*limit + 60);
}

std::vector<std::string> sbatch_arguments(const SlurmSubmission& submission) {
  assert(!submission.case_folders.empty());
  assert(submission.ranks >= 1);
  const SlurmSettings& settings = submission.settings;
  std::vector<std::string> args{"--parsable"};
  const std::string logs = escape_percent((submission.work_dir / "logs").string());
  if (settings.mode == SlurmMode::pack) {
    args.insert(args.end(), {"--job-name=" + submission.job_name, fmt::format("--ntasks={}", pack_parallel(submission)),
                             fmt::format("--cpus-per-task={}", submission.ranks),
                             "--chdir=" + submission.work_dir.string(), "--output=" + logs + "/%j.out"});
    if (!submission.comment.empty()) args.push_back("--comment=" + submission.comment);
    if (const long seconds = pack_allocation_seconds(submission); seconds > 0)
      args.push_back("--time=" + format_slurm_time(seconds));
  } else {
    std::string array = fmt::format("--array=0-{}", submission.case_folders.size() - 1);
    if (settings.throttle > 0) array += fmt::format("%{}", settings.throttle);
    args.insert(args.end(), {array, "--job-name=" + submission.job_name, fmt::format("--ntasks={}", submission.ranks),
                             "--chdir=" + submission.work_dir.string(), "--output=" + logs + "/%A_%a.out"});
    if (!submission.comment.empty()) args.push_back("--comment=" + submission.comment);
    if (!settings.time_limit.empty()) args.push_back("--time=" + settings.time_limit);
  }
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
  } else if (kind == "timeout") {
    sentinel.timed_out = true;
    // no value: the next word is already a key=value pair
    words.clear();
    words.str(first.substr(kind.size()));
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

std::optional<SqueueTask> parse_squeue_job(const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string id;
    std::string state;
    std::string code;
    if (!(words >> id >> state) || id != "N/A") continue;
    words >> code;
    SqueueTask job;
    job.state = state;
    if (const auto status = parse_long(code)) job.wait_status = static_cast<int>(*status);
    return job;
  }
  return std::nullopt;
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

std::string SlurmClient::submit(const SlurmSubmission& submission) const {
  if (submission.case_folders.empty()) throw std::invalid_argument("SlurmClient::submit: no case folders");
  const bool pack = submission.settings.mode == SlurmMode::pack;
  fs::create_directories(submission.work_dir / "logs");
  fs::create_directories(sentinel_dir(submission.work_dir));

  // a new script per submission, never overwritten: it is what each task of that job reads
  const std::time_t now = std::time(nullptr);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::gmtime(&now));
  fs::path script;
  for (int n = 0;; ++n) {
    script = submission.work_dir / fmt::format("{}-{}-{}.sh", pack ? "pack" : "batch", stamp, n);
    if (!fs::exists(script)) break;
  }
  {
    std::ofstream out(script);
    out << (pack ? render_pack_script(submission) : render_batch_script(submission));
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
  result.job = parse_squeue_job(r.out);
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
