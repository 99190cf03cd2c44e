#include "orchestrator/exec/failure.hpp"

#include "orchestrator/cases/case_writer.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <deque>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace demsa::exec {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::cases;

namespace {

namespace fs = std::filesystem;

std::vector<std::string> split_words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  std::string word;
  while (in >> word) words.push_back(word);
  return words;
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string trim_left(const std::string& line) {
  const auto first = line.find_first_not_of(" \t");
  return first == std::string::npos ? std::string{} : line.substr(first);
}

/// First `ERROR` line (LAMMPS/LIGGGHTS print "ERROR: ..." or "ERROR on proc N: ...") in a file, or "".
std::string first_error_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    const std::string text = trim_left(line);
    if (text.rfind("ERROR:", 0) == 0 || text.rfind("ERROR on proc", 0) == 0) return text;
  }
  return {};
}

/// A thermo column that holds kinetic energy: LAMMPS's `ke` keyword ("KinEng") or a compute/variable/fix whose
/// name is ke/kinetic energy ("c_ke", "v_ke", "v_kinetic", "c_KE").
bool is_kinetic_energy_column(const std::string& name) {
  const std::string n = lower(name);
  if (n == "kineng" || n == "ke") return true;
  if (n.size() > 2 && (n.rfind("c_", 0) == 0 || n.rfind("v_", 0) == 0 || n.rfind("f_", 0) == 0)) {
    const std::string base = n.substr(2);
    return base == "ke" || base == "vke" || base == "kineng" || base.rfind("kinetic", 0) == 0;
  }
  return false;
}

bool parse_number(const std::string& word, double& value) {
  try {
    std::size_t used = 0;
    value = std::stod(word, &used);
    return used == word.size();
  } catch (const std::exception&) {
    // stod throws out_of_range for 1e999 and invalid_argument for words; "nan"/"inf" parse fine.
    const std::string w = lower(word);
    if (w == "nan" || w == "-nan" || w == "inf" || w == "-inf") {
      value = std::nan("");
      return true;
    }
    return false;
  }
}

/// Scans the thermo blocks of a LIGGGHTS log (a header line starting with "Step", then rows of numbers) for NaN
/// or infinite values and for kinetic energy above `limit` (limit 0: not checked). Returns a message or "".
std::string thermo_blowup(const fs::path& log, double limit) {
  std::ifstream in(log);
  std::string line;
  std::vector<std::string> header;
  int ke_column = -1;
  while (std::getline(in, line)) {
    const std::vector<std::string> words = split_words(line);
    if (words.empty()) {
      header.clear();
      continue;
    }
    if (words.front() == "Step") {
      header = words;
      ke_column = -1;
      for (std::size_t i = 0; i < words.size(); ++i)
        if (is_kinetic_energy_column(words[i])) ke_column = static_cast<int>(i);
      continue;
    }
    if (header.empty() || words.size() != header.size()) {
      header.clear();
      continue;
    }
    std::vector<double> values(words.size());
    bool numeric = true;
    for (std::size_t i = 0; i < words.size() && numeric; ++i) numeric = parse_number(words[i], values[i]);
    if (!numeric) {
      header.clear();
      continue;
    }
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i]))
        return fmt::format("thermo column '{}' is {} at step {}", header[i], words[i], words.front());
    if (ke_column >= 0 && limit > 0 && values[static_cast<std::size_t>(ke_column)] > limit)
      return fmt::format("kinetic energy {} J above the limit {} J at step {}", words[ke_column], limit, words.front());
  }
  return {};
}

struct DumpCheck {
  bool ok = false;
  long atoms = 0;
  std::string problem;
};

