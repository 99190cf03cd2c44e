#include "postprocess/oedometer.hpp"

#include "postprocess/measures.hpp"
#include "postprocess/text.hpp"

#include <fmt/core.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace demsa::postprocess {

namespace {

/// Plate files are small (one short row per output step, a few MB for millions of steps): a longer line or a larger
/// file is not a plate file. 64 MiB of rows of 4 values hold at most 8 M rows (≈ 0.6 GB parsed).
constexpr LineLimits k_plate_limits{std::size_t{1} << 16, std::uint64_t{64} << 20};

/// A whitespace table with `#` comments. `header_key` is the first column name that marks the column header
/// comment (`# step ...`); the last such comment before the first row names the columns.
struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::vector<long> lines;  // file line of each row
};

Table read_table(LineReader& in, const std::string& header_key, const std::vector<std::string>& default_columns) {
  const std::string& path = in.name();
  std::string_view view;
  std::string raw;
  Table table;
  bool have_header = false;
  while (in.next(view)) {
    const long line_no = in.line();
    raw.assign(view);
    const std::size_t first = raw.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    if (raw[first] == '#') {
      if (!table.rows.empty()) continue;
      std::vector<std::string> words = split_words(raw.substr(first + 1));
      if (!words.empty() && words.front() == header_key) {
        table.columns = std::move(words);
        have_header = true;
      }
      continue;
    }
    if (!have_header) {
      if (default_columns.empty())
        throw ParseError(
            path, line_no,
            fmt::format("data row before the column header (a comment line starting with '# {}')", header_key));
      table.columns = default_columns;
      have_header = true;
    }
    const std::vector<std::string> words = split_words(raw);
    if (words.size() != table.columns.size())
      throw ParseError(
          path, line_no,
          fmt::format("row has {} values, the header names {} columns", words.size(), table.columns.size()));
    std::vector<double> row(words.size());
    for (std::size_t c = 0; c < words.size(); ++c)
      if (!parse_double(words[c], row[c], true))
        throw ParseError(path, line_no, fmt::format("column '{}': '{}' is not a number", table.columns[c], words[c]));
    table.rows.push_back(std::move(row));
    table.lines.push_back(line_no);
  }
  return table;
}

int find_column(const Table& table, const std::string& name) {
  for (std::size_t c = 0; c < table.columns.size(); ++c)
    if (table.columns[c] == name) return static_cast<int>(c);
  return -1;
}

int require_column(const Table& table, const std::string& path, const std::string& name) {
  const int c = find_column(table, name);
  if (c < 0) {
    std::string names;
    for (const std::string& n : table.columns) names += " " + n;
    throw ParseError(path, 0, fmt::format("no column '{}' (columns:{})", name, names));
  }
  return c;
}

long whole(const std::string& path, long line, const std::string& column, double value) {
  if (value != std::floor(value) || std::fabs(value) > 9.0e15)
    throw ParseError(path, line, fmt::format("column '{}': {} is not an integer", column, value));
  return static_cast<long>(value);
}

/// Bounds of a plausible plate row: the loads of an oedometer only grow (paper §4: 100 N, then larger steps), and
/// no DEM box holding a plate is a kilometre across. A value outside is a corrupt or foreign file, and would give
/// settlements that are wrong without a sign in the numbers.
constexpr double k_max_position_m = 1.0e3;

void check_row(const std::string& path, const Table& table, std::size_t i, int c_load, int c_z, const char* what) {
  const std::vector<double>& row = table.rows[i];
  const long line = table.lines[i];
  const double load = row[static_cast<std::size_t>(c_load)];
  const double z = row[static_cast<std::size_t>(c_z)];
  if (load < 0.0) throw ParseError(path, line, fmt::format("column 'load_N': {} is negative", load));
  if (std::fabs(z) > k_max_position_m)
    throw ParseError(path, line,
                     fmt::format("column 'plate_z_m': {} m is not a plate position (|z| > {} m)", z, k_max_position_m));
  if (i > 0) {
    const double previous = table.rows[i - 1][static_cast<std::size_t>(c_load)];
    if (load < previous)
      throw ParseError(path, line,
                       fmt::format("column 'load_N': {} is below the {} of line {}: the loads of {} must not decrease",
                                   load, previous, table.lines[i - 1], what));
  }
}

