#include "postprocess/liggghts_log.hpp"

#include "postprocess/text.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <string_view>

namespace demsa::postprocess {

namespace {

bool starts_with(const std::string& s, std::string_view prefix) { return s.compare(0, prefix.size(), prefix) == 0; }

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string trim_left(const std::string& line) {
  const std::size_t first = line.find_first_not_of(" \t");
  return first == std::string::npos ? std::string() : line.substr(first);
}

/// LAMMPS and LIGGGHTS print "ERROR: ..." from one process and "ERROR on proc N: ..." from another (error.cpp).
bool is_error_line(const std::string& trimmed) {
  return starts_with(trimmed, "ERROR:") || starts_with(trimmed, "ERROR on proc");
}

/// The thermo part of the log: a header line (`Step` and the column names; LIGGGHTS indents it) opens a block, lines
/// of as many numbers as the header names columns are its rows, the first other line closes it. Shared by the
/// whole-log reader and the row scanner so that both read the same rows.
class ThermoParser {
 public:
  enum class Kind { header, row, other };

  /// Classifies the next line (without its '\n' and '\r').
  Kind feed(const std::string& raw, long line_no) {
    if (m_open) {
      m_words = split_words(raw);
      bool numeric = m_words.size() == m_block.columns.size();
      m_values.resize(m_words.size());
      for (std::size_t c = 0; numeric && c < m_words.size(); ++c) numeric = parse_double(m_words[c], m_values[c]);
      if (numeric) return Kind::row;
      m_open = false;  // a Loop time line, a warning, a cut row of a killed run
    }
    const std::string trimmed = trim_left(raw);
    if (starts_with(trimmed, "Step ") || trimmed == "Step") {
      m_block = ThermoBlock{line_no, split_words(trimmed), {}};
      m_open = true;
      return Kind::header;
    }
    return Kind::other;
  }

  const ThermoBlock& block() const { return m_block; }
  const std::vector<std::string>& words() const { return m_words; }
  const std::vector<double>& values() const { return m_values; }

 private:
  ThermoBlock m_block;
  bool m_open = false;
  std::vector<std::string> m_words;
  std::vector<double> m_values;
};

/// Lines of a log: a LIGGGHTS log never has a line near 1 MiB; a longer one is binary data, not a log.
constexpr std::size_t k_max_line_bytes = std::size_t{1} << 20;
/// read_liggghts_log keeps every thermo row (about as many bytes as the text): larger logs are streamed by
/// scan_thermo instead.
constexpr std::uint64_t k_max_log_bytes = std::uint64_t{1} << 30;

/// Calls `line(text, line_no)` for every line of `in`, without its '\n' and a '\r' before it.
template <class F>
void for_each_line(LineReader& in, F&& line) {
  std::string_view view;
  std::string raw;
  while (in.next(view)) {
    raw.assign(view);
    if (!line(raw, in.line())) return;
  }
}

LiggghtsLog parse_log(LineReader& in) {
  LiggghtsLog log;
  ThermoParser thermo;
  bool have_atoms = false;
  double last_atoms = 0.0;
  long lost_reported = -1;
  for_each_line(in, [&](const std::string& raw, long line_no) {
    const ThermoParser::Kind kind = thermo.feed(raw, line_no);
    if (kind == ThermoParser::Kind::row) {
      ThermoBlock& block = log.thermo.back();
      const int atoms = block.column_index("Atoms");
      if (atoms >= 0) {
        const double now = thermo.values()[static_cast<std::size_t>(atoms)];
        if (have_atoms && now < last_atoms) log.lost_atoms += static_cast<long>(last_atoms - now);
        last_atoms = now;
        have_atoms = true;
      }
      block.rows.push_back(thermo.values());
      return true;
    }
    const std::string trimmed = trim_left(raw);
    if (kind == ThermoParser::Kind::header) {
      log.thermo.push_back(thermo.block());
    } else if (starts_with(raw, "LIGGGHTS (Version ") && log.version.empty()) {
      const std::size_t b = std::strlen("LIGGGHTS (Version ");
      const std::size_t e = raw.find_first_of(",)", b);
      log.version = raw.substr(b, e == std::string::npos ? std::string::npos : e - b);
    } else if (starts_with(raw, "WARNING: ")) {
      log.warnings.push_back({line_no, raw.substr(std::strlen("WARNING: "))});
    } else if (is_error_line(trimmed)) {
      const std::size_t colon = trimmed.find(": ");
      log.errors.push_back({line_no, colon == std::string::npos ? trimmed : trimmed.substr(colon + 2)});
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
    return true;
  });
  if (lost_reported >= 0) log.lost_atoms = lost_reported;
  return log;
}

}  // namespace

int ThermoBlock::column_index(const std::string& name) const {
  for (std::size_t c = 0; c < columns.size(); ++c)
    if (columns[c] == name) return static_cast<int>(c);
  return -1;
}

int ThermoBlock::kinetic_energy_column() const {
  int found = -1;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const std::string n = lower(columns[c]);
    bool ke = n == "kineng" || n == "ke";
    if (!ke && n.size() > 2 && (starts_with(n, "c_") || starts_with(n, "v_") || starts_with(n, "f_"))) {
      const std::string base = n.substr(2);
      ke = base == "ke" || base == "vke" || base == "kineng" || starts_with(base, "kinetic");
    }
    if (ke) found = static_cast<int>(c);
  }
  return found;
}

LiggghtsLog parse_liggghts_log(const std::string& text) {
  LineReader in = LineReader::of_text(text, "log text", {k_max_line_bytes, k_max_log_bytes});
  return parse_log(in);
}

LiggghtsLog read_liggghts_log(const std::filesystem::path& path) {
  LineReader in(path, {k_max_line_bytes, k_max_log_bytes});
  return parse_log(in);
}

void scan_thermo(const std::filesystem::path& path, const std::function<bool(const ThermoRow&)>& visit) {
  LineReader in(path, {k_max_line_bytes, 0});
  ThermoParser thermo;
  for_each_line(in, [&](const std::string& raw, long line_no) {
    if (thermo.feed(raw, line_no) != ThermoParser::Kind::row) return true;
    return visit(ThermoRow{thermo.block(), line_no, thermo.words(), thermo.values()});
  });
}

std::string first_error_line(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec) || !std::filesystem::exists(path, ec)) return {};
  std::string found;
  try {
    LineReader in(path, {k_max_line_bytes, 0});
    for_each_line(in, [&](const std::string& raw, long) {
      const std::string trimmed = trim_left(raw);
      if (is_error_line(trimmed)) found = trimmed;
      return found.empty();
    });
  } catch (const ParseError&) {
    // Unreadable, or binary data after the lines read (a node that died mid-write): no ERROR line before it.
  }
  return found;
}

}  // namespace demsa::postprocess
