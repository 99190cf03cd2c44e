#include "orchestrator/study/config.hpp"

#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"
#include "postprocess/text.hpp"
#include "sobol/design.hpp"
#include "sobol/error.hpp"
#include "sobol/metamodel.hpp"

#include <fmt/core.h>

#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <string_view>
#include <vector>

namespace demsa::study {

using namespace demsa::util;

namespace {

/// Reads one TOML table key by key: every key must be known (a row of settings.hpp), every value of the right
/// type. Messages are "study.toml:LINE: [section] key: ...".
class TableReader {
 public:
  TableReader(const SettingsTable& settings, const toml::table& table, std::string file, std::string section)
      : m_settings(settings), m_table(table), m_file(std::move(file)), m_section(std::move(section)) {}

  /// Calls `handle(key, node)` for every key; `handle` returns false for an unknown key.
  void each(const std::function<bool(const std::string&, const toml::node&)>& handle) const {
    for (const auto& [key, node] : m_table) {
      const std::string name(key.str());
      if (!handle(name, node)) {
        throw UserError(
            m_file, line_of(node),
            fmt::format("unknown key '{}' in [{}]{}", name, m_section, m_settings.unknown_key_hint(m_section, name)));
      }
    }
  }

  int line_of(const toml::node& node) const { return static_cast<int>(node.source().begin.line); }

  [[noreturn]] void fail(const toml::node& node, const std::string& key, const std::string& message) const {
    throw UserError(m_file, line_of(node), fmt::format("[{}] {}: {}", m_section, key, message));
  }

  double number(const std::string& key, const toml::node& node) const {
    if (const auto v = node.value<double>(); v && (node.is_floating_point() || node.is_integer())) {
      if (!std::isfinite(*v)) fail(node, key, fmt::format("must be a finite number, got {}", *v));
      return *v;
    }
    fail(node, key, fmt::format("expected a number, got {}", describe(node)));
  }
  long integer(const std::string& key, const toml::node& node) const {
    if (!node.is_integer()) fail(node, key, fmt::format("expected an integer, got {}", describe(node)));
    return static_cast<long>(*node.value<std::int64_t>());
  }
  std::string string(const std::string& key, const toml::node& node) const {
    if (!node.is_string()) fail(node, key, fmt::format("expected a string, got {}", describe(node)));
    return *node.value<std::string>();
  }
  bool boolean(const std::string& key, const toml::node& node) const {
    if (!node.is_boolean()) fail(node, key, fmt::format("expected true or false, got {}", describe(node)));
    return *node.value<bool>();
  }
  std::vector<double> numbers(const std::string& key, const toml::node& node) const {
    const toml::array* array = node.as_array();
    if (!array) fail(node, key, fmt::format("expected an array of numbers, got {}", describe(node)));
    std::vector<double> out;
    for (const toml::node& element : *array) out.push_back(number(key, element));
    return out;
  }
  std::vector<std::string> strings(const std::string& key, const toml::node& node) const {
    const toml::array* array = node.as_array();
    if (!array) fail(node, key, fmt::format("expected an array of strings, got {}", describe(node)));
    std::vector<std::string> out;
    for (const toml::node& element : *array) out.push_back(string(key, element));
    return out;
  }
  const toml::table& table(const std::string& key, const toml::node& node) const {
    const toml::table* t = node.as_table();
    if (!t) fail(node, key, fmt::format("expected a table, got {}", describe(node)));
    return *t;
  }

  const std::string& file() const { return m_file; }
  const std::string& section() const { return m_section; }
  const SettingsTable& settings() const { return m_settings; }

  static std::string describe(const toml::node& node) {
    switch (node.type()) {
      case toml::node_type::string:
        return "the string \"" + *node.value<std::string>() + "\"";
      case toml::node_type::table:
        return "a table";
      case toml::node_type::array:
        return "an array";
      case toml::node_type::integer:
        return "the integer " + std::to_string(*node.value<std::int64_t>());
      case toml::node_type::floating_point:
        return fmt::format("the number {}", *node.value<double>());
      case toml::node_type::boolean:
        return *node.value<bool>() ? "true" : "false";
      default:
        return "a date or time";
    }
  }

