#include "orchestrator/exec/runner.hpp"

#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/exec/failure.hpp"
#include "orchestrator/exec/local_executor.hpp"
#include "orchestrator/exec/measure.hpp"
#include "orchestrator/exec/progress.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/process.hpp"
#include "orchestrator/util/signals.hpp"
#include "sobol/design.hpp"
#include "sobol/scaling.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <deque>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

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
  const double r_max = config.experiment == Experiment::pile ? config.pile.radii.r_max : config.oedometer.radii.r_max;
  const double mass = config.material.density * 4.0 / 3.0 * std::numbers::pi * r_max * r_max * r_max;
  return 100.0 * static_cast<double>(particles) * mass * 9.81 * 1.0;
}

long configured_particles(const StudyConfig& config) {
  return config.experiment == Experiment::pile ? config.pile.particles : config.oedometer.particles;
}

FailureOptions failure_options(const StudyConfig& config, long particles) {
  FailureOptions options;
  options.experiment = config.experiment;
  options.expected_particles = particles;
  options.lost_fraction = config.run.lost_fraction;
  options.kinetic_energy_limit = kinetic_energy_limit(config, particles);
  options.load_steps = config.experiment == Experiment::oedometer ? static_cast<int>(config.oedometer.loads.size()) : 0;
  return options;
}

