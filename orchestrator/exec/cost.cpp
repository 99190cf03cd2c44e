#include "orchestrator/exec/cost.hpp"

#include "orchestrator/exec/liggghts_locator.hpp"
#include "orchestrator/exec/local_executor.hpp"
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/process.hpp"
#include "orchestrator/util/signals.hpp"
#include "postprocess/error.hpp"
#include "postprocess/liggghts_log.hpp"
#include "postprocess/text.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>
#include <queue>
#include <sstream>

namespace demsa::exec {

namespace fs = std::filesystem;
using util::UserError;

namespace {

constexpr const char* k_rate_input =
    R"LIG(# demsa: the standard run that measures a LIGGGHTS's atom-steps per CPU-second (exec/cost.hpp)
atom_style      sphere
atom_modify     map array
boundary        f f f
newton          off
communicate     single vel yes
units           si
region          domain block -0.021 0.021 -0.021 0.021 0.0 0.08 units box
create_box      3 domain
neighbor        0.001 bin
neigh_modify    delay 0
fix m1 all property/global youngsModulus peratomtype 1e7 1e7 1e7
fix m2 all property/global poissonsRatio peratomtype 0.3 0.3 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 3 0.4 0.4 0.4 0.4 0.4 0.4 0.4 0.4 0.4
fix m4 all property/global coefficientFriction peratomtypepair 3 0.5 0.5 0.5 0.5 0.5 0.5 0.5 0.5 0.5
fix m5 all property/global coefficientRollingFriction peratomtypepair 3 0.1 0.1 0.1 0.1 0.1 0.1 0.1 0.1 0.1
pair_style      gran model hertz tangential history rolling_friction cdt
pair_coeff      * *
timestep        1e-5
fix             gravi all gravity 9.81 vector 0.0 0.0 -1.0
fix             floor all wall/gran model hertz tangential history rolling_friction cdt primitive type 3 zplane 0.0
fix             xlo all wall/gran model hertz tangential history rolling_friction cdt primitive type 3 xplane -0.02
fix             xhi all wall/gran model hertz tangential history rolling_friction cdt primitive type 3 xplane 0.02
fix             ylo all wall/gran model hertz tangential history rolling_friction cdt primitive type 3 yplane -0.02
fix             yhi all wall/gran model hertz tangential history rolling_friction cdt primitive type 3 yplane 0.02
region          fill block -0.0185 0.0185 -0.0185 0.0185 0.0015 0.06 units box
lattice         fcc 0.0042426
create_atoms    1 region fill
set             group all diameter 0.003 density 2500
fix             integr all nve/sphere
thermo          1000
run             1000
run             4000
)LIG";

/// The JSON of `file`; discarded (is_discarded()) when it is missing or not JSON. The rate cache and the probe hold
/// only measurements: one that is not ours (cut, edited) is measured again rather than refused.
nlohmann::json read_measurement(const fs::path& file) {
  // A FIFO would wait for a writer for ever: refused, naming the file (DEMSA_RATE_CACHE, the study's probe).
  if (const std::optional<std::string> kind = postprocess::special_file_kind(file))
    throw UserError(file.string(), 0, postprocess::special_file_message(*kind));
  std::ifstream in(file);
  if (!in) return nlohmann::json(nlohmann::json::value_t::discarded);
  std::stringstream text;
  text << in.rdbuf();
  return nlohmann::json::parse(text.str(), nullptr, false);
}

/// The share of its cores a run had: its CPU time (wait4's rusage) over its wall time on `ranks` cores, at most 1. A
/// LIGGGHTS log's loop times are wall time; times this share they are the loops' CPU time on a loaded machine. 1 when
/// the run measured no CPU or is shorter than its loops (a log it did not write).
double core_share(const util::CaptureResult& run, int ranks, double loop_seconds) {
  if (!(run.cpu_seconds > 0.0) || run.wall_seconds < loop_seconds || !(run.wall_seconds > 0.0)) return 1.0;
  return std::min(1.0, run.cpu_seconds / (run.wall_seconds * std::max(1, ranks)));
}

/// Now, in UTC, as 2026-12-03T15:46:20Z: when a measurement was taken.
std::string utc_now() {
  const auto now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char when[32];
  std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return when;
}

nlohmann::json read_cache(const fs::path& file) {
  nlohmann::json doc = read_measurement(file);
  // A cache that is not ours (cut, edited) is measured again rather than refused: it holds nothing but measurements.
  if (!doc.is_object() || !doc.contains("rates") || !doc["rates"].is_array()) return nlohmann::json::object();
  return doc;
}

std::string seconds_text(double s) {
  if (s < 120.0) return fmt::format("{:.0f} s", s);
  if (s < 2.0 * 3600.0) return fmt::format("{:.1f} min", s / 60.0);
  return fmt::format("{:.1f} h", s / 3600.0);
}

}  // namespace

