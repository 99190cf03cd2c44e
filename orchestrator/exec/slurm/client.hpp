#pragma once
// A small SLURM client: submits job arrays (or, in pack mode, one allocation whose cases run as job steps) with
// `sbatch`, reads the state of their tasks with `squeue`, cancels them with `scancel`, and reads the sentinel file
// each case writes when it ends. The programs are run directly
// (util::run_capture: argv, no shell, each killed after SlurmCommands::timeout), so paths with spaces or quotes
// need no care here; the batch script quotes every path itself.
//
// Why sentinels: without slurmdbd there is no `sacct`, and `squeue` forgets finished jobs after MinJobAge (300 s
// by default). A task cancelled while still pending leaves no trace at all. So each task writes, atomically
// (write + rename), a sentinel with its exit status when it ends; a TERM trap covers `scancel` and the time limit,
// because SLURM sends SIGTERM to the batch shell first. A task that is gone from `squeue` and left no sentinel was
// cancelled before it started (or purged by the controller): its outcome is unknown.
#include "orchestrator/study/config.hpp"
#include "orchestrator/util/text.hpp"

#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace demsa::exec {

/// The programs the client runs (names on PATH or paths).
struct SlurmCommands {
  std::string sbatch = "sbatch";
  std::string squeue = "squeue";
  std::string scancel = "scancel";
  std::chrono::milliseconds timeout{120000};  ///< a command that takes longer is killed and counts as failed
};

/// One submission. settings.mode array: `sbatch --array=0-(N-1)`, task i runs `./run.sh` in case_folders[i]. pack:
/// one `sbatch` of a driver script whose allocation holds pack_parallel() cases of `ranks` CPUs each; the driver
/// runs case i as job step `srun --exclusive -N1 -n RANKS`, at most pack_parallel() at a time.
struct SlurmSubmission {
  std::vector<std::filesystem::path> case_folders;  ///< absolute paths, at least one
  std::filesystem::path work_dir;                   ///< where the batch script, the sentinels and SLURM's own logs go
  std::string job_name = "demsa";                   ///< sbatch --job-name
  std::string comment;            ///< sbatch --comment (empty: none); the executor marks each submission with it
  int ranks = 1;                  ///< CPUs per case: sbatch --ntasks per array task, srun -n per step (mpirun -np)
  study::SlurmSettings settings;  ///< mode, partition, account, time limit, throttle, extra options, prologue
};

/// The batch script of a submission (bash). Every case folder and file is single-quoted. Each task:
/// runs the prologue, sets the Open MPI variables that let mpirun run as root when it is root, starts
/// `./run.sh` in its case folder with stdout and stderr to run.out, waits for it and writes its sentinel
/// (work_dir/sentinels/JOB_TASK) atomically; a TERM trap writes "signal TERM" and stops run.sh.
std::string render_batch_script(const SlurmSubmission& submission);

/// The driver script of a pack submission (bash). It runs the prologue once, then starts case i as the job step
/// `srun --exclusive --wait=0 -N1 -n RANKS -c1 bash -c STEP`, at most pack_parallel() steps at a time (a new one as
/// soon as one ends), and waits for them. In each step, task 0 runs `./run.sh` in the case folder (output to
/// run.out; mpirun inside it starts the ranks on the step's CPUs) and writes the case's sentinel
/// (work_dir/sentinels/JOB_I) as an array task does; the other tasks of the step only hold its CPUs. A case still
/// running after [run.slurm] time_limit is stopped (SIGTERM) and its sentinel says "timeout". When srun fails without
/// the step having written a sentinel (the step could not be started), the driver writes "exit N" to
/// launch_failure_path() instead. On SIGTERM (scancel, the allocation's end) it starts nothing more.
std::string render_pack_script(const SlurmSubmission& submission);

/// Cases that run at once in a pack allocation: [run.slurm] throttle, at most the number of cases; all of them when
/// throttle is 0.
int pack_parallel(const SlurmSubmission& submission);

/// Seconds of a SLURM time ("MM", "MM:SS", "HH:MM:SS", "D-HH", "D-HH:MM", "D-HH:MM:SS"); 0 for no limit ("",
/// "0", "UNLIMITED", "INFINITE"); nullopt when the text is none of these.
std::optional<long> parse_slurm_time(const std::string& text);
/// A duration as sbatch --time "D-HH:MM:SS", rounded up to whole minutes (SLURM's resolution); seconds > 0.
std::string format_slurm_time(long seconds);

/// The walltime of a pack allocation [s], 0 when time_limit sets none: ceil(N / P) waves of at most time_limit plus
/// one minute each (step start, sentinel). The driver starts a case whenever a step ends, and with every case at most
/// L long the k-th case (0-based) starts by floor(k / P) L (greedy list scheduling, Graham 1966, "Bounds for certain
/// multiprocessing anomalies"), so all N end within ceil(N / P) L. Throws std::invalid_argument for a time_limit
/// that parse_slurm_time() refuses.
long pack_allocation_seconds(const SlurmSubmission& submission);

