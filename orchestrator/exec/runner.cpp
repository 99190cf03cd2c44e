#include "orchestrator/exec/runner.hpp"

#include "orchestrator/exec/liggghts_locator.hpp"

#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/exec/case_vtk.hpp"
#include "orchestrator/exec/cost.hpp"
#include "orchestrator/exec/failure.hpp"
#include "orchestrator/exec/local_executor.hpp"
#include "orchestrator/exec/measure.hpp"
#include "orchestrator/exec/open_study.hpp"
#include "orchestrator/exec/progress.hpp"
#include "orchestrator/exec/remeasure.hpp"
#include "orchestrator/exec/run_queue.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/process.hpp"
#include "orchestrator/util/signals.hpp"
#include "sobol/augment.hpp"
#include "sobol/design.hpp"
#include "sobol/scaling.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <stdexcept>
#include <utility>

namespace demsa::exec {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::cases;

using util::StopFlag;
using util::UserError;
using util::write_file_atomically;

namespace {

namespace fs = std::filesystem;

/// Mass of the heaviest particle times g times 1 m, times the particle count, times 100: a kinetic energy no
/// settling pile or oedometer reaches (its potential energy is below N m_max g × 1 m).
double kinetic_energy_limit(const StudyConfig& config, long particles) {
  const double r_max = experiments::of(config).largest_radius(config);
  const double mass = config.material.density * 4.0 / 3.0 * std::numbers::pi * r_max * r_max * r_max;
  return 100.0 * static_cast<double>(particles) * mass * 9.81 * 1.0;
}

long configured_particles(const StudyConfig& config) { return experiments::of(config).particles(config); }

FailureOptions failure_options(const StudyConfig& config, long particles) {
  FailureOptions options;
  options.config = &config;
  options.expected_particles = particles;
  options.lost_fraction = config.run.lost_fraction;
  options.kinetic_energy_limit = kinetic_energy_limit(config, particles);
  return options;
}

/// The result.json of a run, when the file is complete and belongs to run `run` of sample `sample`.
std::optional<std::map<std::string, double>> read_result(const fs::path& folder, int sample, long run) {
  const fs::path file = folder / k_result_file;
  if (!fs::exists(file)) return std::nullopt;
  try {
    const nlohmann::json j = nlohmann::json::parse(util::read_file(file));
    if (j.at("sample").get<int>() != sample || j.at("run").get<long>() != run) return std::nullopt;
    return j.at("observables").get<std::map<std::string, double>>();
  } catch (const std::exception&) {
    return std::nullopt;  // a torn or foreign file: the run is redone
  }
}

RunOutcome outcome_from(const CaseExit& exit) {
  RunOutcome o;
  o.exit_code = exit.exit_code;
  o.signal = exit.signal;
  o.wall_seconds = exit.wall_seconds;
  o.cpu_seconds = exit.cpu_seconds;
  o.host = exit.host;
  return o;
}

/// Removes what an earlier attempt left and writes the case anew. Returns the particle count of the case.
long prepare_case(const StudyConfig& config, const StudyCase& study_case, const fs::path& folder) {
  clear_case_folder(folder);
  const CaseSummary summary = write_case(config, case_request(config, study_case), folder);
  return summary.particles > 0 ? summary.particles : configured_particles(config);
}

}  // namespace

// ----------------------------------------------------------------------------------------------- helpers

void RunOptions::validate() const {
  if (study_file.empty()) throw std::invalid_argument("study_file is empty: a study file is required");
  if (!(progress_interval > 0))
    throw std::invalid_argument(fmt::format("progress_interval = {}: must be > 0", progress_interval));
  if (submit_only && collect_only)
    throw std::invalid_argument("submit_only and collect_only are both set: at most one of them may be");
  if (dry_run && (submit_only || collect_only))
    throw std::invalid_argument("dry_run with submit_only or collect_only: a dry run submits and collects nothing");
}

// ----------------------------------------------------------------------------------------------- run_study

namespace {

/// What the runner keeps of a case from its start to its end.
struct InFlight {
  long run = 0;
  int sample = 0;
  int attempt = 1;
  long particles = 0;
};

/// One invocation's loop, in the shape of ninja's Builder (src/build.h): the study, the executor (the
/// CommandRunner), what is left (the RunQueue, ninja's Plan) and the cases in flight.
struct Loop {
  const RunOptions& options;
  const StudyConfig& config;
  const fs::path& dir;
  Store& store;
  Executor& executor;
  RunSummary& summary;
  std::function<bool()> should_stop;
  RunQueue queue;
  std::map<std::string, InFlight> in_flight = {};  ///< by case folder
  std::vector<double> walls = {};                  ///< [s] wall times of the done runs, for the ETA
};

/// Runs an earlier demsa left `submitted`: the ones whose folder holds a complete result.json of that very run are
/// committed from it; with submit_only the others are left to the cluster (no polling: they only stay out of the
/// queue); otherwise the executor adopts them and they end through collect() like the cases this run starts.
void recover_submitted(Loop& loop) {
  std::vector<SubmittedCase> adopt;
  for (const RunRow& r : loop.store.runs_in_state(RunState::submitted)) {
    const fs::path folder = case_dir(loop.dir, r.sample);
    if (const auto observables = read_result(folder, r.sample, r.id)) {
      RunOutcome outcome;
      outcome.exit_code = 0;
      outcome.message = "recovered from result.json after an interruption";
      loop.store.record_done(r.id, outcome, *observables);
      loop.queue.mark_done(r.sample, r.attempt);
      ++loop.summary.recovered;
      continue;
    }
    if (loop.options.submit_only) {
      loop.queue.leave_submitted(r.sample);
      continue;
    }
    adopt.push_back({CaseTask{r.sample, r.attempt, folder}, r.job_id});
    loop.in_flight[folder.string()] = InFlight{r.id, r.sample, r.attempt, configured_particles(loop.config)};
    loop.queue.adopt(r.sample);
  }
  if (!adopt.empty()) {
    loop.store.add_event("resume", fmt::format("{} runs left in flight by an earlier demsa", adopt.size()));
    loop.executor.adopt(adopt);
  }
}

/// Starts a batch of prepared case folders and returns their run ids, in the order of `batch`. The run rows, with
/// the ids the executor can find the tasks by (SLURM: the submission's token), are committed in one transaction
/// before anything starts: a crash at any point after it leaves runs to adopt, never a process or an array job the
/// store does not know how to find (that would run a case twice). The real ids replace them once submit() returns.
std::vector<long> start_batch(Executor& executor, Store& store, const std::vector<CaseTask>& batch) {
  const std::vector<std::string> reserved = executor.reserve_ids(batch);
  std::vector<NewRun> rows;
  for (std::size_t i = 0; i < batch.size(); ++i)
    rows.push_back(NewRun{batch[i].sample, batch[i].attempt, reserved.at(i)});
  const std::vector<long> runs = store.add_runs(rows);
  const std::vector<std::string> ids = executor.submit(batch);
  std::vector<std::pair<long, std::string>> job_ids;
  for (std::size_t i = 0; i < batch.size(); ++i) job_ids.emplace_back(runs.at(i), ids.at(i));
  store.set_job_ids(job_ids);
  return runs;
}

/// Takes from the front of the queue as many cases as the executor has room for, writes each case folder anew and
/// starts them in one batch.
void start_what_fits(Loop& loop, const std::map<int, StudyCase>& cases) {
  std::vector<CaseTask> batch;
  std::vector<InFlight> flights;
  const int slots = loop.executor.free_slots();
  while (static_cast<int>(batch.size()) < slots) {
    const std::optional<QueuedCase> next = loop.queue.next();
    if (!next) break;
    const fs::path folder = case_dir(loop.dir, next->sample);
    long particles = 0;
    try {
      particles = prepare_case(loop.config, cases.at(next->sample), folder);
    } catch (const util::StopRequested&) {
      // A signal while the case was written (its folder is removed): nothing of this batch starts, and the loop
      // stops as for any signal; the next `demsa run` writes these cases again.
      return;
    }
    batch.push_back(CaseTask{next->sample, next->attempt, folder});
    flights.push_back(InFlight{0, next->sample, next->attempt, particles});
  }
  if (batch.empty()) return;
  const std::vector<long> runs = start_batch(loop.executor, loop.store, batch);
  for (std::size_t i = 0; i < batch.size(); ++i) {
    flights[i].run = runs.at(i);
    loop.in_flight[batch[i].folder.string()] = flights[i];
  }
  loop.summary.submitted += static_cast<int>(batch.size());
}

/// The text of a done run's result.json: what recovery needs to commit the run without running it again.
std::string result_json(const FinishedCase& finished, const InFlight& flight,
                        const std::map<std::string, double>& observables) {
  nlohmann::json result;
  result["sample"] = flight.sample;
  result["run"] = flight.run;
  result["attempt"] = flight.attempt;
  result["observables"] = observables;
  result["exit_code"] = finished.exit.exit_code;
  result["wall_seconds"] = finished.exit.wall_seconds;
  result["cpu_seconds"] = finished.exit.cpu_seconds;
  result["host"] = finished.exit.host;
  return result.dump(2) + "\n";
}

/// Stores what a done case cost against its prediction (exec/cost.hpp); a case whose cost cannot be read is noted in
/// the events and left out of the comparison (its result counts all the same). The actual CPU is the run's own
/// (wait4's rusage of run.sh and what it waited for) when the executor measured one: its log's loop times are wall
/// time, which overstate the CPU of a case that shared its core.
void record_case_cost(Loop& loop, const fs::path& folder, long run, int sample, double run_cpu_seconds) {
  try {
    if (auto row = case_cost_row(loop.config, loop.dir, folder, run, sample, loop.store.case_costs())) {
      if (run_cpu_seconds > 0) row->cpu_seconds = run_cpu_seconds;
      loop.store.record_case_cost(*row);
    }
  } catch (const std::exception& e) {
    loop.store.add_event("cost", fmt::format("run {}: its cost was not recorded: {}", run, e.what()), sample);
  }
}

/// One case ended (ninja's Builder::FinishCommand): classify it, measure it, write its result.json, commit its run
/// (done, failed or requeued: one store transaction) and tell the queue. result.json is written atomically before
/// the commit, so a crash between the two is recovered from it (recover_submitted).
void finish_case(Loop& loop, const FinishedCase& finished, const InFlight& flight) {
  const fs::path& folder = finished.task.folder;
  FailureReport report = classify_case(finished.exit, folder, failure_options(loop.config, flight.particles));
  if (report.requeue) {
    loop.store.record_requeued(flight.run, report.message);
    if (!finished.exit.detail.empty())
      loop.store.add_event("requeued", fmt::format("run {}: {}: {}", flight.run, report.message, finished.exit.detail),
                           flight.sample);
    loop.queue.requeue(flight.sample, loop.should_stop());
    return;
  }
  RunOutcome outcome = outcome_from(finished.exit);
  std::map<std::string, double> observables;
  if (report.failure == FailureClass::none) {
    try {
      observables = measure_case(folder);
    } catch (const std::exception& e) {
      report.failure = FailureClass::measurement;
      report.message = e.what();
      report.log_tail = file_tail(folder / k_case_log, 30);
    }
  }
  if (report.failure == FailureClass::none) {
    write_case_vtk_or_warn(folder);
    write_file_atomically(folder / k_result_file, result_json(finished, flight, observables));
    loop.store.record_done(flight.run, outcome, observables);
    record_case_cost(loop, folder, flight.run, flight.sample, finished.exit.cpu_seconds);
    loop.queue.mark_done(flight.sample, flight.attempt);
    ++loop.summary.done_now;
    if (finished.exit.wall_seconds > 0) loop.walls.push_back(finished.exit.wall_seconds);
    return;
  }
  outcome.failure = report.failure;
  outcome.message = report.message;
  outcome.log_tail = report.log_tail;
  loop.store.record_failed(flight.run, outcome);
  ++loop.summary.failures_by_class[to_string(report.failure)];
  // collect_only: the queue neither retries nor gives up; the next `demsa run` retries it.
  if (report.final)
    loop.queue.give_up(flight.sample, flight.attempt);
  else
    loop.queue.retry_or_give_up(flight.sample, flight.attempt, !loop.options.collect_only && loop.should_stop());
}

/// Polls the executor (waiting up to `wait`) and finishes every case that ended; first stores the real job ids it
/// found for adopted runs that had only a provisional one.
void collect(Loop& loop, std::chrono::milliseconds wait) {
  const std::vector<FinishedCase> finished = loop.executor.poll(wait);
  std::vector<std::pair<long, std::string>> learned;
  for (const SubmittedCase& found : loop.executor.take_learned_ids()) {
    const auto it = loop.in_flight.find(found.task.folder.string());
    if (it == loop.in_flight.end()) continue;
    learned.emplace_back(it->second.run, found.job_id);
    loop.store.add_event("adopted",
                         fmt::format("run {}: its array job was found by its submission token: SLURM task {}",
                                     it->second.run, found.job_id),
                         it->second.sample);
  }
  if (!learned.empty()) loop.store.set_job_ids(learned);
  for (const FinishedCase& f : finished) {
    const auto it = loop.in_flight.find(f.task.folder.string());
    if (it == loop.in_flight.end()) continue;  // not ours (cannot happen with one runner per study)
    const InFlight flight = it->second;
    loop.in_flight.erase(it);
    ++loop.summary.collected;
    finish_case(loop, f, flight);
  }
}

/// Whether the loop goes on: samples left to start, or (unless submit_only, which does not poll) cases in flight.
bool work_left(const Loop& loop) {
  return loop.queue.has_queued() || (!loop.options.submit_only && loop.executor.in_flight() > 0);
}

ProgressCounts counts(const Loop& loop) {
  ProgressCounts c;
  c.done = loop.queue.done_count();
  c.running = static_cast<int>(loop.in_flight.size());
  c.failed = loop.queue.failed_count();
  c.total = loop.summary.samples + loop.summary.replicates;
  return c;
}

double eta(const Loop& loop, int parallel) {
  double mean = 0;
  for (double w : loop.walls) mean += w;
  mean = loop.walls.empty() ? 0.0 : mean / static_cast<double>(loop.walls.size());
  const int remaining =
      loop.summary.samples + loop.summary.replicates - loop.queue.done_count() - loop.queue.failed_count();
  return estimate_remaining(remaining, parallel, mean);
}

/// Stopped by a signal or should_stop. Local cases die with demsa anyway; SLURM tasks are cancelled only on request
/// (they cost nothing to keep); --submit-only never cancels what it submitted. Cancelled cases are collected and
/// recorded `requeued`.
void handle_interrupt(Loop& loop) {
  loop.summary.interrupted = true;
  const std::string why =
      StopFlag::signal_number() != 0 ? fmt::format("signal {}", StopFlag::signal_number()) : std::string("stopped");
  bool cancel = !loop.options.submit_only;
  if (cancel && loop.config.run.executor == ExecutorKind::slurm && loop.executor.in_flight() > 0)
    cancel = loop.options.cancel_on_interrupt ||
             (loop.options.ask_cancel && loop.options.ask_cancel(loop.executor.in_flight()));
  if (cancel) {
    loop.executor.cancel_all();
    collect(loop, std::chrono::milliseconds(0));
    loop.store.add_event("interrupted", why);
  } else {
    loop.store.add_event("interrupted", fmt::format("{}; {} SLURM task(s) left running", why, loop.in_flight.size()));
  }
}

}  // namespace

RunSummary run_study(const RunOptions& options) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  StudyConfig config = experiments::load_study(options.study_file);
  // The LIGGGHTS the cases run, and whether it has the study's rolling model: refused before any case runs.
  resolve_liggghts(config, !options.dry_run);
  RunSummary summary;
  summary.dir = options.dir.empty() ? default_study_dir(options.study_file) : options.dir;
  summary.dry_run = options.dry_run;
  const fs::path& dir = summary.dir;
  fs::create_directories(dir);
  const StudyLock lock(dir);
  Store store = open_study(config, options.study_file, dir, options.new_study, options.dry_run, &summary.remeasured);
  summary.samples = static_cast<int>(store.samples().size());
  // Every case by its id: the design's samples, then the replicate cases (ReplicateRow), in the order they run.
  std::vector<int> order;
  const std::map<int, StudyCase> cases = study_cases(store, &order);
  summary.replicates = static_cast<int>(order.size()) - summary.samples;