PlateHistory plate_history_from(LineReader& in) {
  const std::string& path = in.name();
  const Table table = read_table(in, "step", {});
  PlateHistory h;
  h.file = path;
  h.columns = table.columns;
  if (table.columns.empty()) {
    if (table.rows.empty()) return h;
  }
  const int c_step = require_column(table, path, "step");
  const int c_load = require_column(table, path, "load_N");
  const int c_z = require_column(table, path, "plate_z_m");
  const int c_force = require_column(table, path, "force_N");
  const int c_trial = find_column(table, "trial");
  const int c_delta = find_column(table, "delta_m");
  const int c_acc = find_column(table, "accepted");
  for (std::size_t i = 0; i < table.rows.size(); ++i) {
    check_row(path, table, i, c_load, c_z, "a plate history");
    const std::vector<double>& row = table.rows[i];
    const long line = table.lines[i];
    h.step.push_back(whole(path, line, "step", row[static_cast<std::size_t>(c_step)]));
    h.load_N.push_back(row[static_cast<std::size_t>(c_load)]);
    h.plate_z_m.push_back(row[static_cast<std::size_t>(c_z)]);
    h.force_N.push_back(row[static_cast<std::size_t>(c_force)]);
    if (c_trial >= 0) h.trial.push_back(whole(path, line, "trial", row[static_cast<std::size_t>(c_trial)]));
    if (c_delta >= 0) {
      const double delta = row[static_cast<std::size_t>(c_delta)];
      if (std::fabs(delta) > k_max_position_m)
        throw ParseError(
            path, line,
            fmt::format("column 'delta_m': {} m is not a trial step (|delta| > {} m)", delta, k_max_position_m));
      h.delta_m.push_back(delta);
    }
    if (c_acc >= 0) {
      const double a = row[static_cast<std::size_t>(c_acc)];
      if (a != 0.0 && a != 1.0) throw ParseError(path, line, fmt::format("column 'accepted': {} is not 0 or 1", a));
      h.accepted.push_back(static_cast<int>(a));
    }
  }
  return h;
}

std::vector<PlateState> plate_states_from(LineReader& in) {
  const std::string& path = in.name();
  const Table table = read_table(in, "load_N", {"load_N", "plate_z_m", "force_N", "converged"});
  std::vector<PlateState> states;
  if (table.rows.empty()) return states;
  const int c_load = require_column(table, path, "load_N");
  const int c_z = require_column(table, path, "plate_z_m");
  const int c_force = require_column(table, path, "force_N");
  const int c_conv = require_column(table, path, "converged");
  for (std::size_t i = 0; i < table.rows.size(); ++i) {
    check_row(path, table, i, c_load, c_z, "the load states");
    const std::vector<double>& row = table.rows[i];
    PlateState s;
    s.load_N = row[static_cast<std::size_t>(c_load)];
    s.plate_z_m = row[static_cast<std::size_t>(c_z)];
    s.force_N = row[static_cast<std::size_t>(c_force)];
    const double conv = row[static_cast<std::size_t>(c_conv)];
    if (conv != 0.0 && conv != 1.0)
      throw ParseError(path, table.lines[i], fmt::format("column 'converged': {} is not 0 or 1", conv));
    s.converged = conv == 1.0;
    states.push_back(s);
  }
  return states;
}

std::optional<SettledPacking> settled_packing_from(LineReader& in) {
  static constexpr std::string_view k_prefix = "# settled packing:";
  std::string_view view;
  while (in.next(view)) {
    if (view.substr(0, k_prefix.size()) != k_prefix) continue;
    // "particles N, top_z_m Z, void_ratio E, plate_start_z_m Z0": name-value pairs separated by commas.
    std::string rest(view.substr(k_prefix.size()));
    for (char& c : rest)
      if (c == ',') c = ' ';
    const std::vector<std::string> words = split_words(rest);
    const auto field = [&](const std::string& name) {
      for (std::size_t i = 0; i + 1 < words.size(); i += 2)
        if (words[i] == name) {
          double v = 0.0;
          if (!parse_double(words[i + 1], v, true))
            throw ParseError(in.name(), in.line(),
                             fmt::format("settled packing: {} = {} is not a finite number", name, shown(words[i + 1])));
          return v;
        }
      throw ParseError(in.name(), in.line(), fmt::format("settled packing: no {} in {}", name, shown(view)));
    };
    SettledPacking p;
    const double particles = field("particles");
    p.top_z_m = field("top_z_m");
    p.void_ratio = field("void_ratio");
    p.plate_start_z_m = field("plate_start_z_m");
    if (!(particles >= 1.0 && particles <= 1e12) || particles != std::floor(particles))
      throw ParseError(in.name(), in.line(), fmt::format("settled packing: particles = {} is not a count", particles));
    p.particles = static_cast<long>(particles);
    if (p.void_ratio < 0.0)
      throw ParseError(in.name(), in.line(), fmt::format("settled packing: void_ratio = {} is negative", p.void_ratio));
    if (p.plate_start_z_m < p.top_z_m)
      throw ParseError(
          in.name(), in.line(),
          fmt::format("settled packing: plate_start_z_m = {} lies below top_z_m = {}", p.plate_start_z_m, p.top_z_m));
    return p;
  }
  return std::nullopt;
}

}  // namespace

PlateHistory read_plate_history(const std::filesystem::path& path) {
  LineReader in(path, k_plate_limits);
  return plate_history_from(in);
}

PlateHistory parse_plate_history(std::string_view text, const std::string& name) {
  LineReader in = LineReader::of_text(text, name, k_plate_limits);
  return plate_history_from(in);
}

std::vector<PlateState> read_plate_states(const std::filesystem::path& path) {
  LineReader in(path, k_plate_limits);
  return plate_states_from(in);
}

