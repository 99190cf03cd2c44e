#include "postprocess/liggghts_log.hpp"

#include "postprocess/text.hpp"

#include <fmt/core.h>

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>

namespace demsa::postprocess {

namespace {

bool starts_with(const std::string& s, std::string_view prefix) { return s.compare(0, prefix.size(), prefix) == 0; }

}  // namespace

int ThermoBlock::column_index(const std::string& name) const {
  for (std::size_t c = 0; c < columns.size(); ++c)
    if (columns[c] == name) return static_cast<int>(c);
  return -1;
}

LiggghtsLog parse_liggghts_log(const std::string& text) {
  LiggghtsLog log;
  std::istringstream in(text);
  std::string raw;
  long line_no = 0;
  ThermoBlock* block = nullptr;  // the block collecting rows, if any
  bool have_atoms = false;
  double last_atoms = 0.0;
  long lost_reported = -1;

  while (std::getline(in, raw)) {
    ++line_no;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    // Thermo rows: numeric lines with as many values as the header names.
    if (block != nullptr) {
      const std::vector<std::string> words = split_words(raw);
      bool numeric = words.size() == block->columns.size();
      std::vector<double> row(words.size());
      for (std::size_t c = 0; numeric && c < words.size(); ++c) numeric = parse_double(words[c], row[c]);
      if (numeric) {
        const int atoms = block->column_index("Atoms");
        if (atoms >= 0) {
          const double now = row[static_cast<std::size_t>(atoms)];
          if (have_atoms && now < last_atoms) log.lost_atoms += static_cast<long>(last_atoms - now);
          last_atoms = now;
          have_atoms = true;
        }
        block->rows.push_back(std::move(row));
        continue;
      }
      block = nullptr;  // the block ends at the first line that is not a row (Loop time, a warning, a cut row)
    }

    // LIGGGHTS indents the thermo header ("    Step    Atoms  KinEng ...").
    const std::size_t indent = raw.find_first_not_of(" \t");
    const std::string trimmed = indent == std::string::npos ? std::string() : raw.substr(indent);
    if (starts_with(raw, "LIGGGHTS (Version ") && log.version.empty()) {
      const std::size_t b = std::strlen("LIGGGHTS (Version ");
      const std::size_t e = raw.find_first_of(",)", b);
      log.version = raw.substr(b, e == std::string::npos ? std::string::npos : e - b);
    } else if (starts_with(trimmed, "Step ") || trimmed == "Step") {
      log.thermo.push_back(ThermoBlock{line_no, split_words(trimmed), {}});
      block = &log.thermo.back();
    } else if (starts_with(raw, "WARNING: ")) {
      log.warnings.push_back({line_no, raw.substr(std::strlen("WARNING: "))});
    } else if (starts_with(raw, "ERROR")) {
      const std::size_t colon = raw.find(": ");
      log.errors.push_back({line_no, colon == std::string::npos ? raw : raw.substr(colon + 2)});
    } else if (starts_with(raw, "Loop time of ")) {
      // "Loop time of 45.721 on 1 procs for 300000 steps with 496 atoms"
      LoopSummary loop;
      loop.line = line_no;
      const std::vector<std::string> w = split_words(raw);
      if (w.size() >= 12 && parse_double(w[3], loop.seconds)) {
        double procs = 0, steps = 0, atoms = 0;
        if (parse_double(w[5], procs)) loop.procs = static_cast<int>(procs);
        if (parse_double(w[8], steps)) loop.steps = static_cast<long>(steps);
        if (parse_double(w[11], atoms)) loop.atoms = static_cast<long>(atoms);
        log.loops.push_back(loop);
        log.loop_seconds += loop.seconds;
        log.steps += loop.steps;
      }
    } else if (starts_with(raw, "Total wall time: ")) {
      int h = 0, m = 0, s = 0;
      if (std::sscanf(raw.c_str() + std::strlen("Total wall time: "), "%d:%d:%d", &h, &m, &s) == 3)
        log.total_wall_seconds = 3600.0 * h + 60.0 * m + s;
    }
    // "Lost atoms: original N current M" (in an ERROR or WARNING line, or on its own).
    const std::size_t lost = raw.find("Lost atoms: original ");
    if (lost != std::string::npos) {
      long original = 0, current = 0;
      if (std::sscanf(raw.c_str() + lost, "Lost atoms: original %ld current %ld", &original, &current) == 2)
        lost_reported = original - current;
    }
  }
  if (lost_reported >= 0) log.lost_atoms = lost_reported;
  return log;
}

LiggghtsLog read_liggghts_log(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ParseError(path.string(), 0, fmt::format("cannot open: {}", std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_liggghts_log(text.str());
}

}  // namespace demsa::postprocess