/// Checks the last snapshot of a LIGGGHTS text dump: header complete, as many atom rows as announced, each with
/// as many columns as the ATOMS line names.
DumpCheck check_dump(const fs::path& file) {
  DumpCheck check;
  std::ifstream in(file);
  if (!in) {
    check.problem = fmt::format("{} is missing", file.filename().string());
    return check;
  }
  std::string line;
  long announced = -1;
  long rows = 0;
  std::size_t columns = 0;
  bool in_atoms = false;
  bool bad_row = false;
  bool any_snapshot = false;
  while (std::getline(in, line)) {
    if (line.rfind("ITEM:", 0) == 0) {
      in_atoms = false;
      if (line.rfind("ITEM: TIMESTEP", 0) == 0) {
        announced = -1;
        rows = 0;
        bad_row = false;
      } else if (line.rfind("ITEM: NUMBER OF ATOMS", 0) == 0) {
        if (std::getline(in, line)) {
          double n = 0;
          if (parse_number(trim_left(line).substr(0, line.find_last_not_of(" \t\r") + 1), n) && n >= 0)
            announced = static_cast<long>(n);
        }
      } else if (line.rfind("ITEM: ATOMS", 0) == 0) {
        columns = split_words(line).size() - 2;
        in_atoms = true;
        any_snapshot = true;
      }
      continue;
    }
    if (in_atoms) {
      const std::size_t n = split_words(line).size();
      if (n == 0) continue;
      if (n != columns) bad_row = true;
      ++rows;
    }
  }
  if (!any_snapshot || announced < 0) {
    check.problem = fmt::format("{} has no complete snapshot", file.filename().string());
    return check;
  }
  if (rows != announced || bad_row) {
    check.problem = fmt::format("{} is truncated: {} of {} atom rows{}", file.filename().string(), rows, announced,
                                bad_row ? ", some incomplete" : "");
    return check;
  }
  check.ok = true;
  check.atoms = rows;
  return check;
}

/// Oedometer: every row of plate_states.txt has converged = 1 and there is a row per load. Returns a message or "".
std::string plate_problem(const fs::path& file, std::size_t loads, bool& missing) {
  std::ifstream in(file);
  missing = !in;
  if (missing) return fmt::format("{} is missing", file.filename().string());
  std::string line;
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    const std::vector<std::string> words = split_words(line);
    if (words.empty() || words.front().front() == '#') continue;
    ++rows;
    if (words.size() < 4) {
      missing = true;
      return fmt::format("{}: row {} has {} columns, expected 4", file.filename().string(), rows, words.size());
    }
    if (words[3] != "1")
      return fmt::format("load {} N not reached (plate force {} N)", words[0], words.size() > 2 ? words[2] : "?");
  }
  if (rows < loads) return fmt::format("only {} of {} load steps reached", rows, loads);
  return {};
}

std::string combined_tail(const fs::path& folder, int lines) {
  std::string tail = file_tail(folder / "log.liggghts", lines);
  const std::string out = file_tail(folder / k_run_output_file, std::max(5, lines / 3));
  if (tail.empty()) tail = file_tail(folder / "screen.txt", lines);
  if (!out.empty()) {
    if (!tail.empty()) tail += "--- run.out ---\n";
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
  if (load_steps < 0) throw std::invalid_argument(fmt::format("load_steps = {}: must be >= 0", load_steps));
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
    const std::string error = first_error_line(folder / name);
    if (!error.empty()) return fail(FailureClass::liggghts_error, error);
  }
  const std::string blowup = thermo_blowup(folder / "log.liggghts", options.kinetic_energy_limit);
  if (!blowup.empty()) return fail(FailureClass::energy_blowup, blowup);
  // A shell reports a child killed by signal N as exit status 128 + N (mpirun and liggghts run under run.sh).
  if (exit.exit_code > 128 && exit.exit_code <= 128 + 64)
    return fail(FailureClass::signal,
                fmt::format("exit status {} (128 + signal {})", exit.exit_code, exit.exit_code - 128));
  if (exit.exit_code != 0) return fail(FailureClass::nonzero_exit, fmt::format("exit status {}", exit.exit_code));

  const DumpCheck dump =
      check_dump(folder / (options.experiment == Experiment::pile ? k_pile_final_dump : k_oedometer_final_dump));
  if (!dump.ok) return fail(FailureClass::missing_dump, dump.problem);
  if (options.expected_particles > 0) {
    const long lost = std::max(0L, options.expected_particles - dump.atoms);
    const double fraction = static_cast<double>(lost) / static_cast<double>(options.expected_particles);
    if (fraction > options.lost_fraction)
      return fail(FailureClass::lost_particles,
                  fmt::format("{} of {} particles lost ({:.3g} %, limit {:.3g} %)", lost, options.expected_particles,
                              100 * fraction, 100 * options.lost_fraction));
  }
  if (options.experiment == Experiment::oedometer) {
    bool missing = false;
    const std::string problem =
        plate_problem(folder / k_plate_states, static_cast<std::size_t>(options.load_steps), missing);
    if (!problem.empty())
      return fail(missing ? FailureClass::missing_dump : FailureClass::plate_not_converged, problem);
  }
  return report;
}

}  // namespace demsa::exec