 private:
  const SettingsTable& m_settings;
  const toml::table& m_table;
  std::string m_file;
  std::string m_section;
};

/// LIGGGHTS's SI check on Young's modulus (physics.hpp: k_liggghts_min_E, k_liggghts_max_E), applied to the whole
/// range of a varied E and to a fixed [material] E once every table is read (the flags may follow [parameters]):
/// otherwise the study is accepted and its samples fail one by one when their cases are written.
void check_young_modulus_limits(const StudyConfig& c, const std::string& file, int material_E_line) {
  const auto it =
      std::find_if(c.parameters.begin(), c.parameters.end(), [](const ParameterRange& p) { return p.name == "E"; });
  const bool varied = it != c.parameters.end();
  const double low = varied ? it->bounds.low : c.material.E;
  const double high = varied ? it->bounds.high : c.material.E;
  const int line = varied ? it->line : material_E_line;
  const std::string what = varied ? fmt::format("[parameters] E: range [{:.4g}, {:.4g}] Pa", low, high)
                                  : fmt::format("[material] E: {:.4g} Pa", low);
  if (high > k_liggghts_max_E && !c.material.hard_particles)
    throw UserError(file, line,
                    fmt::format("{} reaches above {:.0e} Pa, which LIGGGHTS refuses in SI units: set [material] "
                                "hard_particles = true to allow it, or keep E <= {:.0e} Pa",
                                what, k_liggghts_max_E, k_liggghts_max_E));
  if (low < k_liggghts_min_E && !c.material.soft_particles)
    throw UserError(file, line,
                    fmt::format("{} reaches below {:.0e} Pa, which LIGGGHTS refuses in SI units: set [material] "
                                "soft_particles = true to allow it, or keep E >= {:.0e} Pa",
                                what, k_liggghts_min_E, k_liggghts_min_E));
}

/// "must be > 0, got 0" (and the bounds' reason): the message for a value outside a row's bounds.
[[noreturn]] void out_of_bounds(const TableReader& r, const toml::node& node, const Setting& s,
                                const std::string& value) {
  r.fail(node, s.key,
         fmt::format("{}, got {}{}", s.bounds.rule(), value, s.bounds.reason.empty() ? "" : ": " + s.bounds.reason));
}

/// Reads the value of a plain row: its type, its bounds, then the row's own assignment (which may refuse it).
void read_value(const TableReader& r, const Setting& s, const toml::node& node, StudyConfig& c) {
  SettingValue value;
  switch (s.type) {
    case SettingType::number: {
      const double v = r.number(s.key, node);
      if (!s.bounds.contains(v)) out_of_bounds(r, node, s, fmt::format("{}", v));
      value = v;
      break;
    }
    case SettingType::integer: {
      const long v = r.integer(s.key, node);
      if (!s.bounds.contains(static_cast<double>(v))) out_of_bounds(r, node, s, std::to_string(v));
      value = v;
      break;
    }
    case SettingType::boolean:
      value = r.boolean(s.key, node);
      break;
    case SettingType::string:
    case SettingType::enumeration:
      value = r.string(s.key, node);
      break;
    case SettingType::string_list:
      value = r.strings(s.key, node);
      break;
    case SettingType::number_list: {
      std::vector<double> v = r.numbers(s.key, node);
      for (double x : v)
        if (!s.bounds.contains(x)) out_of_bounds(r, node, s, fmt::format("{}", x));
      value = std::move(v);
      break;
    }
    case SettingType::table:
      assert(false && "a table row is read by dedicated code");
  }
  try {
    s.assign(c, value);
  } catch (const SettingError& e) {
    r.fail(node, s.key, e.what());
  }
}

/// One [parameters] entry `{ low, high, scale }`, into c.parameters; its admissible values are those of its row (the
/// [material] rules). Or a tie `{ same_as = "KEY" }`, into c.ties (checked once every entry is read: check_ties).
void read_parameter(const TableReader& r, const Setting& s, const toml::node& node, StudyConfig& c) {
  const toml::table& pt = r.table(s.key, node);
  const TableReader pr(r.settings(), pt, r.file(), "parameters." + s.key);
  ParameterRange p;
  p.name = s.key;
  p.line = r.line_of(node);
  bool low = false, high = false;
  std::optional<std::string> same_as;
  std::string range_key;  // the first key of a range, refused beside same_as
  pr.each([&](const std::string& pk, const toml::node& pn) {
    if (pk != "same_as" && range_key.empty()) range_key = pk;
    if (pk == "same_as") {
      same_as = pr.string(pk, pn);
    } else if (pk == "low") {
      p.bounds.low = pr.number(pk, pn);
      low = true;
    } else if (pk == "high") {
      p.bounds.high = pr.number(pk, pn);
      high = true;
    } else if (pk == "scale") {
      try {
        p.bounds.scale = sobol::scale_from_string(pr.string(pk, pn));
      } catch (const sobol::InputError& e) {
        pr.fail(pn, pk, e.what());
      }
    } else {
      return false;
    }
    return true;
  });
  if (same_as) {
    if (!range_key.empty())
      r.fail(node, s.key,
             fmt::format("same_as = \"{}\" ties it to {}, so it has no range of its own: remove '{}'", *same_as,
                         *same_as, range_key));
    c.ties.push_back({s.key, *same_as, p.line});
    return;
  }
  if (!low || !high) r.fail(node, s.key, "needs both 'low' and 'high' (or `same_as = \"KEY\"` to tie it to KEY)");
  try {
    sobol::validate_bounds({p.bounds}, {s.key});
  } catch (const sobol::InputError& e) {
    r.fail(node, s.key, e.what());
  }
  if (!s.bounds.contains(p.bounds.low) || !s.bounds.contains(p.bounds.high))
    r.fail(node, s.key, fmt::format("range [{}, {}] {}", p.bounds.low, p.bounds.high, s.bounds.rule()));
  c.parameters.push_back(std::move(p));
}

/// `[design] replicates = { points = P, repeats = R }` (P <= samples is checked with the section: check_section).
ReplicateSettings read_replicates(const TableReader& r, const Setting& s, const toml::node& node) {
  const toml::table& t = r.table(s.key, node);
  const TableReader tr(r.settings(), t, r.file(), "design." + s.key);
  ReplicateSettings rep;
  bool points = false, repeats = false;
  tr.each([&](const std::string& key, const toml::node& n) {
    if (key == "points") {
      const long v = tr.integer(key, n);
      if (v < 1 || v > 100000)
        tr.fail(n, key, fmt::format("must be in [1, [design] samples], got {}: the design points with replicates", v));
      rep.points = static_cast<int>(v);
      points = true;
    } else if (key == "repeats") {
      const long v = tr.integer(key, n);
      if (v < 2 || v > 1000)
        tr.fail(n, key,
                fmt::format("must be in [2, 1000], got {}: the cases per point, the design point's own included; "
                            "one case gives no variance",
                            v));
      rep.repeats = static_cast<int>(v);
      repeats = true;
    } else {
      return false;
    }
    return true;
  });
  if (!points || !repeats) r.fail(node, s.key, "needs both 'points' and 'repeats' ({ points = P, repeats = R })");
  return rep;
}

/// What one pass over the file collects besides the config: the keys given and their lines.
struct Seen {
  std::map<std::string, int> lines;  ///< "section.key" -> line
};

/// Reads one section through its rows: presets first (explicit keys override them), then every key in file order.
void read_section(const TableReader& r, const toml::table& table, StudyConfig& c, Seen& seen) {
  for (const Setting& s : r.settings().rows()) {
    if (s.section != r.section() || !s.first) continue;
    if (const toml::node* node = table.get(s.key)) read_value(r, s, *node, c);
  }
  r.each([&](const std::string& key, const toml::node& node) {
    const Setting* s = r.settings().find(r.section(), key);
    if (!s) {
      // A sub-table with rows of its own ([run.slurm]).
      const std::string sub = r.section() + "." + key;
      const auto& sections = r.settings().sections();
      if (std::none_of(sections.begin(), sections.end(), [&](const SettingSection& x) { return x.name == sub; }))
        return false;
      read_section(TableReader(r.settings(), r.table(key, node), r.file(), sub), r.table(key, node), c, seen);
      return true;
    }
    seen.lines[s->section + "." + key] = r.line_of(node);
    if (s->first) return true;
    if (s->type == SettingType::table && r.section() == "design")
      c.replicates = read_replicates(r, *s, node);
    else if (s->type == SettingType::table)
      read_parameter(r, *s, node, c);
    else
      read_value(r, *s, node, c);
    return true;
  });
}

/// A section's cross-key rules fail at the line of the key they name (SectionCheck).
class SectionAt final : public SectionCheck {
 public:
  SectionAt(const TableReader& reader, const toml::table& table) : m_reader(reader), m_table(table) {}
  const std::string& section() const override { return m_reader.section(); }
  bool given(const std::string& key) const override { return m_table.get(key) != nullptr; }
  [[noreturn]] void fail(const std::string& key, const std::string& message) const override {
    if (const toml::node* node = m_table.get(key)) m_reader.fail(*node, key, message);
    m_reader.fail(m_table, key, message);
  }