  if (options.dry_run) {
    // Validate every case by writing it (a case that breaks a LIGGGHTS limit throws UserError here).
    for (const int sample : order) {
      const fs::path folder = case_dir(dir, sample);
      // A case that ran keeps its files (a change of measurement settings measures them again).
      if (!fs::exists(folder / k_result_file) && !fs::exists(folder / k_case_log))
        prepare_case(config, cases.at(sample), folder);
    }
    const StoreCounts counts = store.counts();
    summary.done = counts.done;
    summary.replicates_done = counts.replicates_done;
    summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  }

  if ((options.submit_only || options.collect_only) && config.run.executor != ExecutorKind::slurm)
    throw UserError(fmt::format(
        "{}: {} needs [run] executor = \"slurm\"; the local executor runs the cases inside `demsa run` itself",
        options.study_file.string(), options.submit_only ? "RunOptions.submit_only" : "collecting submitted runs"));
  std::unique_ptr<Executor> executor = make_executor(config.run, dir);
  summary.executor = executor->name();
  const int parallel = config.run.executor == ExecutorKind::local ? local_parallel(config.run, machine_cores()) : 1;

  Loop loop{.options = options,
            .config = config,
            .dir = dir,
            .store = store,
            .executor = *executor,
            .summary = summary,
            .should_stop = options.should_stop ? options.should_stop : [] { return StopFlag::raised(); },
            .queue = RunQueue(RunQueueOptions{.retries = config.run.retries, .collect_only = options.collect_only})};
  // Who is done, which attempt each sample is at; then the runs an earlier demsa left in flight; then the queue.
  for (const RunRow& r : store.runs()) {
    loop.queue.add_past_run(r);
    if (r.state == RunState::done && r.wall_seconds > 0) loop.walls.push_back(r.wall_seconds);
  }
  recover_submitted(loop);
  loop.queue.queue_remaining(order);

