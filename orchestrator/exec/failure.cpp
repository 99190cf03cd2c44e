#include "orchestrator/exec/failure.hpp"

#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "postprocess/dump.hpp"
#include "postprocess/liggghts_log.hpp"
#include "postprocess/oedometer.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <fstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace demsa::exec {

using namespace demsa::study;

namespace {

namespace fs = std::filesystem;

/// A reader's complaint about `file`, named by its file name alone (the case folder is in the report already).
std::string problem(const fs::path& file, const postprocess::ParseError& e) {
  const std::string name = file.filename().string();
  return e.line() > 0 ? fmt::format("{}:{}: {}", name, e.line(), e.message())
                      : fmt::format("{}: {}", name, e.message());
}

/// NaN or infinite values anywhere in the thermo rows of the log, or kinetic energy above `limit` (0: not checked).
/// Returns a message or "". A log that cannot be read says nothing: the dump checks still apply.
std::string thermo_blowup(const fs::path& log, double limit) {
  std::string message;
  std::error_code ec;
  if (!fs::exists(log, ec)) return message;
  long header_line = -1;
  int ke = -1;
  try {
    postprocess::scan_thermo(log, [&](const postprocess::ThermoRow& row) {
      if (row.block.header_line != header_line) {  // once per block, not per row
        header_line = row.block.header_line;
        ke = row.block.kinetic_energy_column();
      }
      for (std::size_t i = 0; i < row.values.size(); ++i)
        if (!std::isfinite(row.values[i])) {
          message =
              fmt::format("thermo column '{}' is {} at step {}", row.block.columns[i], row.words[i], row.words.front());
          return false;
        }
      if (ke >= 0 && limit > 0 && row.values[static_cast<std::size_t>(ke)] > limit) {
        message = fmt::format("kinetic energy {} J above the limit {} J at step {}",
                              row.words[static_cast<std::size_t>(ke)], limit, row.words.front());
        return false;
      }
      return true;
    });
  } catch (const postprocess::ParseError&) {
    return {};
  }
  return message;
}

struct DumpCheck {
  bool ok = false;
  long atoms = 0;
  std::string problem;
};

/// Reads the final dump as the measurement does (postprocess::read_particles), and also refuses a last line without
/// end of line: a dump the measurement would refuse, or that was cut, is not a finished case.
DumpCheck check_dump(const fs::path& file) {
  DumpCheck check;
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    check.problem = fmt::format("{} is missing", file.filename().string());
    return check;
  }
  postprocess::DumpReaderOptions options;
  options.require_final_newline = true;
  try {
    check.atoms = static_cast<long>(postprocess::read_particles(file, 0, options).size());
  } catch (const postprocess::ShortFrameError& e) {
    check.problem =
        fmt::format("{} is truncated: {} of {} atom rows", file.filename().string(), e.rows(), e.announced());
    return check;
  } catch (const postprocess::ParseError& e) {
    check.problem = problem(file, e);
    return check;
  }
  check.ok = true;
  return check;
}

std::string combined_tail(const fs::path& folder, int lines) {
  std::string tail = file_tail(folder / k_case_log, lines);
  const std::string out = file_tail(folder / k_run_output_file, std::max(5, lines / 3));
  if (tail.empty()) tail = file_tail(folder / k_case_screen, lines);
  if (!out.empty()) {
    if (!tail.empty()) tail += fmt::format("--- {} ---\n", k_run_output_file);
    tail += out;
  }
  return tail;
}

}  // namespace

void FailureOptions::validate() const {
  if (expected_particles < 0)
    throw std::invalid_argument(fmt::format("expected_particles = {}: must be >= 0", expected_particles));
  if (!(lost_fraction >= 0 && lost_fraction <= 1))
    throw std::invalid_argument(fmt::format("lost_fraction = {}: must be in [0, 1]", lost_fraction));
  if (!(kinetic_energy_limit >= 0))
    throw std::invalid_argument(fmt::format("kinetic_energy_limit = {}: must be >= 0", kinetic_energy_limit));
  if (config == nullptr) throw std::invalid_argument("config: the case's study is needed");
  if (tail_lines < 1) throw std::invalid_argument(fmt::format("tail_lines = {}: must be >= 1", tail_lines));
}