BinaryKey binary_key(const std::string& executable) {
  const std::optional<std::string> found = find_on_path(executable);
  if (!found) throw UserError(fmt::format("{}: no such LIGGGHTS executable", executable));
  std::error_code ec;
  const fs::path path = fs::canonical(*found, ec);
  if (ec) throw UserError(fmt::format("{}: {}", *found, ec.message()));
  BinaryKey key;
  key.path = path.string();
  key.size = fs::file_size(path);
  key.mtime_ns =
      static_cast<std::int64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                    std::chrono::file_clock::to_sys(fs::last_write_time(path)).time_since_epoch())
                                    .count());
  return key;
}

fs::path rate_cache_file() {
  if (const char* env = std::getenv("DEMSA_RATE_CACHE"); env != nullptr && *env != '\0') return env;
  return liggghts_cache_dir() / "liggghts-rates.json";
}

std::string rate_benchmark_input() { return k_rate_input; }

bool plausible_rate(double rate) { return rate >= k_min_plausible_rate && rate <= k_max_plausible_rate; }

std::optional<LiggghtsRate> cached_rate(const std::string& executable, const fs::path& cache_file) {
  const BinaryKey key = binary_key(executable);
  const nlohmann::json doc = read_cache(cache_file);
  if (!doc.contains("rates")) return std::nullopt;
  for (const nlohmann::json& e : doc["rates"]) {
    if (!e.is_object() || !e.contains("binary") || !e["binary"].is_string() || e["binary"] != key.path) continue;
    // An entry of the wrong types (edited, written by another program) is measured again, never read as a default.
    const auto field = [&](const char* name) { return e.contains(name) ? &e[name] : nullptr; };
    const nlohmann::json* size = field("size");
    const nlohmann::json* mtime = field("mtime_ns");
    const nlohmann::json* rate = field("atom_steps_per_cpu_second");
    if (size == nullptr || !size->is_number_unsigned() || mtime == nullptr || !mtime->is_number_integer() ||
        rate == nullptr || !rate->is_number())
      return std::nullopt;
    if (size->get<std::uintmax_t>() != key.size || mtime->get<std::int64_t>() != key.mtime_ns)
      return std::nullopt;  // the binary changed since it was measured
    if (!plausible_rate(rate->get<double>())) return std::nullopt;
    const nlohmann::json* when = field("measured_at");
    return LiggghtsRate{
        rate->get<double>(),
        fmt::format("the standard run of {} measured {} (cached in {})", key.path,
                    when != nullptr && when->is_string() ? when->get<std::string>() : "earlier", cache_file.string())};
  }
  return std::nullopt;
}

LiggghtsRate machine_rate(const std::string& executable, const fs::path& cache_file) {
  if (std::optional<LiggghtsRate> cached = cached_rate(executable, cache_file)) return *cached;
  const BinaryKey key = binary_key(executable);
  const fs::path work = cache_file.parent_path() / fmt::format("rate-run-{}", ::getpid());
  fs::create_directories(work);
  util::write_file_atomically(work / "rate.liggghts", rate_benchmark_input());
  util::CaptureOptions options;
  options.cwd = work;
  options.merge_stderr = true;
  options.timeout = std::chrono::minutes(5);
  const util::CaptureResult r =
      util::run_capture({key.path, "-in", "rate.liggghts", "-log", "log.rate", "-screen", "none"}, options);
  std::optional<postprocess::LoopSummary> last;
  if (fs::exists(work / "log.rate")) {
    const postprocess::LiggghtsLog log = postprocess::read_liggghts_log(work / "log.rate");
    if (!log.loops.empty()) last = log.loops.back();
  }
  std::error_code ec;
  fs::remove_all(work, ec);
  if (r.exit_code != 0 || !last || !(last->seconds > 0.0) || last->steps <= 0 || last->atoms <= 0)
    throw UserError(fmt::format("{}: the standard run that measures its speed failed (exit {}{}): {}", key.path,
                                r.exit_code, r.timed_out ? ", timed out" : "",
                                r.start_error.empty() ? std::string("no `Loop time` line in its log") : r.start_error));
  // The last run only: the first starts the packing (neighbour lists, contact histories). Its loop time is wall time;
  // on a loaded machine the run had only a share of a core, so the loop's CPU time is its wall time times the share
  // the whole run had: its CPU time from wait4's rusage over its wall time, at most one core per rank (a log whose loop
  // outlasts the run it came from is taken as it is).
  const double atom_steps = static_cast<double>(last->steps) * static_cast<double>(last->atoms);
  const int ranks = std::max(1, last->procs);
  const double cpu = last->seconds * ranks * core_share(r, ranks, last->seconds);
  const double rate = atom_steps / cpu;
  if (!plausible_rate(rate))
    throw UserError(fmt::format(
        "{}: the standard run measured {:.3g} atom-steps per CPU-second, outside [{:.0e}, {:.0e}]: no LIGGGHTS runs "
        "at that speed (its log: {} steps of {} atoms in {:.3g} s); not cached",
        key.path, rate, k_min_plausible_rate, k_max_plausible_rate, last->steps, last->atoms, last->seconds));
  const std::string when = utc_now();
  nlohmann::json doc = read_cache(cache_file);
  if (!doc.contains("rates")) doc = {{"rates", nlohmann::json::array()}};
  nlohmann::json kept = nlohmann::json::array();
  for (const nlohmann::json& e : doc["rates"])
    if (e.is_object() && e.value("binary", "") != key.path) kept.push_back(e);
  kept.push_back({{"binary", key.path},
                  {"size", key.size},
                  {"mtime_ns", key.mtime_ns},
                  {"atom_steps_per_cpu_second", rate},
                  {"atom_steps", atom_steps},
                  {"cpu_seconds", cpu},
                  {"measured_at", when}});
  doc["rates"] = kept;
  fs::create_directories(cache_file.parent_path());
  util::write_file_atomically(cache_file, doc.dump(2) + "\n");
  return LiggghtsRate{rate, fmt::format("the standard run of {} measured now ({:.3g} atom-steps in {:.2f} CPU-s; "
                                        "cached in {})",
                                        key.path, atom_steps, cpu, cache_file.string())};
}