std::string design_csv(const StudyConfig& config, const std::vector<SampleRow>& samples) {
  std::string text = "sample";
  for (const ParameterRange& p : config.parameters) text += ",u_" + p.name;
  for (const ParameterRange& p : config.parameters) text += "," + p.name;
  text += "\n";
  for (const SampleRow& s : samples) {
    text += std::to_string(s.sample);
    for (double u : s.unit) text += fmt::format(",{:.17g}", u);
    for (double x : s.physical) text += fmt::format(",{:.17g}", x);
    text += "\n";
  }
  return text;
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
long prepare_case(const StudyConfig& config, const SampleRow& sample, const fs::path& folder) {
  std::error_code ec;
  fs::remove_all(folder, ec);
  if (ec) throw std::runtime_error(fmt::format("{}: cannot remove: {}", folder.string(), ec.message()));
  CaseRequest request = request_from_unit_point(config, sample.sample, sample.unit);
  request.demsa_executable = util::self_executable();
  const CaseSummary summary = write_case(config, request, folder);
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

std::vector<SampleRow> draw_design(const StudyConfig& config) {
  sobol::DesignOptions options;
  options.kind = sobol::design_kind_from_string(config.design);
  options.samples = config.samples;
  options.dimension = static_cast<int>(config.parameters.size());
  options.seed = config.seed;
  // Reproducibility over speed: the iteration count alone ends the search (a wall-clock budget would make the
  // design depend on the machine's load).
  options.time_limit = std::numeric_limits<double>::infinity();
  const sobol::DesignResult design = sobol::make_design(options);
  std::vector<sobol::Bounds> bounds;
  for (const ParameterRange& p : config.parameters) bounds.push_back(p.bounds);
  const Eigen::MatrixXd physical = sobol::to_physical(design.points, bounds);
  std::vector<SampleRow> rows;
  for (int i = 0; i < design.points.rows(); ++i) {
    SampleRow row;
    row.sample = i;
    for (int j = 0; j < design.points.cols(); ++j) {
      row.unit.push_back(design.points(i, j));
      row.physical.push_back(physical(i, j));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

// ----------------------------------------------------------------------------------------------- run_study

namespace {

/// Opens the store of `dir` for `config`: creates design, samples and design.csv on a new study, refuses a changed
/// design-relevant setting.
Store open_study(const StudyConfig& config, const fs::path& study_file, const fs::path& dir, bool new_study) {
  const fs::path db = dir / k_store_file;
  if (new_study) {
    for (const char* name : {"study.db", "study.db-wal", "study.db-shm", k_design_file, "cases", "analysis"})
      fs::remove_all(dir / name);
  }
  Store store(db.string());
  const std::string hash = design_hash(config);
  if (const std::optional<std::string> stored = store.design_hash()) {
    if (*stored != hash)
      throw UserError(fmt::format(
          "{}: the design-relevant settings differ from those of the study in {} (design hash {} there, {} now); "
          "only [run] and [analysis] may change in an existing study. Use `demsa run --new` to discard it and start "
          "a new study there, or choose another --dir",
          study_file.string(), dir.string(), *stored, hash));
  } else {
    const std::vector<SampleRow> samples = draw_design(config);
    write_file_atomically(dir / k_design_file, design_csv(config, samples));
    store.initialize(hash, config.name, samples);
    store.add_event("created",
                    fmt::format("{} samples, design {}, seed {}", samples.size(), config.design, config.seed));
  }
  // The frozen copy: the design part is identical by the hash check; [run]/[analysis] follow the latest file.
  const fs::path frozen = dir / k_frozen_study;
  std::error_code ec;
  if (!fs::equivalent(study_file, frozen, ec)) write_file_atomically(frozen, util::read_file(study_file));
  return store;
}

struct InFlight {
  long run = 0;
  int sample = 0;
  int attempt = 1;
  long particles = 0;
};

}  // namespace

RunSummary run_study(const RunOptions& options) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  const StudyConfig config = load_study(options.study_file);
  RunSummary summary;
  summary.dir = options.dir.empty() ? default_study_dir(options.study_file) : options.dir;
  summary.dry_run = options.dry_run;
  const fs::path& dir = summary.dir;
  fs::create_directories(dir);
  const StudyLock lock(dir);
  Store store = open_study(config, options.study_file, dir, options.new_study);
  const std::vector<SampleRow> samples = store.samples();
  summary.samples = static_cast<int>(samples.size());
  const std::function<bool()> should_stop =
      options.should_stop ? options.should_stop : [] { return StopFlag::raised(); };

  if (options.dry_run) {
    // Validate every case by writing it (a case that breaks a LIGGGHTS limit throws UserError here).
    for (const SampleRow& s : samples) {
      const fs::path folder = case_dir(dir, s.sample);
      if (!fs::exists(folder / k_result_file)) prepare_case(config, s, folder);
    }
    summary.done = store.counts().done;
    summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  }

  if ((options.submit_only || options.collect_only) && config.run.executor != ExecutorKind::slurm)
    throw UserError(fmt::format(
        "{}: {} needs [run] executor = \"slurm\"; the local executor runs the cases inside `demsa run` itself",
        options.study_file.string(), options.submit_only ? "--submit-only" : "collecting submitted runs"));
  std::unique_ptr<Executor> executor = make_executor(config.run, dir);
  summary.executor = executor->name();
  const int parallel = config.run.executor == ExecutorKind::local ? local_parallel(config.run, machine_cores()) : 1;

  // Who is done, who has a run in flight.
  std::set<int> done;
  std::map<int, int> attempts;  // sample -> attempts that counted (not requeued)
  for (const RunRow& r : store.runs()) {
    if (r.state == RunState::done) done.insert(r.sample);
    if (r.state != RunState::requeued) attempts[r.sample] = std::max(attempts[r.sample], r.attempt);
  }

  std::map<std::string, InFlight> in_flight;  // keyed by case folder
  auto key = [&](int sample) { return case_dir(dir, sample).string(); };

  // Recover runs an earlier demsa left `submitted`. With submit_only they are left to the cluster (no polling):
  // they are only kept out of the queue.
  std::vector<SubmittedCase> adopt;
  std::set<int> left_submitted;
  for (const RunRow& r : store.runs_in_state(RunState::submitted)) {
    const fs::path folder = case_dir(dir, r.sample);
    if (const auto observables = read_result(folder, r.sample, r.id)) {
      RunOutcome outcome;
      outcome.exit_code = 0;
      outcome.message = "recovered from result.json after an interruption";
      store.record_done(r.id, outcome, *observables);
      done.insert(r.sample);
      ++summary.recovered;
      continue;
    }
    if (options.submit_only) {
      left_submitted.insert(r.sample);
      continue;
    }
    adopt.push_back({CaseTask{r.sample, r.attempt, folder}, r.job_id});
    in_flight[folder.string()] = InFlight{r.id, r.sample, r.attempt, configured_particles(config)};
  }
  if (!adopt.empty()) {
    store.add_event("resume", fmt::format("{} runs left in flight by an earlier demsa", adopt.size()));
    executor->adopt(adopt);
  }

  // This invocation gives every sample that is not done 1 + retries attempts.
  const int budget = 1 + std::max(0, config.run.retries);
  std::map<int, int> tries_now;
  std::deque<int> queue;
  if (!options.collect_only) {
    for (const SampleRow& s : samples)
      if (!done.count(s.sample) && !in_flight.count(key(s.sample)) && !left_submitted.count(s.sample))
        queue.push_back(s.sample);
  }

  const bool quiet = options.quiet || options.collect_only;
  Progress progress(quiet ? nullptr : stderr, Progress::is_terminal(stderr), options.progress_interval);
  std::vector<double> walls;
  for (const RunRow& r : store.runs())
    if (r.state == RunState::done && r.wall_seconds > 0) walls.push_back(r.wall_seconds);
  std::set<int> failed_final;
  auto counts = [&] {
    ProgressCounts c;
    c.done = static_cast<int>(done.size());
    c.running = static_cast<int>(in_flight.size());
    c.failed = static_cast<int>(failed_final.size());
    c.total = summary.samples;
    return c;
  };
  auto eta = [&] {
    double mean = 0;
    for (double w : walls) mean += w;
    mean = walls.empty() ? 0.0 : mean / static_cast<double>(walls.size());
    const int remaining = summary.samples - static_cast<int>(done.size()) - static_cast<int>(failed_final.size());
    return estimate_remaining(remaining, parallel, mean);
  };

  auto handle = [&](const FinishedCase& finished) {
    const auto it = in_flight.find(finished.task.folder.string());
    if (it == in_flight.end()) return;  // not ours (cannot happen with one runner per study)
    const InFlight flight = it->second;
    in_flight.erase(it);
    ++summary.collected;
    const fs::path folder = finished.task.folder;
    FailureReport report = classify_case(finished.exit, folder, failure_options(config, flight.particles));
    if (report.requeue) {
      store.record_requeued(flight.run, report.message);
      if (!finished.exit.detail.empty())
        store.add_event("requeued", fmt::format("run {}: {}: {}", flight.run, report.message, finished.exit.detail),
                        flight.sample);
      if (!should_stop() && !options.collect_only) queue.push_front(flight.sample);
      return;
    }
    RunOutcome outcome = outcome_from(finished.exit);
    std::map<std::string, double> observables;
    if (report.failure == FailureClass::none) {
      try {
        observables = measure_case(config, folder);
      } catch (const std::exception& e) {
        report.failure = FailureClass::measurement;
        report.message = e.what();
        report.log_tail = file_tail(folder / k_case_log, 30);
      }
    }
    attempts[flight.sample] = std::max(attempts[flight.sample], flight.attempt);
    if (report.failure == FailureClass::none) {
      nlohmann::json result;
      result["sample"] = flight.sample;
      result["run"] = flight.run;
      result["attempt"] = flight.attempt;
      result["observables"] = observables;
      result["exit_code"] = finished.exit.exit_code;
      result["wall_seconds"] = finished.exit.wall_seconds;
      result["cpu_seconds"] = finished.exit.cpu_seconds;
      result["host"] = finished.exit.host;
      write_file_atomically(folder / k_result_file, result.dump(2) + "\n");
      store.record_done(flight.run, outcome, observables);
      done.insert(flight.sample);
      ++summary.done_now;
      if (finished.exit.wall_seconds > 0) walls.push_back(finished.exit.wall_seconds);
      return;
    }
    outcome.failure = report.failure;
    outcome.message = report.message;
    outcome.log_tail = report.log_tail;
    store.record_failed(flight.run, outcome);
    ++summary.failures_by_class[to_string(outcome.failure)];
    if (options.collect_only) return;  // the next `demsa run` retries it
    if (tries_now[flight.sample] < budget && !should_stop())
      queue.push_back(flight.sample);
    else
      failed_final.insert(flight.sample);
  };

  // Polls the executor; first stores the real job ids it found for adopted runs that had only a provisional one.
  auto collect = [&](std::chrono::milliseconds wait) {
    const std::vector<FinishedCase> finished = executor->poll(wait);
    std::vector<std::pair<long, std::string>> learned;
    for (const SubmittedCase& found : executor->take_learned_ids()) {
      const auto it = in_flight.find(found.task.folder.string());
      if (it == in_flight.end()) continue;
      learned.emplace_back(it->second.run, found.job_id);
      store.add_event("adopted",
                      fmt::format("run {}: its array job was found by its submission token: SLURM task {}",
                                  it->second.run, found.job_id),
                      it->second.sample);
    }
    if (!learned.empty()) store.set_job_ids(learned);
    for (const FinishedCase& f : finished) handle(f);
  };

  if (options.collect_only) {
    // One look without waiting (squeue once, the sentinels once); what has not ended stays submitted.
    collect(std::chrono::milliseconds(0));
  }

  while (!options.collect_only && (!queue.empty() || (!options.submit_only && executor->in_flight() > 0)) &&
         !should_stop()) {
    std::vector<CaseTask> batch;
    std::vector<InFlight> flights;
    const int slots = executor->free_slots();
    while (static_cast<int>(batch.size()) < slots && !queue.empty()) {
      const int sample = queue.front();
      queue.pop_front();
      if (done.count(sample)) continue;
      const fs::path folder = case_dir(dir, sample);
      InFlight flight;
      flight.sample = sample;
      flight.attempt = attempts[sample] + 1;
      flight.particles = prepare_case(config, samples.at(static_cast<std::size_t>(sample)), folder);
      attempts[sample] = flight.attempt;
      ++tries_now[sample];
      batch.push_back(CaseTask{sample, flight.attempt, folder});
      flights.push_back(flight);
    }
    if (!batch.empty()) {
      // The run rows, with the ids the executor can find the tasks by (SLURM: the submission's token), are
      // committed in one transaction before anything starts: a crash at any point after it leaves runs to adopt,
      // never a process or an array job the store does not know how to find (that would run a case twice).
      const std::vector<std::string> reserved = executor->reserve_ids(batch);
      std::vector<NewRun> rows;
      for (std::size_t i = 0; i < batch.size(); ++i)
        rows.push_back(NewRun{flights[i].sample, flights[i].attempt, reserved.at(i)});
      const std::vector<long> runs = store.add_runs(rows);
      for (std::size_t i = 0; i < batch.size(); ++i) flights[i].run = runs.at(i);
      const std::vector<std::string> ids = executor->submit(batch);
      std::vector<std::pair<long, std::string>> job_ids;
      for (std::size_t i = 0; i < batch.size(); ++i) {
        job_ids.emplace_back(flights[i].run, ids.at(i));
        in_flight[batch[i].folder.string()] = flights[i];
      }
      store.set_job_ids(job_ids);
      summary.submitted += static_cast<int>(batch.size());
    }
    if (options.submit_only) continue;  // no polling: the cluster runs them, a later run or status collects
    collect(std::chrono::milliseconds(200));
    progress.update(counts(), eta());
  }

  if (!options.collect_only && should_stop()) {
    summary.interrupted = true;
    const std::string why =
        StopFlag::signal_number() != 0 ? fmt::format("signal {}", StopFlag::signal_number()) : std::string("stopped");
    // Local cases die with demsa anyway; SLURM tasks are cancelled only on request (they cost nothing to keep).
    // --submit-only never cancels what it submitted.
    bool cancel = !options.submit_only;
    if (cancel && config.run.executor == ExecutorKind::slurm && executor->in_flight() > 0)
      cancel = options.cancel_on_interrupt || (options.ask_cancel && options.ask_cancel(executor->in_flight()));
    if (cancel) {
      executor->cancel_all();
      collect(std::chrono::milliseconds(0));
      store.add_event("interrupted", why);
    } else {
      store.add_event("interrupted", fmt::format("{}; {} SLURM task(s) left running", why, in_flight.size()));
    }
  }
  progress.finish(counts());
  summary.left_running = static_cast<int>(in_flight.size() + left_submitted.size());

  summary.done = static_cast<int>(done.size());
  for (const SampleRow& s : samples)
    if (!done.count(s.sample) && failed_final.count(s.sample)) summary.failed_samples.push_back(s.sample);
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
