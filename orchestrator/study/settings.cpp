#include "orchestrator/study/settings.hpp"

#include "orchestrator/study/setting_row.hpp"

#include "orchestrator/study/parameters.hpp"
#include "orchestrator/util/log.hpp"
#include "sobol/design.hpp"
#include "sobol/enum_names.hpp"
#include "sobol/error.hpp"
#include "sobol/metamodel.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/saltelli.hpp"
#include "sobol/scaling.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>
#include <utility>

namespace demsa::study {

namespace {

std::string fnv1a_64(const std::string& text) {
  std::uint64_t h = 1469598103934665603ULL;
  for (const unsigned char ch : text) {
    h ^= ch;
    h *= 1099511628211ULL;
  }
  return fmt::format("{:016x}", h);
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::string markdown_cell(std::string text) {
  // A '|' ends a cell unless escaped; the docs write \| themselves where they mean |x|.
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '|' && (i == 0 || text[i - 1] != '\\')) out += '\\';
    out += text[i];
  }
  return out;
}

}  // namespace

std::string shortest(double v) {
  const std::string fixed = fmt::format("{}", v);
  for (int digits = 1; digits <= 17; ++digits) {
    const std::string g = fmt::format("{:.{}g}", v, digits);
    if (std::stod(g) == v) return g.size() < fixed.size() ? g : fixed;
  }
  return fixed;
}

std::string canonical_number(double v) { return fmt::format("{:.17g}", v); }

std::string code_list(const std::vector<std::string>& names) {
  std::vector<std::string> quoted;
  for (const std::string& name : names) quoted.push_back(fmt::format("`{}`", name));
  return util::join(quoted);
}

SettingBounds step_bounds() {
  return between(1, true, k_max_steps, true,
                 "LIGGGHTS reads step counts through variables printed with 15 significant digits");
}

void check_radii(const RadiusDistribution& radii, const SectionCheck& at) {
  const std::string key = at.given("r_min") ? "r_min" : "r_max";
  if (!(radii.r_min < radii.r_max))
    at.fail(key, fmt::format("r_min ({}) must be less than r_max ({})", radii.r_min, radii.r_max));
  if (radii.mean < radii.r_min || radii.mean > radii.r_max)
    at.fail(key,
            fmt::format("r_mean ({}) must lie in [r_min, r_max] = [{}, {}]", radii.mean, radii.r_min, radii.r_max));
  // The share of N(mean, sd) inside [r_min, r_max] falls as sd grows (both ends of the standardised interval move
  // towards 0), so the largest admissible sd is found by bisection for the message.
  const auto share = [&](double sd) {
    const auto phi = [](double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); };
    return phi((radii.r_max - radii.mean) / sd) - phi((radii.r_min - radii.mean) / sd);
  };
  if (share(radii.sd) < k_min_radius_acceptance) {
    double low = 0, high = radii.sd;
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (low + high);
      (share(mid) >= k_min_radius_acceptance ? low : high) = mid;
    }
    at.fail(at.given("r_sd") ? "r_sd" : key,
            fmt::format("r_sd = {} m leaves {:.3g} of the normal distribution in [r_min, r_max] = [{}, {}] m, less "
                        "than {} (the radii are drawn by rejection): r_sd must be at most {:.4g} m",
                        radii.sd, share(radii.sd), radii.r_min, radii.r_max, k_min_radius_acceptance, low));
  }
}

std::vector<Setting> finish_rows(std::vector<Row>& rows) {
  std::vector<Setting> settings;
  for (Row& row : rows) settings.push_back(std::move(row).finish());
  return settings;
}

std::string to_string(SettingType type) {
  static const sobol::EnumNames<SettingType> names{"setting type",
                                                   {{SettingType::number, "number"},
                                                    {SettingType::integer, "integer"},
                                                    {SettingType::boolean, "boolean"},
                                                    {SettingType::string, "string"},
                                                    {SettingType::string_list, "string list"},
                                                    {SettingType::number_list, "number list"},
                                                    {SettingType::enumeration, "enum"},
                                                    {SettingType::table, "table"}}};
  return names.to_string(type);
}