std::optional<CaseActual> case_actual(const fs::path& case_dir) {
  const fs::path log = case_dir / study::k_case_log;
  if (!fs::exists(log)) return std::nullopt;
  const postprocess::LiggghtsLog parsed = postprocess::read_liggghts_log(log);
  if (parsed.loops.empty()) return std::nullopt;
  CaseActual a;
  for (const postprocess::LoopSummary& l : parsed.loops) {
    a.atom_steps += static_cast<double>(l.steps) * static_cast<double>(l.atoms);
    a.cpu_seconds += l.seconds * std::max(1, l.procs);
  }
  return a;
}

namespace {

/// The case's cost by its experiment's model, with what the study's probe learnt (`probed`, null: nothing; the cap
/// does not depend on it).
std::optional<experiments::CaseCost> case_cost_of(const study::StudyConfig& config, const fs::path& case_dir,
                                                  const nlohmann::json& probed = nullptr) {
  if (!fs::exists(case_dir / study::k_case_json)) return std::nullopt;
  const experiments::Experiment& experiment = experiments::of(config);
  if (experiment.case_cost == nullptr) return std::nullopt;
  const nlohmann::json doc = experiments::read_case_json(case_dir);
  return experiment.case_cost(config, doc, case_dir / study::k_case_json, probed);
}

}  // namespace

std::optional<double> case_cap_atom_steps(const study::StudyConfig& config, const fs::path& case_dir) {
  const std::optional<experiments::CaseCost> c = case_cost_of(config, case_dir);
  if (!c) return std::nullopt;
  return c->atom_steps;
}

namespace {

/// A probe as JSON: DIR/cost_probe.json and the estimate's "probe" (read_probe reads these keys back).
nlohmann::ordered_json probe_json(const ProbeResult& p) {
  return {{"sample", p.sample},
          {"budget_seconds", p.budget_seconds},
          {"finished", p.finished},
          {"cap_atom_steps", p.cap_atom_steps},
          {"atom_steps", p.atom_steps},
          {"cpu_seconds", p.cpu_seconds},
          {"atom_steps_per_cpu_second", p.rate},
          {"binary", p.binary},
          {"binary_mtime_ns", p.binary_mtime_ns},
          {"measured_at", p.measured_at},
          {"state", p.state}};
}

}  // namespace

void check_probe_budget(double budget_seconds) {
  // A budget that rounds to 0 ms would be run_capture's "no timeout": the probe would run the whole case.
  if (!(budget_seconds >= k_min_probe_seconds) || !std::isfinite(budget_seconds))
    throw UserError(
        fmt::format("--probe {}: give at least {:g} s (LIGGGHTS alone takes a fraction of a second to "
                    "start; a shorter budget measures nothing)",
                    budget_seconds, k_min_probe_seconds));
}