/// The sbatch arguments (after the program name, before the script path) of a submission: `--array` and
/// `--ntasks=RANKS` for an array; `--ntasks=P --cpus-per-task=RANKS` (P = pack_parallel(): every case's CPUs on one
/// node) and `--time` = pack_allocation_seconds() for a pack.
std::vector<std::string> sbatch_arguments(const SlurmSubmission& submission);

/// Folder of the sentinels under a submission's work_dir.
std::filesystem::path sentinel_dir(const std::filesystem::path& work_dir);
/// Sentinel file of task `task` of array job `job` (pack: case `task` of allocation `job`):
/// work_dir/sentinels/JOB_TASK.
std::filesystem::path sentinel_path(const std::filesystem::path& work_dir, const std::string& job, int task);
/// What a pack driver writes when srun failed and the step wrote no sentinel: work_dir/sentinels/JOB_TASK.srun.
std::filesystem::path launch_failure_path(const std::filesystem::path& work_dir, const std::string& job, int task);

/// What a task wrote when it ended.
struct Sentinel {
  bool signalled = false;     ///< ended by SIGTERM (scancel, time limit, preemption)
  bool timed_out = false;     ///< stopped by a pack driver at [run.slurm] time_limit ("timeout")
  int exit_code = -1;         ///< run.sh's exit status (when not signalled)
  std::string host;           ///< node it ran on
  double wall_seconds = 0.0;  ///< from the start of run.sh to its end
  double cpu_seconds = 0.0;   ///< user + system time of run.sh and its descendants on that node
};

/// Parses a sentinel's text; nullopt when it is not a complete sentinel.
std::optional<Sentinel> parse_sentinel(const std::string& text);
/// Reads and parses a sentinel file; nullopt when it does not exist (yet) or is incomplete.
std::optional<Sentinel> read_sentinel(const std::filesystem::path& file);

/// One task as `squeue -h -r -t all -j JOB -O ArrayTaskID,State,exit_code` shows it.
struct SqueueTask {
  std::string state;    ///< PENDING, RUNNING, COMPLETED, FAILED, CANCELLED, TIMEOUT, ...
  int wait_status = 0;  ///< exit_code column: the raw wait status (256 = exit 1)
};

/// True for the states a task never leaves (COMPLETED, FAILED, CANCELLED, TIMEOUT, NODE_FAIL, OUT_OF_MEMORY, ...).
bool is_terminal_state(const std::string& state);

/// Parses squeue's output (see SqueueTask). Lines that are not "TASK STATE CODE" (e.g. a pending range such as
/// "[2-7]") are skipped.
std::map<int, SqueueTask> parse_squeue(const std::string& text);

/// The one state of a job that is not an array (a pack allocation): squeue shows its ArrayTaskID as "N/A". nullopt
/// when there is no such line.
std::optional<SqueueTask> parse_squeue_job(const std::string& text);

/// Outcome of one squeue call for one job.
struct SqueueResult {
  bool ok = false;                  ///< false: squeue failed (controller down, timeout); tasks unknown
  std::map<int, SqueueTask> tasks;  ///< by array task id; empty when the controller no longer knows the job
  std::optional<SqueueTask> job;    ///< the state of a job that is not an array (parse_squeue_job)
  std::string error;                ///< squeue's message when !ok
};

/// Outcome of one `squeue -h -t all --me -o "%F %k"` call: the caller's jobs that the controller knows (pending,
/// running, or finished within MinJobAge), by their comment.
struct CommentLookup {
  bool ok = false;                                       ///< false: squeue failed; nothing is known
  std::map<std::string, std::vector<std::string>> jobs;  ///< comment -> array job ids (sorted, each once)
  std::string error;                                     ///< squeue's message when !ok
};

/// Parses the output of `squeue -o "%F %k"` ("JOB COMMENT" per line; the comment may be "(null)" or have spaces).
std::map<std::string, std::vector<std::string>> parse_comment_lines(const std::string& text);

/// Array job id from `sbatch --parsable` output ("123" or "123;cluster"); nullopt when there is none.
std::optional<std::string> parse_sbatch_job_id(const std::string& text);

/// Runs the SLURM programs. Stateless apart from the command names.
class SlurmClient {
 public:
  explicit SlurmClient(SlurmCommands commands = {});

  /// Writes work_dir/batch-<stamp>.sh (pack: pack-<stamp>.sh) and submits it with sbatch; returns the job id. Creates
  /// work_dir, its logs/ and sentinels/ folders. Throws std::runtime_error with sbatch's message when it fails.
  std::string submit(const SlurmSubmission& submission) const;

  /// The tasks of array job `job` that the controller still knows (pending, running, or finished recently).
  SqueueResult query(const std::string& job) const;

  /// The caller's jobs by comment (one squeue call for all of them): how a restarted demsa finds an array it
  /// submitted but whose job id it never learned.
  CommentLookup jobs_by_comment() const;

  /// Cancels the whole job (array or pack allocation), or one task of an array. Returns false (and scancel's message in
  /// `error`) on failure.
  bool cancel(const std::string& job, std::optional<int> task = std::nullopt, std::string* error = nullptr) const;

  const SlurmCommands& commands() const { return m_commands; }

 private:
  SlurmCommands m_commands;
};

}  // namespace demsa::exec