std::vector<PlateState> parse_plate_states(std::string_view text, const std::string& name) {
  LineReader in = LineReader::of_text(text, name, k_plate_limits);
  return plate_states_from(in);
}

std::optional<SettledPacking> read_settled_packing(const std::filesystem::path& path) {
  LineReader in(path, k_plate_limits);
  return settled_packing_from(in);
}

std::optional<SettledPacking> parse_settled_packing(std::string_view text, const std::string& name) {
  LineReader in = LineReader::of_text(text, name, k_plate_limits);
  return settled_packing_from(in);
}

std::vector<PlateState> states_from_history(const PlateHistory& history, double load_tolerance) {
  std::vector<PlateState> states;
  const bool trial_mode = !history.accepted.empty();
  std::size_t i = 0;
  while (i < history.size()) {
    std::size_t j = i;
    while (j < history.size() && history.load_N[j] == history.load_N[i]) ++j;
    // rows [i, j) share one load: the last (accepted) row is the state reached
    std::size_t pick = j;
    for (std::size_t k = j; k-- > i;)
      if (!trial_mode || history.accepted[k] == 1) {
        pick = k;
        break;
      }
    if (pick < j) {
      PlateState s;
      s.load_N = history.load_N[pick];
      s.plate_z_m = history.plate_z_m[pick];
      s.force_N = history.force_N[pick];
      s.converged = std::fabs(s.force_N - s.load_N) <= load_tolerance;
      states.push_back(s);
    }
    i = j;
  }
  return states;
}

void OedometerOptions::validate() const {
  if (!(box_side > 0.0) || !std::isfinite(box_side))
    throw std::invalid_argument(fmt::format("OedometerOptions.box_side = {}: must be a positive length [m]", box_side));
  if (!std::isfinite(floor_z))
    throw std::invalid_argument(fmt::format("OedometerOptions.floor_z = {}: must be finite [m]", floor_z));
  if (!(solid_volume >= 0.0) || !std::isfinite(solid_volume))
    throw std::invalid_argument(
        fmt::format("OedometerOptions.solid_volume = {}: must be >= 0 [m^3] (0 = no void ratio)", solid_volume));
  for (std::size_t i = 0; i < measured_settlements.size(); ++i)
    if (!std::isfinite(measured_settlements[i]))
      throw std::invalid_argument(fmt::format("OedometerOptions.measured_settlements[{}] = {}: must be finite [m]", i,
                                              measured_settlements[i]));
}

OedometerResult measure_oedometer(const std::vector<PlateState>& states, const OedometerOptions& options,
                                  std::optional<PlateHistory> history) {
  options.validate();
  if (states.empty()) throw InputError("no load state reached: the plate files hold no load step");
  OedometerResult result;
  result.options = options;
  const double area = options.box_side * options.box_side;
  // Paper §4: the settlement s = h_0 − h, h_0 being the plate height at the first load step (100 N).
  const double h0 = states.front().plate_z_m;
  result.all_converged = true;
  for (const PlateState& s : states) {
    OedometerStep step;
    step.load_N = s.load_N;
    step.plate_z_m = s.plate_z_m;
    step.force_N = s.force_N;
    step.converged = s.converged;
    step.settlement_m = h0 - s.plate_z_m;
    step.stress_Pa = s.load_N / area;
    if (options.solid_volume > 0.0) {
      // Void ratio e = V_voids / V_S (paper §4 writes V_S/V_P, but its values 0.66/0.67 are voids over solids).
      const double total = area * (s.plate_z_m - options.floor_z);
      step.void_ratio = (total - options.solid_volume) / options.solid_volume;
    }
    result.all_converged = result.all_converged && s.converged;
    result.steps.push_back(step);
  }
  for (std::size_t i = 1; i < result.steps.size(); ++i) result.settlements.push_back(result.steps[i].settlement_m);

  const std::size_t n = states.size();
  const std::vector<double>& measured = options.measured_settlements;
  if (!measured.empty()) {
    // E_0 = sqrt(Σ (s̃_i − s_i)²) over the loads after the first (paper §4).
    if (measured.size() == n - 1 && n > 1) {
      result.settlement_error = settlement_error(result.settlements, measured);
    } else if (measured.size() == n) {
      std::vector<double> all{0.0};
      all.insert(all.end(), result.settlements.begin(), result.settlements.end());
      result.settlement_error = settlement_error(all, measured);
    } else {
      throw InputError(fmt::format(
          "{} measured settlements for {} load states: give {} (one per load after the first) or {} (starting with "
          "the first load's 0)",
          measured.size(), n, n - 1, n));
    }
  }
  if (history) {
    for (int a : history->accepted) (a == 1 ? result.trials_accepted : result.trials_rejected) += 1;
    result.history = std::move(history);
  }
  return result;
}

double solid_volume(const Particles& particles) {
  double v = 0.0;
  for (double r : particles.radius) v += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  return v;
}

}  // namespace demsa::postprocess