ProbeResult probe_study(const study::StudyConfig& config, const fs::path& dir, double budget_seconds) {
  check_probe_budget(budget_seconds);
  const study::Store store = study::Store::open_read_only((dir / study::k_store_file).string());
  const std::vector<study::SampleRow> samples = store.samples();
  if (samples.empty()) throw UserError(fmt::format("{}: the study has no samples to probe", dir.string()));
  const int sample = samples.front().sample;
  const fs::path folder = study::case_dir(dir, sample);
  const std::optional<experiments::CaseCost> cost = case_cost_of(config, folder);
  if (!cost)
    throw UserError(
        fmt::format("{}: no estimate of this case's schedule (its experiment has no case_cost): nothing to "
                    "probe against",
                    folder.string()));
  const std::optional<std::string> exe = find_on_path(config.run.liggghts);
  if (!exe) throw UserError(fmt::format("{}: no such LIGGGHTS executable", config.run.liggghts));
  const BinaryKey key = binary_key(*exe);
  // A copy of the case's own files (not its outputs' folders), run as the executor runs it: ./run.sh.
  const fs::path work = dir / study::k_cost_probe_folder;
  fs::remove_all(work);
  fs::create_directories(work);
  for (const fs::directory_entry& e : fs::directory_iterator(folder))
    if (e.is_regular_file()) fs::copy_file(e.path(), work / e.path().filename());
  for (const char* output : {study::k_case_log, study::k_case_screen, study::k_result_file, study::k_run_output_file})
    fs::remove(work / output);
  util::CaptureOptions options;
  options.cwd = work;
  options.merge_stderr = true;
  options.timeout =
      std::chrono::milliseconds(static_cast<long long>(std::ceil(std::min(budget_seconds, 1e9) * 1000.0)));
  options.should_stop = [] { return util::StopFlag::raised(); };  // Ctrl-C: its own process group does not see it
  const util::CaptureResult r = util::run_capture({"./" + std::string(study::k_case_run_script)}, options);
  if (r.stopped) {
    std::error_code ec;
    fs::remove_all(work, ec);
    throw util::StopRequested();  // nothing stored; run_cli() returns 128 + the signal
  }
  ProbeResult p;
  p.sample = sample;
  p.budget_seconds = budget_seconds;
  p.cap_atom_steps = cost->atom_steps;
  p.binary = key.path;
  p.binary_mtime_ns = key.mtime_ns;
  p.finished = !r.timed_out && r.exit_code == 0;
  // Its complete LIGGGHTS runs, as a finished case's: atom-steps and loop time (wall time) on every rank.
  const CaseActual loops = case_actual(work).value_or(CaseActual{});
  p.atom_steps = loops.atom_steps;
  if (const experiments::Experiment& experiment = experiments::of(config); experiment.probe_state != nullptr) {
    try {
      p.state = experiment.probe_state(work);
    } catch (const postprocess::ParseError&) {
      // A file the case was still writing when the budget killed it: the probe's rate stands without its state.
    }
  }
  const double loop_cpu = loops.cpu_seconds;
  // A probe that failed, or ran no LIGGGHTS run to its end, keeps its folder for the user to look into.
  const bool failed = !r.timed_out && r.exit_code != 0;
  const bool measured = p.atom_steps > 0.0 && loop_cpu > 0.0;
  std::string kept;
  if (failed || !measured) {
    kept = fmt::format(" (its folder is kept: {})", work.string());
  } else {
    std::error_code ec;
    fs::remove_all(work, ec);
  }
  if (failed)
    throw UserError(fmt::format("the probe of sample {} failed: ./run.sh exited with {}{}", sample, r.exit_code, kept));
  if (!measured)
    throw UserError(
        fmt::format("the probe of sample {} completed no LIGGGHTS run in {:.0f} s: give --probe more "
                    "seconds{}",
                    sample, budget_seconds, kept));
  if (p.finished && r.cpu_seconds > 0.0) {
    p.cpu_seconds = r.cpu_seconds;  // what the runner will count: the run's rusage
  } else if (r.timed_out) {
    // The loop times are wall time. A run its budget killed has no share of a core to credit them with: its rusage
    // misses the processes its killed parents never waited for (an in-process driver under mpirun read 0.04 CPU-s
    // for 900 s of loops).
    p.cpu_seconds = loop_cpu;
  } else {
    // The loop times are wall time: credit them with the share of a core the run had (as the standard run).
    const int ranks = std::max(1, config.run.ranks);
    p.cpu_seconds = loop_cpu * core_share(r, ranks, loop_cpu / ranks);
  }
  p.rate = p.atom_steps / p.cpu_seconds;
  p.measured_at = utc_now();
  util::write_file_atomically(dir / study::k_cost_probe_file, probe_json(p).dump(2) + "\n");
  return p;
}