std::string to_string(SettingEffect effect) {
  static const sobol::EnumNames<SettingEffect> names{
      "setting effect",
      {{SettingEffect::cases, "cases"}, {SettingEffect::measurement, "measurement"}, {SettingEffect::none, "none"}}};
  return names.to_string(effect);
}

bool SettingBounds::contains(double value) const {
  if (low && (low->inclusive ? value < low->value : !(value > low->value))) return false;
  if (high && (high->inclusive ? value > high->value : !(value < high->value))) return false;
  return true;
}

std::string SettingBounds::text() const {
  // An integer bound reads as the integer it is (100000, not 1e+05).
  const auto show = [this](double v) { return integral ? fmt::format("{:.0f}", v) : shortest(v); };
  if (low && high)
    return fmt::format("{}{}, {}{}", low->inclusive ? "[" : "(", show(low->value), show(high->value),
                       high->inclusive ? "]" : ")");
  if (low) return fmt::format("{} {}", low->inclusive ? ">=" : ">", show(low->value));
  if (high) return fmt::format("{} {}", high->inclusive ? "<=" : "<", show(high->value));
  return {};
}

std::string SettingBounds::rule() const {
  if (!low && !high) return {};
  return (low && high ? "must lie in " : "must be ") + text();
}

SettingsTable::SettingsTable(std::vector<SettingSection> sections, std::vector<Setting> rows,
                             std::vector<ExperimentSchema> experiments)
    : m_sections(std::move(sections)), m_experiments(std::move(experiments)) {
  // Section by section in the order of the sections (stable: the table order within a section).
  for (const SettingSection& section : m_sections)
    for (Setting& s : rows)
      if (s.section == section.name) m_rows.push_back(std::move(s));
  assert(m_rows.size() == rows.size() && "a row of an unlisted section");
  // [study] experiment: one of the experiments' names.
  std::vector<std::string> names;
  std::string summaries;
  for (const ExperimentSchema& e : m_experiments) {
    names.push_back(e.name);
    summaries += fmt::format("{}`{}` ({})", summaries.empty() ? "" : ", ", e.name, e.summary);
  }
  for (Setting& s : m_rows) {
    if (s.section != "study" || s.key != "experiment") continue;
    s.type = SettingType::enumeration;
    s.choices = names;
    s.range_text = code_list(names);
    s.doc = "the experiment the cases simulate: " + summaries;
    s.assign = [names](StudyConfig& c, const SettingValue& v) {
      const std::string& value = std::get<std::string>(v);
      if (std::find(names.begin(), names.end(), value) == names.end())
        throw SettingError(fmt::format("unknown value '{}' (valid: {})", value, util::join(names)));
      c.experiment = value;
    };
  }
}

const Setting* SettingsTable::find(const std::string& section, const std::string& key) const {
  for (const Setting& s : m_rows)
    if (s.section == section && s.key == key) return &s;
  return nullptr;
}

const ExperimentSchema* SettingsTable::experiment(const std::string& name) const {
  for (const ExperimentSchema& e : m_experiments)
    if (e.name == name) return &e;
  return nullptr;
}

const ExperimentSchema* SettingsTable::owner(const std::string& section) const {
  for (const ExperimentSchema& e : m_experiments)
    if (std::find(e.sections.begin(), e.sections.end(), section) != e.sections.end()) return &e;
  return nullptr;
}

bool SettingsTable::applies(const Setting& s, const std::string& experiment) const {
  const ExperimentSchema* e = owner(s.section);
  return !e || e->name == experiment;
}

std::vector<std::string> SettingsTable::keys(const std::string& section) const {
  // The keys of a table row ("parameters.E": low, high, scale).
  if (const std::size_t dot = section.rfind('.'); dot != std::string::npos)
    if (const Setting* s = find(section.substr(0, dot), section.substr(dot + 1)); s && s->type == SettingType::table)
      return s->choices;
  std::vector<std::string> keys;
  for (const Setting& s : m_rows)
    if (s.section == section) keys.push_back(s.key);
  const std::string prefix = section + ".";
  for (const SettingSection& sub : m_sections)
    if (sub.name.rfind(prefix, 0) == 0) keys.push_back(sub.name.substr(prefix.size()));
  return keys;
}