 private:
  const TableReader& m_reader;
  const toml::table& m_table;
};

/// The rules that tie keys of one section together.
void check_section(const TableReader& r, const toml::table& table, StudyConfig& c) {
  const std::string& section = r.section();
  if (const ExperimentSchema* experiment = r.settings().owner(section)) {
    if (experiment->check) experiment->check(c, SectionAt(r, table));
  } else if (section == "design") {
    if (c.replicates.points > c.samples)
      r.fail(*table.get("replicates"), "replicates",
             fmt::format("points = {} exceeds [design] samples = {}: the replicates are taken at the first P design "
                         "points",
                         c.replicates.points, c.samples));
  } else if (section == "timestep") {
    if (c.timestep.mode == TimestepMode::fixed && !(c.timestep.value > 0))
      r.fail(table, "value", "mode = \"fixed\" needs value = the time step in seconds");
  }
}

/// Refuses a non-ASCII character anywhere but in a value's string or a comment, before toml++ reads the text: toml++
/// 3.3 asks whether such a character (U+00A1 to U+0499) in code is whitespace and reaches TOML_UNREACHABLE, i.e.
/// undefined behaviour (impl/unicode_autogenerated.h, is_non_ascii_horizontal_whitespace; found by
/// bench/fuzz-study-file.sh). The check follows TOML 1.0's grammar only as far as it must to tell a value's string
/// from code, and where it cannot be sure what toml++ reads, it reads code: a quote opens a string only where TOML
/// has one (a key at a line's start or after '.', '[' of a header, ',' or '{' of an inline table; a value after '=',
/// or after '[' or ',' inside an array), and a key's string (single-line in TOML, `"""` there included) takes no
/// non-ASCII character, since a malformed key is where toml++'s reading and this one may part. A leading UTF-8 byte
/// order mark is allowed, as toml++ allows it.
void check_ascii_outside_strings(const std::string& text, const std::string& name) {
  enum class In { code, comment, key_basic, key_literal, basic, literal, multiline_basic, multiline_literal };
  In in = In::code;
  long line = 1;
  char previous = '\n';       // the last character of code that is not blank
  bool header = false;        // inside a table header "[a.b]" or "[[a.b]]"
  std::vector<char> nesting;  // the open arrays '[' and inline tables '{' of values
  bool key_context = true;    // a key may come (a line's start, after '{' or an inline table's ',')
  const auto at = [&](std::size_t i, std::string_view s) { return text.compare(i, s.size(), s) == 0; };
  const auto refuse = [&](std::string_view where) {
    throw UserError(name, line,
                    fmt::format("a non-ASCII character {} (TOML allows them only in strings and comments, and "
                                "demsa only in the strings of values)",
                                where));
  };
  for (std::size_t i = at(0, "\xEF\xBB\xBF") ? 3 : 0; i < text.size(); ++i) {
    const char c = text[i];
    const bool non_ascii = static_cast<unsigned char>(c) >= 0x80;
    if (c == '\n') {
      ++line;
      if (in == In::code || in == In::comment || in == In::basic || in == In::literal || in == In::key_basic ||
          in == In::key_literal) {
        in = In::code;  // these end at the line's end
        previous = '\n';
        header = false;
        if (nesting.empty()) key_context = true;
      }
      continue;
    }
    const bool escape = c == '\\' && i + 1 < text.size() && text[i + 1] != '\n';
    switch (in) {
      case In::code: {
        if (non_ascii) refuse("outside a string or a comment");
        if (c == ' ' || c == '\t' || c == '\r') break;
        const bool in_array = !header && !nesting.empty() && nesting.back() == '[';
        const bool value_place =
            previous == '=' || (in_array && std::string_view("[,\n").find(previous) != std::string_view::npos);
        const bool key_place = !value_place && std::string_view("\n[,{.").find(previous) != std::string_view::npos;
        const char before = previous;
        previous = c;
        if (c == '#') {
          in = In::comment;
        } else if (c == '=') {
          // Only the '=' after a key opens a value; any other (`n = -n = "...`) is inside a malformed value, which
          // toml++ reads on as code.
          const bool separator = key_context && !header && (nesting.empty() || nesting.back() == '{');
          key_context = false;
          if (!separator) previous = '~';
        } else if ((c == '"' || c == '\'') && value_place) {
          if (at(i, "\"\"\"") || at(i, "\'\'\'")) {
            in = c == '"' ? In::multiline_basic : In::multiline_literal;
            i += 2;
          } else {
            in = c == '"' ? In::basic : In::literal;
          }
        } else if ((c == '"' || c == '\'') && key_place) {
          in = c == '"' ? In::key_basic : In::key_literal;
        } else if (c == '[') {
          if (nesting.empty() && (before == '\n' || (header && before == '[')))
            header = true;
          else if (value_place)
            nesting.push_back('[');
          else
            previous = '~';  // inside a malformed value (`a = 5.6["...`), which toml++ reads on as code
        } else if (c == ']') {
          if (header)
            header = false;  // the second ']' of "]]" then closes nothing
          else if (!nesting.empty() && nesting.back() == '[')
            nesting.pop_back();
        } else if (c == '{') {
          if (value_place) {
            nesting.push_back('{');
            key_context = true;
          } else {
            previous = '~';
          }
        } else if (c == '}') {
          if (!nesting.empty() && nesting.back() == '{') nesting.pop_back();
          key_context = false;
        } else if (c == ',') {
          key_context = !nesting.empty() && nesting.back() == '{';
        }
        break;
      }
      case In::comment:
        break;
      case In::key_basic:
      case In::key_literal:
        if (non_ascii) refuse("in a key (demsa's keys are ASCII names)");
        if (in == In::key_basic && escape)
          ++i;
        else if (c == (in == In::key_basic ? '"' : '\''))
          in = In::code, previous = c;
        break;
      case In::basic:
        if (escape)
          ++i;
        else if (c == '"')
          in = In::code, previous = c;
        break;
      case In::literal:
        if (c == '\'') in = In::code, previous = c;
        break;
      case In::multiline_basic:
        if (escape) {
          ++i;
        } else if (at(i, "\"\"\"")) {
          in = In::code, previous = '"';
          i += 2;
        }
        break;
      case In::multiline_literal:
        if (at(i, "\'\'\'")) {
          in = In::code, previous = '\'';
          i += 2;
        }
        break;
    }
  }
}

}  // namespace

StudyConfig SettingsTable::parse(const std::string& text, const std::filesystem::path& file) const {
  const std::string name = file.filename().string();
  check_ascii_outside_strings(text, name);
  toml::table root;
  try {
    root = toml::parse(text, file.string());
  } catch (const toml::parse_error& e) {
    throw UserError(name, static_cast<int>(e.source().begin.line), std::string(e.description()));
  }
  StudyConfig c;
  c.file = file;
  c.table = this;
  Seen seen;
  const TableReader top(*this, root, name, "");

  std::vector<std::string> sections;
  std::map<std::string, int> section_lines;  ///< the top-level tables given, and their lines
  for (const SettingSection& s : m_sections)
    if (s.name.find('.') == std::string::npos) sections.push_back(s.name);
  for (const auto& [key, node] : root) {
    const std::string section(key.str());
    if (std::find(sections.begin(), sections.end(), section) == sections.end()) {
      std::vector<std::string> sorted = sections;
      std::sort(sorted.begin(), sorted.end());
      throw UserError(name, top.line_of(node), fmt::format("unknown section [{}] (valid: {})", section, join(sorted)));
    }
    const toml::table& table = top.table(section, node);
    section_lines[section] = top.line_of(node);
    const TableReader r(*this, table, name, section);
    read_section(r, table, c, seen);
    check_section(r, table, c);
  }

  for (const Setting& s : m_rows) {
    if (!s.required || seen.lines.count(s.section + "." + s.key)) continue;
    const std::string choices = s.choices.empty() ? "" : " (" + join(s.choices, " or ") + ")";
    throw UserError(name, 0, fmt::format("[{}] {} is required{}", s.section, s.key, choices));
  }
  // The table of another experiment would be silently ignored: its values would look used and are not.
  for (const auto& [section, line] : section_lines) {
    const ExperimentSchema* experiment = owner(section);
    if (!experiment || experiment->name == c.experiment) continue;
    const auto at = seen.lines.find("study.experiment");
    throw UserError(
        name, line,
        fmt::format("[{}] does not apply to this study: [study] experiment = \"{}\"{}; remove the table or "
                    "change the experiment",
                    section, c.experiment, at == seen.lines.end() ? "" : fmt::format(" (line {})", at->second)));
  }
  if (c.parameters.empty()) throw UserError(name, 0, "[parameters] must vary at least one parameter");
  std::vector<std::string> varied;
  for (const ParameterRange& p : c.parameters) varied.push_back(p.name);
  for (const ParameterTie& t : c.ties)
    if (const std::string problem = tie_problem(t, c.ties, varied); !problem.empty())
      throw UserError(name, t.line, fmt::format("[parameters] {}: {}", t.name, problem));
  // A tied parameter takes every value of its partner's range: each must be admissible for it too (no E = nu).
  for (const ParameterTie& t : c.ties) {
    const Setting* row = find("parameters", t.name);
    assert(row && "a [parameters] key without a row");
    for (const ParameterRange& p : c.parameters)
      if (p.name == t.partner && (!row->bounds.contains(p.bounds.low) || !row->bounds.contains(p.bounds.high)))
        throw UserError(
            name, t.line,
            fmt::format("[parameters] {}: same_as = \"{}\": the range [{}, {}] of {} (line {}) {} for {}", t.name,
                        t.partner, p.bounds.low, p.bounds.high, t.partner, p.line, row->bounds.rule(), t.name));
  }
  // The optimised Latin hypercubes keep an N x N matrix of the sample pairs: refused here, at its line, rather than
  // when `demsa run` draws the design and runs out of memory.
  const bool optimised = c.design == sobol::to_string(sobol::DesignKind::lhs_maximin) ||
                         c.design == sobol::to_string(sobol::DesignKind::lhs_cl2);
  if (optimised && c.samples > k_max_optimised_lhs_samples) {
    const auto at =
        seen.lines.count("design.samples") ? seen.lines.find("design.samples") : seen.lines.find("design.method");
    throw UserError(
        name, at == seen.lines.end() ? 0 : at->second,
        fmt::format("[design] samples: method \"{}\" takes at most {} samples (its optimiser keeps an N x N "
                    "matrix of the sample pairs), got {}; use \"lhs\" or \"sobol\" for more",
                    c.design, k_max_optimised_lhs_samples, c.samples));
  }
  // Keep the paper's order (eq. 1) whatever order the file lists them in.
  const auto& order = contact_parameter_names();
  std::sort(c.parameters.begin(), c.parameters.end(), [&](const ParameterRange& a, const ParameterRange& b) {
    return std::find(order.begin(), order.end(), a.name) < std::find(order.begin(), order.end(), b.name);
  });
  std::sort(c.ties.begin(), c.ties.end(), [&](const ParameterTie& a, const ParameterTie& b) {
    return std::find(order.begin(), order.end(), a.name) < std::find(order.begin(), order.end(), b.name);
  });
  const auto E_line = seen.lines.find("material.E");
  check_young_modulus_limits(c, name, E_line == seen.lines.end() ? 0 : E_line->second);
  return c;
}

StudyConfig SettingsTable::load(const std::filesystem::path& file) const {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    throw UserError(fmt::format("{}: is a folder, not a study file (give the study's .toml file{})", file.string(),
                                std::filesystem::exists(file / k_frozen_study, ec)
                                    ? fmt::format("; this folder's frozen copy is {}", (file / k_frozen_study).string())
                                    : ""));
  if (const std::optional<std::string> kind = postprocess::special_file_kind(file))
    throw UserError(file.string(), 0, postprocess::special_file_message(*kind));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw UserError(file.string() + ": cannot read the study file");
  // Read at most one byte more than a study file may hold: /dev/zero or a huge file is refused, not read whole.
  std::string text(k_max_study_file_bytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw UserError(file.string() + ": cannot read the study file");
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > k_max_study_file_bytes)
    throw UserError(fmt::format("{}: larger than {} bytes; a study file is a few kB of TOML", file.string(),
                                k_max_study_file_bytes));
  StudyConfig c = parse(text, file);
  c.file = file;
  return c;
}

double Material::*material_member(std::string_view key) {
  // One entry per contact parameter of study/parameters.hpp, in the paper's order.
  static constexpr std::array<std::pair<std::string_view, double Material::*>, 7> members{{
      {"E", &Material::E},
      {"nu", &Material::nu},
      {"mu_pp", &Material::mu_pp},
      {"mu_pw", &Material::mu_pw},
      {"e_r", &Material::e_r},
      {"mu_r_pp", &Material::mu_r_pp},
      {"mu_r_pw", &Material::mu_r_pw},
  }};
  for (const auto& [name, member] : members)
    if (name == key) return member;
  return nullptr;
}

Material material_for(const StudyConfig& config, const std::vector<double>& physical) {
  assert(physical.size() == config.parameters.size());
  Material m = config.material;
  for (std::size_t i = 0; i < physical.size(); ++i) {
    const auto member = material_member(config.parameters[i].name);
    assert(member && "unknown parameter name in config.parameters");
    m.*member = physical[i];
  }
  for (const ParameterTie& t : config.ties) {
    const auto tied = material_member(t.name), partner = material_member(t.partner);
    assert(tied && partner && "a tie not checked by the parser");
    m.*tied = m.*partner;
  }
  return m;
}

std::string_view rolling_model_name(RollingModel model) {
  switch (model) {
    case RollingModel::cdt:
      return "cdt";
    case RollingModel::epsd:
      return "epsd";
    case RollingModel::epsd2:
      return "epsd2";
    case RollingModel::epsd3:
      return "epsd3";
    case RollingModel::viscous:
      return "viscous";
  }
  assert(false && "rolling model without a name");
  return "cdt";
}

double viscous_unit_factor(ViscousUnit unit) {
  // 1 mm·ms = 1e-3 m × 1e-3 s = 1e-6 s·m.
  return unit == ViscousUnit::mm_ms ? 1e-6 : 1.0;
}

sobol::MetamodelOptions AnalysisSettings::metamodel_options() const {
  sobol::MetamodelOptions o;
  o.gp.kernel = gp_kernel;
  o.gp.trend = gp_trend;
  o.gp.nugget = gp_nugget;
  return o;
}

}  // namespace demsa::study