std::optional<ProbeResult> read_probe(const study::StudyConfig& config, const fs::path& dir) {
  const nlohmann::json j = read_measurement(dir / study::k_cost_probe_file);
  if (!j.is_object()) return std::nullopt;  // none, or not ours: `--probe` measures again
  ProbeResult p;
  try {
    p.sample = j.at("sample").get<int>();
    p.budget_seconds = j.at("budget_seconds").get<double>();
    p.finished = j.at("finished").get<bool>();
    p.cap_atom_steps = j.at("cap_atom_steps").get<double>();
    p.atom_steps = j.at("atom_steps").get<double>();
    p.cpu_seconds = j.at("cpu_seconds").get<double>();
    p.rate = j.at("atom_steps_per_cpu_second").get<double>();
    p.binary = j.at("binary").get<std::string>();
    p.binary_mtime_ns = j.at("binary_mtime_ns").get<std::int64_t>();
    p.measured_at = j.at("measured_at").get<std::string>();
    p.state = j.value("state", nlohmann::json());  // none in a probe of an older demsa
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
  if (!(p.rate > 0.0) || !std::isfinite(p.rate) || !(p.cap_atom_steps > 0.0)) return std::nullopt;
  // The same LIGGGHTS binary, and the same case (its schedule's cap).
  const std::optional<std::string> exe = find_on_path(config.run.liggghts);
  if (!exe) return std::nullopt;
  try {
    const BinaryKey key = binary_key(*exe);
    if (key.path != p.binary || key.mtime_ns != p.binary_mtime_ns) return std::nullopt;
  } catch (const UserError&) {
    return std::nullopt;
  }
  const std::optional<experiments::CaseCost> cost = case_cost_of(config, study::case_dir(dir, p.sample));
  if (!cost || std::abs(cost->atom_steps - p.cap_atom_steps) > 1e-9 * p.cap_atom_steps) return std::nullopt;
  return p;
}

std::string probe_text(const ProbeResult& p) {
  return fmt::format(
      "probe: sample {} {} {:.0f} s: {:.3g} atom-steps in {:.1f} CPU-s, {:.3g} per CPU-second{}\n", p.sample,
      p.finished ? "ran to its end within" : "was stopped after", p.budget_seconds, p.atom_steps, p.cpu_seconds, p.rate,
      p.finished ? fmt::format("; {:.3f} of its cap", p.atom_steps / p.cap_atom_steps)
                 : fmt::format(" ({:.1f} % of its cap; its rate is not used: the start of a case is not its "
                               "average, give --probe the seconds of a whole case)",
                               100.0 * p.atom_steps / p.cap_atom_steps));
}

StudyEstimate estimate(const EstimateInput& input) {
  StudyEstimate e;
  e.probe = input.probe;
  e.slots = std::max(1, input.slots);
  e.ranks = std::max(1, input.ranks);
  // What a case is expected to cost before any ratio: the experiment's model when it has one, else its cap.
  const auto expected = [](const CaseCostInput& c) {
    return c.expected_atom_steps > 0.0 ? std::min(c.expected_atom_steps, c.cap_atom_steps) : c.cap_atom_steps;
  };
  const bool modelled = std::any_of(input.cases.begin(), input.cases.end(),
                                    [](const CaseCostInput& c) { return c.expected_atom_steps > 0.0; });
  const std::string basis = modelled ? fmt::format("the expected atom-steps ({})",
                                                   input.expected_source.empty() ? std::string("the experiment's model")
                                                                                 : input.expected_source)
                                     : std::string("the schedule's cap");
  double early_expected = 0.0, early_actual = 0.0, atom_steps = 0.0, cpu = 0.0;
  int early_finished = 0;
  for (const CaseCostInput& c : input.cases) {
    if (!c.actual) continue;
    ++e.finished;
    atom_steps += c.actual->atom_steps;
    cpu += c.actual->cpu_seconds;
    if (c.may_end_early && expected(c) > 0.0) {
      early_expected += expected(c);
      early_actual += c.actual->atom_steps;
      ++early_finished;
    }
  }
  const std::optional<ProbeResult>& probe = input.probe;
  if (early_expected > 0.0) {
    const double observed = early_actual / early_expected;
    // Bühlmann's credibility: n finished cases weigh n / (n + k) against the model's ratio of 1.
    const double k = modelled ? std::max(0.0, input.expected_weight) : 0.0;
    const double weight = early_finished / (early_finished + k);
    e.early_ratio = weight * observed + (1.0 - weight);
    e.atom_step_source =
        k > 0.0 ? fmt::format(
                      "{} x {:.3f}: the ratio actual / expected of the study's {} finished case(s), {:.3f}, "
                      "weighed {}/({} + {:g}) against the model's 1",
                      basis, e.early_ratio, early_finished, observed, early_finished, early_finished, k)
                : fmt::format("{} x {:.3f}, the ratio actual / expected of the study's finished cases", basis,
                              e.early_ratio);
  } else if (modelled) {
    // A probe's one case measures the rate, not the model's error: one servo oedometer case's actual / expected ranged
    // from 0.37 to 2.36 in 31 cases, while the model's total held a study it was not fitted on to 0.93 of its
    // atom-steps (docs/how-to/cost.md).
    e.atom_step_source = basis;
  } else if (probe && probe->finished && probe->cap_atom_steps > 0.0) {
    e.early_ratio = probe->atom_steps / probe->cap_atom_steps;
    e.atom_step_source = fmt::format(
        "the schedule's cap x {:.3f} for a case that may end early, the ratio actual / cap of the probe (sample {}, "
        "run to its end {})",
        e.early_ratio, probe->sample, probe->measured_at);
  } else {
    e.atom_step_source =
        "the schedule's cap (no finished case yet: a case that ends early or removes particles costs "
        "less)";
  }
  if (e.finished > 0 && cpu > 0.0) {
    e.rate = atom_steps / cpu;
    e.rate_source =
        fmt::format("this study's {} finished case(s): {:.3g} atom-steps in {:.0f} CPU-s", e.finished, atom_steps, cpu);
  } else if (probe && probe->finished && probe->rate > 0.0) {
    // Only a probe that ran its case to the end: the start of a case is not its average (a set-1 pile's first 7 % of
    // atom-steps ran 1.8 times as fast as the whole case, docs/how-to/cost.md).
    e.rate = probe->rate;
    e.rate_source = fmt::format("the probe of sample {} ({:.3g} atom-steps in {:.1f} CPU-s, run to its end; {})",
                                probe->sample, probe->atom_steps, probe->cpu_seconds, probe->measured_at);
  } else if (input.rate && input.rate->atom_steps_per_cpu_second > 0.0) {
    const double factor = input.rate_factor > 0.0 ? input.rate_factor : 1.0;
    e.rate = input.rate->atom_steps_per_cpu_second * factor;
    e.rate_source = factor == 1.0 ? input.rate->source
                                  : fmt::format("{}, {}", input.rate->source,
                                                input.rate_factor_source.empty()
                                                    ? fmt::format("x {:.3f}, the experiment's rate over it", factor)
                                                    : input.rate_factor_source);
  } else {
    e.rate_source = input.rate_failure.empty() ? "none: no finished case and no measured rate of this LIGGGHTS"
                                               : fmt::format("none: {}", input.rate_failure);
  }
  // Graham's list scheduling: each case, in order, on the slot that frees first.
  std::priority_queue<double, std::vector<double>, std::greater<>> all_slots, left_slots;
  for (int i = 0; i < e.slots; ++i) {
    all_slots.push(0.0);
    left_slots.push(0.0);
  }
  const auto schedule = [](std::priority_queue<double, std::vector<double>, std::greater<>>& q, double wall) {
    const double start = q.top();
    q.pop();
    q.push(start + wall);
    return start + wall;
  };
  for (const CaseCostInput& c : input.cases) {
    CaseEstimate ce;
    ce.sample = c.sample;
    ce.cap_atom_steps = c.cap_atom_steps;
    ce.actual = c.actual;
    if (c.actual) {
      ce.atom_steps = c.actual->atom_steps;
      ce.cpu_seconds = c.actual->cpu_seconds;
    } else {
      ce.atom_steps = c.may_end_early ? expected(c) * e.early_ratio : c.cap_atom_steps;
      ce.cpu_seconds = e.rate > 0.0 ? ce.atom_steps / e.rate : 0.0;
    }
    // A case of R ranks spends its CPU on R cores at once (its loop time x R is its CPU).
    ce.wall_seconds = ce.cpu_seconds / e.ranks;
    e.atom_steps += ce.atom_steps;
    e.cpu_seconds += ce.cpu_seconds;
    e.wall_seconds = std::max(e.wall_seconds, schedule(all_slots, ce.wall_seconds));
    if (!c.actual) {
      e.remaining_atom_steps += ce.atom_steps;
      e.remaining_cpu_seconds += ce.cpu_seconds;
      e.remaining_wall_seconds = std::max(e.remaining_wall_seconds, schedule(left_slots, ce.wall_seconds));
    }
    e.cases.push_back(ce);
  }
  return e;
}

namespace {

int executor_slots(const study::RunSettings& run, int cases) {
  if (run.executor == study::ExecutorKind::slurm)
    return run.slurm.throttle > 0 ? std::min(run.slurm.throttle, std::max(1, cases)) : std::max(1, cases);
  try {
    return local_parallel(run, machine_cores());
  } catch (const UserError&) {
    return std::max(1, run.parallel);  // an oversubscribed study: `demsa run` refuses it, the bill counts its slots
  }
}

}  // namespace

StudyEstimate estimate_study(const study::StudyConfig& config, const fs::path& dir, const StudyCostOptions& options) {
  const study::Store store = study::Store::open_read_only((dir / study::k_store_file).string());
  std::vector<int> order;
  for (const study::SampleRow& s : store.samples()) order.push_back(s.sample);
  for (const study::ReplicateRow& r : store.replicates()) order.push_back(r.sample);
  std::map<int, study::CaseCostRow> recorded;
  std::map<int, bool> done;
  for (const study::RunRow& r : store.runs())
    if (r.state == study::RunState::done) done[r.sample] = true;
  for (const study::CaseCostRow& r : store.case_costs())
    if (done.count(r.sample) != 0) recorded[r.sample] = r;

  EstimateInput input;
  input.ranks = config.run.ranks;
  input.slots = executor_slots(config.run, static_cast<int>(order.size()));
  input.probe = read_probe(config, dir);
  const nlohmann::json probed = input.probe ? input.probe->state : nlohmann::json();
  for (const int sample : order) {
    const fs::path folder = study::case_dir(dir, sample);
    const std::optional<experiments::CaseCost> cost = case_cost_of(config, folder, probed);
    if (!cost) continue;
    CaseCostInput c{sample, cost->atom_steps, cost->may_end_early, std::nullopt, cost->expected_atom_steps};
    if (input.cases.empty()) {
      input.rate_factor = cost->rate_factor;
      input.rate_factor_source = cost->rate_factor_source;
      input.expected_source = cost->expected;
      input.expected_weight = cost->expected_weight;
    }
    if (done.count(sample) != 0) {
      if (const auto it = recorded.find(sample); it != recorded.end())
        c.actual = CaseActual{it->second.atom_steps, it->second.cpu_seconds};
      else
        c.actual = case_actual(folder);  // a run an older demsa committed: its log
    }
    input.cases.push_back(c);
  }
  // A rate cache that is a FIFO or a device is the user's mistake to fix, not a rate that could not be measured.
  if (const std::optional<std::string> kind = postprocess::special_file_kind(options.cache_file))
    throw UserError(options.cache_file.string(), 0, postprocess::special_file_message(*kind));
  if (const std::optional<std::string> exe = find_on_path(config.run.liggghts)) {
    try {
      input.rate = options.measure_rate ? std::optional<LiggghtsRate>(machine_rate(*exe, options.cache_file))
                                        : cached_rate(*exe, options.cache_file);
    } catch (const UserError& e) {
      // The bill goes without a rate (atom-steps only) rather than failing the dry run that validated the study.
      input.rate_failure = e.what();
    }
  }
  return estimate(input);
}

nlohmann::ordered_json estimate_json(const StudyEstimate& e) {
  const nlohmann::ordered_json probe = e.probe ? probe_json(*e.probe) : nlohmann::ordered_json(nullptr);
  nlohmann::ordered_json cases = nlohmann::ordered_json::array();
  for (const CaseEstimate& c : e.cases) {
    nlohmann::ordered_json j{
        {"sample", c.sample},           {"cap_atom_steps", c.cap_atom_steps}, {"atom_steps", c.atom_steps},
        {"cpu_seconds", c.cpu_seconds}, {"wall_seconds", c.wall_seconds},     {"finished", c.actual.has_value()}};
    cases.push_back(j);
  }
  return {{"estimate",
           {{"atom_steps", e.atom_steps},
            {"cpu_seconds", e.cpu_seconds},
            {"wall_seconds", e.wall_seconds},
            {"cpu_hours", e.cpu_seconds / 3600.0},
            {"remaining_atom_steps", e.remaining_atom_steps},
            {"remaining_cpu_seconds", e.remaining_cpu_seconds},
            {"remaining_wall_seconds", e.remaining_wall_seconds},
            {"finished_cases", e.finished},
            {"early_ratio", e.early_ratio},
            {"atom_steps_source", e.atom_step_source},
            {"rate_atom_steps_per_cpu_second", e.rate},
            {"rate_source", e.rate_source},
            {"slots", e.slots},
            {"ranks", e.ranks},
            {"probe", probe},
            {"cases", cases}}}};
}

std::string estimate_text(const StudyEstimate& e) {
  double lo = 0.0, hi = 0.0;
  for (const CaseEstimate& c : e.cases) {
    lo = lo == 0.0 ? c.atom_steps : std::min(lo, c.atom_steps);
    hi = std::max(hi, c.atom_steps);
  }
  std::string s = fmt::format("estimate: {} cases, {:.3g}-{:.3g} atom-steps each, {:.3g} in all ({} finished)\n",
                              e.cases.size(), lo, hi, e.atom_steps, e.finished);
  if (e.probe) s += "  " + probe_text(*e.probe);
  s += fmt::format("  atom-steps: {}\n", e.atom_step_source);
  if (e.rate > 0.0) {
    s += fmt::format("  rate: {:.3g} atom-steps per CPU-second, from {}\n", e.rate, e.rate_source);
    s +=
        fmt::format("  CPU: {} ({:.2f} CPU-hours); wall: {} on {} slot(s) of {} rank(s)\n", seconds_text(e.cpu_seconds),
                    e.cpu_seconds / 3600.0, seconds_text(e.wall_seconds), e.slots, e.ranks);
    if (e.finished > 0)
      s += fmt::format("  left: {:.3g} atom-steps, {} CPU, {} wall\n", e.remaining_atom_steps,
                       seconds_text(e.remaining_cpu_seconds), seconds_text(e.remaining_wall_seconds));
  } else {
    s += fmt::format("  rate: {}; `demsa run STUDY --dry-run` measures it\n", e.rate_source);
  }
  return s;
}

std::string predicted_vs_actual_table(const std::vector<study::CaseCostRow>& rows) {
  std::string s =
      "| sample | cap atom-steps | predicted atom-steps | actual atom-steps | actual / predicted | predicted CPU [s] | "
      "actual CPU [s] | actual / predicted CPU |\n|---|---|---|---|---|---|---|---|\n";
  for (const study::CaseCostRow& r : rows) {
    const std::string cpu_ratio =
        r.predicted_cpu_seconds > 0.0 ? fmt::format("{:.2f}", r.cpu_seconds / r.predicted_cpu_seconds) : "-";
    const std::string cpu_pred = r.predicted_cpu_seconds > 0.0 ? fmt::format("{:.1f}", r.predicted_cpu_seconds) : "-";
    s += fmt::format("| {} | {:.3g} | {:.3g} | {:.3g} | {:.2f} | {} | {:.1f} | {} |\n", r.sample, r.cap_atom_steps,
                     r.predicted_atom_steps, r.atom_steps,
                     r.predicted_atom_steps > 0.0 ? r.atom_steps / r.predicted_atom_steps : 0.0, cpu_pred,
                     r.cpu_seconds, cpu_ratio);
  }
  return s;
}

std::optional<study::CaseCostRow> case_cost_row(const study::StudyConfig& config, const fs::path& dir,
                                                const fs::path& case_dir, long run, int sample,
                                                const std::vector<study::CaseCostRow>& before) {
  const std::optional<ProbeResult> probe = read_probe(config, dir);
  const nlohmann::json probed = probe ? probe->state : nlohmann::json();
  const std::optional<experiments::CaseCost> cost = case_cost_of(config, case_dir, probed);
  const std::optional<CaseActual> actual = case_actual(case_dir);
  if (!cost || !actual) return std::nullopt;
  EstimateInput input;
  input.rate_factor = cost->rate_factor;
  input.rate_factor_source = cost->rate_factor_source;
  input.expected_source = cost->expected;
  input.expected_weight = cost->expected_weight;
  for (const study::CaseCostRow& r : before) {
    // The model's expectation of a case done before, from its folder (the store keeps its cap, not its expectation).
    std::optional<experiments::CaseCost> earlier;
    if (cost->expected_atom_steps > 0.0) earlier = case_cost_of(config, study::case_dir(dir, r.sample), probed);
    input.cases.push_back({r.sample, r.cap_atom_steps, true, CaseActual{r.atom_steps, r.cpu_seconds},
                           earlier ? earlier->expected_atom_steps : 0.0});
  }
  input.cases.push_back({sample, cost->atom_steps, cost->may_end_early, std::nullopt, cost->expected_atom_steps});
  // The cases done before set the rate and the ratio when there are any; else the probe, else the machine's rate.
  if (before.empty()) {
    input.probe = probe;
    if (const std::optional<std::string> exe = find_on_path(config.run.liggghts))
      input.rate = cached_rate(*exe, rate_cache_file());
  }
  const StudyEstimate e = estimate(input);
  study::CaseCostRow row;
  row.run = run;
  row.sample = sample;
  row.cap_atom_steps = cost->atom_steps;
  row.predicted_atom_steps = e.cases.back().atom_steps;
  row.predicted_cpu_seconds = e.cases.back().cpu_seconds;
  row.atom_steps = actual->atom_steps;
  row.cpu_seconds = actual->cpu_seconds;
  return row;
}

namespace {

/// "LIGGGHTS 3.8.0 (/usr/bin/liggghts); rolling models: cdt, epsd, ...": read from its `-h` (query_liggghts_at), and
/// its rate when demsa's standard run measured it (the rate cache; a cache that cannot be read is left out).
std::string liggghts_info_text(const std::string& what, const LiggghtsInfo& info) {
  std::string text =
      info.version.empty()
          ? fmt::format("{}: found at {}, but its version could not be read from `-h`\n", what, info.executable)
          : fmt::format("{} {} ({})\n", what, info.version, info.executable);
  std::string models;
  for (const std::string& m : info.rolling_models) models += (models.empty() ? "" : ", ") + m;
  text += fmt::format("  rolling models: {}\n", models.empty() ? "unknown (not listed by `-h`)" : models);
  try {
    if (const std::optional<LiggghtsRate> rate = cached_rate(info.executable, rate_cache_file()))
      text += fmt::format("  speed: {:.3g} atom-steps per CPU-second ({})\n", rate->atom_steps_per_cpu_second,
                          rate->source);
  } catch (const std::exception&) {
  }
  return text;
}

}  // namespace

std::string liggghts_text() {
  std::string text;
  if (const auto info = query_liggghts())
    text += liggghts_info_text("LIGGGHTS", *info);
  else
    text +=
        "LIGGGHTS: not found (no `liggghts` on PATH and DEMSA_LIGGGHTS not set); install it with "
        "scripts/install-deps.sh\n";
  if (const auto cached = cached_liggghts_executable())
    text += liggghts_info_text("LIGGGHTS of scripts/build-liggghts.sh", query_liggghts_at(*cached));
  else
    text += fmt::format(
        "LIGGGHTS of scripts/build-liggghts.sh: none in {} (needed by the viscous rolling model, and the faster "
        "default for every other)\n",
        liggghts_cache_dir().string());
  // resolve_liggghts is the rule; docs/explanation/benchmarks.md ("LIGGGHTS builds") measured the two builds.
  text += fmt::format(
      "which a study runs: the one its [run] liggghts names; else, but for `cdt`, $DEMSA_LIGGGHTS; else the build of "
      "scripts/build-liggghts.sh when it is built ({}); else `liggghts` on PATH. The build is the default because it "
      "runs Debian's trajectories to the last digit, the quickstart's piles about 1.3 times as fast (RECIPE 6: 1.305, "
      "the median of its 20 cases; "
      "docs/explanation/benchmarks.md, \"Profile-guided and link-time optimisation\").\n",
      cached_liggghts_executable() ? "here it is" : "here it is not");
  return text;
}

}  // namespace demsa::exec
