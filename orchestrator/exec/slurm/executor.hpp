#pragma once
// The SLURM executor (ARCHITECTURE.md "exec/"): one `sbatch --array` per submit() call, each array task runs one case
// folder's `./run.sh` (output to run.out) and writes a sentinel when it ends (slurm_client.hpp). In pack mode
// ([run.slurm] mode = "pack") a submit() is one allocation instead, whose driver runs each case as a job step that
// writes the same sentinel; the executor starts a new allocation only when nothing is in flight (free_slots() is 0
// until then), so a study holds one SLURM job at a time. poll() reads the
// sentinels often and `squeue` every [run.slurm] poll_interval; a task's end is taken from its sentinel, and from
// squeue's state when there is none. Everything it writes lives in STUDY/slurm/: batch scripts, SLURM's own logs
// (logs/JOB_TASK.out) and sentinels (sentinels/JOB_TASK).
//
// How a task's end maps to CaseExit:
//   sentinel "exit N"                          -> exit_code N (run.sh's status, as the local executor reports it)
//   sentinel "signal TERM", squeue TIMEOUT     -> timed_out
//   sentinel "signal TERM", squeue CANCELLED   -> cancelled (scancel by cancel_all() or by hand: run it again)
//   sentinel "signal TERM", anything else      -> signal 15
//   no sentinel, squeue TIMEOUT / CANCELLED    -> timed_out / cancelled
//   no sentinel, NODE_FAIL, PREEMPTED, BOOT_FAIL, DEADLINE -> lost (not the case's fault: run it again)
//   no sentinel, OUT_OF_MEMORY                 -> signal 9
//   no sentinel, COMPLETED / FAILED            -> exit status or signal from squeue's exit_code, after a grace
//                                                 period for shared filesystems that show new files late
//   gone from squeue, no sentinel              -> lost (cancelled while pending, or purged by the controller)
// Job ids are "JOB_TASK" (array job id, task index), which is all adopt() needs to follow a task again. A case of a
// pack allocation has the id "JOB_I" too (I its index in the allocation); squeue shows such a job as one line whose
// ArrayTaskID is "N/A", and its state stands for every case of it that has no sentinel:
//   sentinel "timeout"                              -> timed_out (the driver stopped it at time_limit)
//   sentinel JOB_I.srun "exit N" only (srun could not start the step), after the grace period -> exit_code N
//   job CANCELLED                                   -> cancelled
//   job TIMEOUT, NODE_FAIL, PREEMPTED, BOOT_FAIL, DEADLINE -> lost (the allocation ended before the case started)
//   job COMPLETED, FAILED, OUT_OF_MEMORY, after the grace period -> the job's exit status (the driver died)
//
// Before sbatch runs, reserve_ids() gives every array a unique token (Unix time in hex, '-', 32 random bits in hex)
// and the runner stores "pending:TOKEN:INDEX" for each of its tasks; submit() passes `--comment=demsa:TOKEN`. If
// demsa dies after sbatch has created the job but before the real ids were stored, adopt() finds the array again
// with one `squeue -h -t all --me -o "%F %k"` (array job id and comment of every job of the user):
//   token found                     -> followed as JOB_INDEX (the id comes back from take_learned_ids())
//   token not found (absent_confirmations answers in a row, and the token older than the sbatch time limit, so that
//   an sbatch still running from the killed demsa cannot submit it afterwards)
//                                   -> lost: sbatch never submitted it, or it ended longer than MinJobAge ago
//   squeue fails                    -> stays in flight, handled as any squeue outage (never submitted again)
#include "orchestrator/exec/executor.hpp"
#include "orchestrator/exec/slurm/client.hpp"

#include <chrono>
#include <filesystem>
#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace demsa::exec {

struct SlurmExecutorOptions {
  SlurmCommands commands;  ///< sbatch/squeue/scancel to run (tests use fakes)
  /// squeue runs at most this often; from [run.slurm] poll_interval; > 0
  std::chrono::milliseconds query_interval{5000};
  /// sentinel files are looked at this often (cheap); > 0
  std::chrono::milliseconds sentinel_interval{500};
  /// consecutive squeue answers without a task (and no sentinel) before it counts as lost; >= 1
  int absent_confirmations = 2;
  /// how long a task may sit in a final squeue state without its sentinel appearing (shared filesystems
  /// show new files late), and a "signal TERM" sentinel without a final state; >= 0
  std::chrono::milliseconds sentinel_grace{30000};
  /// squeue failing this long without a break makes poll() throw (the tasks stay submitted); > 0
  std::chrono::milliseconds squeue_outage_limit{600000};
  /// cancel_all() waits this long for cancelled tasks to end; >= 0
  std::chrono::milliseconds cancel_wait{60000};
  /// most tasks per array job (SLURM's MaxArraySize is 1001 by default); >= 1
  int max_array_size = 1000;
  /// pack mode: most cases per allocation, one job step each (SLURM's MaxStepCount is 40000 by default); >= 1
  int max_pack_size = 40000;
  int ranks = 1;  ///< sbatch --ntasks per case; >= 1
  std::string job_name = "demsa";
  study::SlurmSettings settings;  ///< mode, partition, account, time limit, throttle, extra options, prologue
  void validate() const;          ///< throws std::invalid_argument naming the field, its value and the rule
};