std::string SettingsTable::unknown_key_hint(const std::string& section, const std::string& key) const {
  // Keys an earlier demsa knew, each with the hint of the experiment that retired it.
  if (const ExperimentSchema* e = owner(section))
    if (const auto it = e->retired_keys.find(key); it != e->retired_keys.end()) return " (" + it->second + ")";
  const std::vector<std::string> names = keys(section);
  if (names.empty()) return {};
  // The nearest key by edit distance, if it is near enough to be a typo, or a key this one begins (or that begins it).
  std::string best;
  std::size_t best_distance = std::string::npos;
  for (const std::string& k : names) {
    const std::size_t d = edit_distance(key, k);
    const bool prefix = !key.empty() && (k.rfind(key, 0) == 0 || key.rfind(k, 0) == 0);
    const std::size_t score = prefix ? std::min<std::size_t>(d, 1) : d;
    if (score < best_distance) {
      best_distance = score;
      best = k;
    }
  }
  const std::size_t near_enough = std::max<std::size_t>(2, key.size() / 3);
  const std::string valid = "valid: " + util::join(names);
  if (best_distance <= near_enough) return fmt::format(" (did you mean '{}'? {})", best, valid);
  return " (" + valid + ")";
}

std::string SettingsTable::hash_text(const StudyConfig& config) const {
  // The rows of effect cases give exactly the text of the first version (same keys, order and number format), so a
  // study keeps its hash. The measurement rows came later: a value at its default adds nothing, so studies that
  // never changed them keep their hash too; a study made before, with a non-default measurement value, is refused
  // once as changed (`demsa run --new` starts it again).
  std::string text = cases_hash_text(config);
  const StudyConfig defaults;
  for (const Setting& s : m_rows)
    if (s.effect == SettingEffect::measurement && applies(s, config.experiment) &&
        s.canonical(config) != s.canonical(defaults))
      for (const auto& [key, value] : s.canonical(config)) text += key + "=" + value + "\n";
  return text;
}

std::string SettingsTable::cases_hash_text(const StudyConfig& config) const {
  std::string text;
  for (const Setting& s : m_rows)
    if (s.effect == SettingEffect::cases && applies(s, config.experiment))
      for (const auto& [key, value] : s.canonical(config)) text += key + "=" + value + "\n";
  return text;
}

std::vector<std::string> SettingsTable::changed(const StudyConfig& before, const StudyConfig& after) const {
  std::vector<std::string> changed;
  for (const Setting& s : m_rows) {
    if (s.effect == SettingEffect::none) continue;
    if (s.canonical(before) == s.canonical(after)) continue;
    changed.push_back(fmt::format("[{}] {}: {} -> {}", s.section, s.key, s.show(before), s.show(after)));
  }
  return changed;
}

std::string SettingsTable::markdown() const {
  std::string md;
  for (const SettingSection& section : m_sections) {
    const bool sub = section.name.find('.') != std::string::npos;
    md += fmt::format("{} [{}]\n\n", sub ? "###" : "##", section.name);
    if (!section.intro.empty()) md += section.intro + "\n\n";
    md += "| key | type | default | admissible | unit | effect | meaning |\n|---|---|---|---|---|---|---|\n";
    for (const Setting& s : m_rows) {
      if (s.section != section.name) continue;
      md += fmt::format("| `{}` | {} | {} | {} | {} | {} | {} |\n", s.key, to_string(s.type),
                        markdown_cell(s.default_text), markdown_cell(s.range_text.empty() ? "—" : s.range_text),
                        s.unit.empty() ? "—" : s.unit, to_string(s.effect), markdown_cell(s.doc));
    }
    md += "\n";
    if (!section.notes.empty()) md += section.notes + "\n\n";
  }
  while (md.size() >= 2 && md.substr(md.size() - 2) == "\n\n") md.pop_back();
  return md;
}

std::string design_hash(const StudyConfig& config) {
  assert(config.table && "a config not read through a settings table");
  return fnv1a_64(config.table->hash_text(config));
}

std::string cases_hash(const StudyConfig& config) {
  assert(config.table && "a config not read through a settings table");
  return fnv1a_64(config.table->cases_hash_text(config));
}

}  // namespace demsa::study