  Progress progress(options.quiet || options.collect_only ? nullptr : stderr, Progress::is_terminal(stderr),
                    options.progress_interval);
  if (options.collect_only) {
    // One look without waiting (squeue once, the sentinels once); what has not ended stays submitted.
    collect(loop, std::chrono::milliseconds(0));
  }
  while (!options.collect_only && work_left(loop) && !loop.should_stop()) {
    start_what_fits(loop, cases);
    if (options.submit_only) continue;  // no polling: the cluster runs them, a later run or status collects
    collect(loop, std::chrono::milliseconds(200));
    progress.update(counts(loop), eta(loop, parallel));
  }
  if (!options.collect_only && loop.should_stop()) handle_interrupt(loop);
  progress.finish(counts(loop));

  summary.left_running = static_cast<int>(loop.in_flight.size()) + loop.queue.left_submitted_count();
  for (const auto& [sample, c] : cases)
    (c.replicate ? summary.replicates_done : summary.done) += loop.queue.is_done(sample);
  summary.failed_samples = loop.queue.failed_samples();
  summary.failed = static_cast<int>(summary.failed_samples.size());
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (options.collect_only)
    store.add_event("collected", fmt::format("{} ended, {} committed, {} still on the cluster", summary.collected,
                                             summary.done_now, summary.left_running));
  else
    store.add_event("finished", fmt::format("{} done, {} failed, {} committed now, {} submitted, {} left on the "
                                            "cluster, in {:.1f} s",
                                            summary.done, summary.failed, summary.done_now, summary.submitted,
                                            summary.left_running, summary.seconds));
  return summary;
}

}  // namespace demsa::exec