/// Options for a study: commands from PATH, intervals from [run.slurm], ranks from [run], job name from the folder.
SlurmExecutorOptions slurm_executor_options(const study::RunSettings& run, const std::filesystem::path& study_dir);

class SlurmExecutor : public Executor {
 public:
  /// `study_dir`: the study folder; the executor writes only to study_dir/slurm (and run.out in case folders).
  SlurmExecutor(SlurmExecutorOptions options, const std::filesystem::path& study_dir);

  std::string name() const override { return "slurm"; }
  int free_slots() const override;
  std::vector<std::string> reserve_ids(const std::vector<CaseTask>& tasks) override;
  std::vector<std::string> submit(const std::vector<CaseTask>& tasks) override;
  void adopt(const std::vector<SubmittedCase>& tasks) override;
  std::vector<SubmittedCase> take_learned_ids() override;
  std::vector<FinishedCase> poll(std::chrono::milliseconds wait) override;
  int in_flight() const override;
  void cancel_all() override;

  /// Folder of batch scripts, logs and sentinels: study_dir/slurm.
  const std::filesystem::path& work_dir() const { return m_work_dir; }

 private:
  struct Tracked {
    CaseTask task;
    std::string job;    ///< array job id; "" while only the submission token is known
    std::string token;  ///< submission token of an adopted provisional id ("" otherwise)
    int index = 0;
    bool pack = false;  ///< a case of a pack allocation: squeue's one state of the job applies to it
    int absent = 0;     ///< consecutive squeue answers without this task
    std::string state;  ///< last state squeue showed ("" = never seen)
    int wait_status = 0;
    std::optional<std::chrono::steady_clock::time_point> final_since;          ///< final state, no sentinel yet
    std::optional<std::chrono::steady_clock::time_point> signalled_since;      ///< "signal TERM", no final state yet
    std::optional<std::chrono::steady_clock::time_point> launch_failed_since;  ///< JOB_I.srun, no sentinel yet
    bool cancel_requested = false;
  };

  /// Tokens of the next submit(): the arrays of `folders`, one token per array of at most max_array_size.
  struct Reservation {
    std::vector<std::filesystem::path> folders;
    std::vector<std::string> tokens;
  };

  std::vector<FinishedCase> sweep(bool force_query);
  void query_jobs();
  /// Looks the tasks that have only a token up in squeue; false when squeue failed (`m_last_query_error`).
  bool resolve_tokens();
  std::optional<CaseExit> decide(Tracked& t, std::chrono::steady_clock::time_point now,
                                 const std::set<std::string>& sentinels) const;
  /// decide() for a case of a pack allocation that has no sentinel of its own.
  std::optional<CaseExit> decide_pack(Tracked& t, std::chrono::steady_clock::time_point now,
                                      const std::set<std::string>& sentinels) const;
  /// Cases per sbatch: max_array_size, or max_pack_size in pack mode.
  size_t chunk_size() const;

  SlurmExecutorOptions m_options;
  SlurmClient m_client;
  std::filesystem::path m_work_dir;
  std::vector<Tracked> m_tasks;
  std::vector<FinishedCase> m_ready;      ///< ended during cancel_all(), handed out by the next poll()
  std::vector<SubmittedCase> m_learned;   ///< real ids found for tokens, handed out by take_learned_ids()
  std::optional<Reservation> m_reserved;  ///< from reserve_ids(), used by the next submit()
  std::optional<std::chrono::steady_clock::time_point> m_last_query;
  std::optional<std::chrono::steady_clock::time_point> m_outage_since;
  std::string m_last_query_error;
};

/// The SLURM executor for a study (same arguments as make_local_executor). Throws util::UserError when sbatch is not
/// on PATH.
std::unique_ptr<Executor> make_slurm_executor(const study::RunSettings& run, const std::filesystem::path& study_dir);

/// Splits a job id "JOB_TASK" into its array job id and task index; nullopt when it is not one.
std::optional<std::pair<std::string, int>> parse_slurm_task_id(const std::string& id);

/// A provisional id "pending:TOKEN:INDEX" (see SlurmExecutor::reserve_ids).
struct PendingSlurmId {
  std::string token;
  int index = 0;
};
/// Splits a provisional id; nullopt when it is not one.
std::optional<PendingSlurmId> parse_pending_slurm_id(const std::string& id);
/// A new submission token: the Unix time `now` [s] in hex, '-', 32 random bits in hex (e.g. "6562f0a1-9c3b07de").
std::string make_submission_token(double now);
/// The Unix time [s] a token was made at; nullopt when the token does not start with one.
std::optional<double> submission_token_time(const std::string& token);
/// The sbatch --comment that marks the array job of a submission token: "demsa:TOKEN".
std::string submission_comment(const std::string& token);

/// After SIGINT with SLURM tasks in flight: asks on `prompt` whether to scancel them and reads the answer from
/// `answer` ("y"/"yes", any case, means yes; anything else, or end of input, means leave them running: a later
/// `demsa run` or `demsa status` collects them).
bool ask_cancel_on_interrupt(int in_flight, std::istream& answer, std::ostream& prompt);

}  // namespace demsa::exec