std::string file_tail(const fs::path& file, int lines) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return {};
  // Read at most the last 64 KiB: a log can be hundreds of MB.
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const std::streamoff start = std::max<std::streamoff>(0, size - 65536);
  in.seekg(start);
  std::string line;
  std::deque<std::string> kept;
  if (start > 0) std::getline(in, line);  // partial first line
  while (std::getline(in, line)) {
    kept.push_back(line);
    if (static_cast<int>(kept.size()) > lines) kept.pop_front();
  }
  std::string text;
  for (const std::string& l : kept) text += l + "\n";
  return text;
}

FailureReport classify_case(const CaseExit& exit, const fs::path& folder, const FailureOptions& options) {
  options.validate();
  FailureReport report;
  auto fail = [&](FailureClass cls, std::string message) {
    report.failure = cls;
    report.message = std::move(message);
    report.log_tail = combined_tail(folder, options.tail_lines);
    return report;
  };
  if (exit.timed_out) return fail(FailureClass::timeout, "time limit exceeded");
  if (exit.cancelled || exit.lost) {
    report.requeue = true;
    report.message = exit.cancelled ? "cancelled" : "lost after a restart";
    return report;
  }
  if (exit.signal > 0) return fail(FailureClass::signal, fmt::format("killed by signal {}", exit.signal));

  for (const char* name : {k_case_log, k_case_screen, k_run_output_file}) {
    const std::string error = postprocess::first_error_line(folder / name);
    if (!error.empty()) {
      // The input scripts stop a case whose settings cannot work by an unknown command named "demsa:_..." after a
      // printed "demsa: ..." line (experiments/pile/case.cpp, liggghts_templates/oedometer_fill.liggghts).
      report.final = error.find("Unknown command: demsa:_") != std::string::npos;
      return fail(FailureClass::liggghts_error, error);
    }
  }
  const std::string blowup = thermo_blowup(folder / k_case_log, options.kinetic_energy_limit);
  if (!blowup.empty()) return fail(FailureClass::energy_blowup, blowup);
  // A shell reports a child killed by signal N as exit status 128 + N (mpirun and liggghts run under run.sh).
  if (exit.exit_code > 128 && exit.exit_code <= 128 + 64)
    return fail(FailureClass::signal,
                fmt::format("exit status {} (128 + signal {})", exit.exit_code, exit.exit_code - 128));
  if (exit.exit_code != 0) return fail(FailureClass::nonzero_exit, fmt::format("exit status {}", exit.exit_code));

  const experiments::Experiment& experiment = experiments::of(*options.config);
  const DumpCheck dump = check_dump(folder / std::string(experiment.final_dump));
  if (!dump.ok) return fail(FailureClass::missing_dump, dump.problem);
  if (options.expected_particles > 0) {
    // Particles the experiment removed on purpose (a pile's particles off the pedestal) are not lost.
    long removed = 0;
    try {
      removed = experiment.removed_particles(folder);
    } catch (const postprocess::ParseError& e) {
      return fail(FailureClass::missing_dump, problem(e.file(), e));
    }
    const long lost = std::max(0L, options.expected_particles - dump.atoms - removed);
    const double fraction = static_cast<double>(lost) / static_cast<double>(options.expected_particles);
    if (fraction > options.lost_fraction)
      return fail(FailureClass::lost_particles,
                  fmt::format("{} of {} particles lost ({:.3g} %, limit {:.3g} %){}", lost, options.expected_particles,
                              100 * fraction, 100 * options.lost_fraction,
                              removed > 0 ? fmt::format("; {} more removed on purpose", removed) : ""));
  }
  if (experiment.check_outputs)
    if (const std::optional<experiments::OutputProblem> p = experiment.check_outputs(folder, *options.config)) {
      report.final = p->final;
      return fail(p->failure, p->message);
    }
  return report;
}

}  // namespace demsa::exec
