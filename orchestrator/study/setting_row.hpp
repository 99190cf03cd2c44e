#pragma once
// How a row of the settings table is built (settings.hpp): the Row builder, the bounds helpers and the shared rows
// (a particle set's radii, presets). The core sections (settings.cpp) and every experiment's own section
// (orchestrator/experiments/) build their rows with it, so that a key is parsed, hashed and documented the same way
// wherever it is declared.
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace demsa::study {

using Lines = std::vector<std::pair<std::string, std::string>>;

/// The shortest text that reads back as the same double, in fixed or exponent notation (1e+08 rather than
/// 100000000, 2500 rather than 2.5e+03): for docs and messages.
std::string shortest(double v);
/// The design hash's number format since the first version: 17 significant digits.
std::string canonical_number(double v);
/// The names as markdown code, joined: "`a`, `b`".
std::string code_list(const std::vector<std::string>& names);

inline SettingBounds greater(double v, std::string reason = {}) {
  return {SettingBound{v, false}, std::nullopt, std::move(reason)};
}
inline SettingBounds at_least(double v) { return {SettingBound{v, true}, std::nullopt, {}}; }
inline SettingBounds between(double low, bool low_in, double high, bool high_in, std::string reason = {}) {
  return {SettingBound{low, low_in}, SettingBound{high, high_in}, std::move(reason)};
}
inline const SettingBounds k_positive = greater(0);
inline const SettingBounds k_non_negative = at_least(0);

// Upper bounds of the settings that size what demsa holds in memory, each far above any DEM study and low enough
// that what it asks for exists: a typo of a few digits (or a 64-bit value) is refused at its line instead of ending
// in std::bad_alloc or being narrowed.
inline constexpr double k_max_particles = 1e7;
inline constexpr double k_max_steps = 1e12;

// The physical ranges shared by every experiment: a particle radius between a fine powder's and a boulder's, and
// the sizes and times of a laboratory-scale test (they bound the meshes, lattices and step counts a case needs).
inline constexpr double k_min_radius = 1e-6;
inline constexpr double k_max_radius = 1.0;
/// The least share of the normal distribution of a particle set that must lie in [r_min, r_max]: the radii are drawn
/// by rejection, so this bounds the draws per radius (100 on average).
inline constexpr double k_min_radius_acceptance = 0.01;
/// The longest simulated time of a stage of a case [s]: hours of a laboratory test.
inline constexpr double k_max_duration = 1e4;
inline const SettingBounds k_duration_bounds = between(0, true, k_max_duration, true);
inline SettingBounds radius_bounds() {
  return between(k_min_radius, true, k_max_radius, true, "from a fine powder's particles to a boulder");
}

/// The bounds of a step count: LIGGGHTS reads step counts through variables printed with 15 significant digits.
SettingBounds step_bounds();

/// Builds one row. The typed setters take the field as a generic lambda `[](auto& c) -> auto& { return c.x; }`
/// (FIELD below), called with a StudyConfig& to assign and a const StudyConfig& to show and hash.
class Row {
 public:
  Row(std::string section, std::string key) {
    m_s.section = std::move(section);
    m_s.key = std::move(key);
    m_s.hash_key = m_s.key;
  }
  Row& doc(std::string text) { return m_s.doc = std::move(text), *this; }
  Row& unit(std::string text) { return m_s.unit = std::move(text), *this; }
  Row& effect(SettingEffect e) { return m_s.effect = e, *this; }
  Row& cases(std::string hash_key) {
    m_s.hash_key = std::move(hash_key);
    return effect(SettingEffect::cases);
  }
  Row& measurement(std::string hash_key) {
    m_s.hash_key = std::move(hash_key);
    return effect(SettingEffect::measurement);
  }
  Row& default_text(std::string text) { return m_s.default_text = std::move(text), *this; }
  Row& range(std::string text) { return m_s.range_text = std::move(text), *this; }
  Row& required() { return m_s.required = true, *this; }
  Row& first() { return m_s.first = true, *this; }

  template <typename F>
  Row& number(F field, SettingBounds bounds = {}) {
    m_s.type = SettingType::number;
    m_s.bounds = std::move(bounds);
    m_s.assign = [field](StudyConfig& c, const SettingValue& v) { field(c) = std::get<double>(v); };
    m_s.show = [field](const StudyConfig& c) { return shortest(field(c)); };
    return scalar_canonical([field](const StudyConfig& c) { return canonical_number(field(c)); });
  }
  /// An integer row: `bounds` must lie inside the range of the field's type, so that the parser refuses (at its line)
  /// every value the field cannot hold instead of narrowing it (4294967304 into an int is 8).
  template <typename F>
  Row& integer(F field, SettingBounds bounds) {
    using T = std::remove_cvref_t<decltype(field(std::declval<StudyConfig&>()))>;
    static_assert(std::is_integral_v<T>);
    // A TOML integer is 64-bit signed: only a field that holds every such value may leave out the upper bound.
    assert(bounds.low && bounds.low->value >= static_cast<double>(std::numeric_limits<T>::min()) &&
           "an integer row needs a lower bound inside its field's type");
    assert((bounds.high
                ? bounds.high->value <= static_cast<double>(std::numeric_limits<T>::max())
                : std::cmp_greater_equal(std::numeric_limits<T>::max(), std::numeric_limits<std::int64_t>::max())) &&
           "an integer row needs an upper bound inside its field's type");
    m_s.type = SettingType::integer;
    m_s.bounds = std::move(bounds);
    m_s.bounds.integral = true;
    m_s.assign = [field](StudyConfig& c, const SettingValue& v) {
      const long value = std::get<long>(v);
      // The parser checked the bounds; this holds whatever a bound says.
      if (!std::in_range<T>(value)) throw SettingError(fmt::format("{} does not fit the setting", value));
      field(c) = static_cast<T>(value);
    };
    m_s.show = [field](const StudyConfig& c) { return std::to_string(field(c)); };
    return scalar_canonical(m_s.show);
  }
  template <typename F>
  Row& boolean(F field) {
    m_s.type = SettingType::boolean;
    m_s.assign = [field](StudyConfig& c, const SettingValue& v) { field(c) = std::get<bool>(v); };
    m_s.show = [field](const StudyConfig& c) { return std::string(field(c) ? "true" : "false"); };
    return scalar_canonical([field](const StudyConfig& c) { return std::string(field(c) ? "1" : "0"); });
  }
  template <typename F>
  Row& string(F field) {
    m_s.type = SettingType::string;
    m_s.assign = [field](StudyConfig& c, const SettingValue& v) { field(c) = std::get<std::string>(v); };
    m_s.show = [field](const StudyConfig& c) { return fmt::format("\"{}\"", field(c)); };
    return scalar_canonical([field](const StudyConfig& c) { return std::string(field(c)); });
  }
  template <typename F>
  Row& strings(F field) {
    m_s.type = SettingType::string_list;
    m_s.assign = [field](StudyConfig& c, const SettingValue& v) { field(c) = std::get<std::vector<std::string>>(v); };
    m_s.show = [field](const StudyConfig& c) {
      std::vector<std::string> quoted;
      for (const std::string& s : field(c)) quoted.push_back(fmt::format("\"{}\"", s));
      return fmt::format("[{}]", util::join(quoted));
    };
    return list_canonical([field](const StudyConfig& c) { return field(c); });
  }
  template <typename F>
  Row& numbers(F field, SettingBounds bounds = {}) {
    m_s.type = SettingType::number_list;
    m_s.bounds = std::move(bounds);
    m_s.assign = [field](StudyConfig& c, const SettingValue& v) { field(c) = std::get<std::vector<double>>(v); };
    m_s.show = [field](const StudyConfig& c) {
      std::vector<std::string> values;
      for (double v : field(c)) values.push_back(shortest(v));
      return fmt::format("[{}]", util::join(values));
    };
    return list_canonical([field](const StudyConfig& c) {
      std::vector<std::string> values;
      for (double v : field(c)) values.push_back(canonical_number(v));
      return values;
    });
  }
  /// An enum of the study layer: the names and their values, here only.
  template <typename F, typename E>
  Row& choice(F field, std::vector<std::pair<std::string, E>> options) {
    m_s.type = SettingType::enumeration;
    for (const auto& option : options) m_s.choices.push_back(option.first);
    m_s.assign = [field, options, names = m_s.choices](StudyConfig& c, const SettingValue& v) {
      const std::string& value = std::get<std::string>(v);
      for (const auto& [name, e] : options)
        if (name == value) return void(field(c) = e);
      throw SettingError(fmt::format("unknown value '{}' (valid: {})", value, util::join(names)));
    };
    m_s.show = [field, options](const StudyConfig& c) {
      for (const auto& [name, e] : options)
        if (field(c) == e) return fmt::format("\"{}\"", name);
      assert(false && "enum value without a name");
      return std::string();
    };
    return scalar_canonical([field, options](const StudyConfig& c) {
      for (const auto& [name, e] : options)
        if (field(c) == e) return name;
      return std::string();
    });
  }
  /// An enum of sobol/: its from_string (which may accept aliases and names the valid names when it throws) and
  /// to_string; `values` lists the values a study may use, in the order the docs show them.
  template <typename F, typename E, typename From, typename To>
  Row& choice(F field, const std::vector<E>& values, From from_string, To to_string) {
    m_s.type = SettingType::enumeration;
    for (const E& e : values) m_s.choices.push_back(to_string(e));
    m_s.assign = [field, from_string](StudyConfig& c, const SettingValue& v) {
      try {
        field(c) = from_string(std::get<std::string>(v));
      } catch (const sobol::InputError& e) {
        throw SettingError(e.what());
      }
    };
    m_s.show = [field, to_string](const StudyConfig& c) { return fmt::format("\"{}\"", to_string(field(c))); };
    return scalar_canonical([field, to_string](const StudyConfig& c) { return to_string(field(c)); });
  }
  /// Makes a string row an enumeration of `names` (its assignment, set before, refuses other names).
  Row& names(std::vector<std::string> names) {
    m_s.type = SettingType::enumeration;
    m_s.choices = std::move(names);
    return *this;
  }
  /// A table row read by dedicated parser code.
  Row& table(std::vector<std::string> keys, std::function<std::string(const StudyConfig&)> show,
             std::function<Lines(const StudyConfig&)> canonical) {
    m_s.type = SettingType::table;
    m_s.choices = std::move(keys);
    m_s.show = std::move(show);
    m_s.canonical = std::move(canonical);
    return *this;
  }
  /// Replaces the assignment of a typed setter (which must come first) by `assign`.
  Row& assign(std::function<void(StudyConfig&, const SettingValue&)> assign) {
    m_s.assign = std::move(assign);
    return *this;
  }
  /// Adds a check to the assignment of a typed setter (which must come first): `check` runs before the value is
  /// stored and throws SettingError.
  Row& check(std::function<void(const SettingValue&)> check) {
    m_s.assign = [check = std::move(check), assign = m_s.assign](StudyConfig& c, const SettingValue& v) {
      check(v);
      assign(c, v);
    };
    return *this;
  }
  /// Refuses an empty (or blank) string: a name, a path or a command must say something.
  Row& non_empty() {
    check([](const SettingValue& v) {
      const std::string& text = std::get<std::string>(v);
      if (text.find_first_not_of(" \t\r\n") == std::string::npos)
        throw SettingError(text.empty() ? "must not be empty" : "must not be blank");
    });
    return range("non-empty");
  }
  /// Replaces the canonical lines of a typed setter (which must come first).
  Row& canonical(std::function<Lines(const StudyConfig&)> canonical) {
    m_s.canonical = std::move(canonical);
    m_value = nullptr;
    m_list = nullptr;
    return *this;
  }

  /// The finished row: the canonical lines of a typed setter use the final hash key (set after the setter).
  Setting finish() && {
    const std::string key = m_s.hash_key;
    if (m_value) m_s.canonical = [key, value = m_value](const StudyConfig& c) -> Lines { return {{key, value(c)}}; };
    if (m_list)
      m_s.canonical = [key, list = m_list](const StudyConfig& c) -> Lines {
        Lines lines;
        for (const std::string& v : list(c)) lines.emplace_back(key, v);
        return lines;
      };
    if (m_s.range_text.empty()) {
      if (m_s.type == SettingType::enumeration) {
        m_s.range_text = code_list(m_s.choices);
      } else {
        m_s.range_text = m_s.bounds.text();
      }
    }
    if (m_s.default_text.empty() && m_s.show) m_s.default_text = m_s.show(StudyConfig{});
    // The reason of a bound is documented where the bound is.
    if (!m_s.bounds.reason.empty()) m_s.doc += " (bounds: " + m_s.bounds.reason + ")";
    return std::move(m_s);
  }

 private:
  Row& scalar_canonical(std::function<std::string(const StudyConfig&)> value) {
    m_value = std::move(value);
    m_list = nullptr;
    return *this;
  }
  Row& list_canonical(std::function<std::vector<std::string>(const StudyConfig&)> values) {
    m_list = std::move(values);
    m_value = nullptr;
    return *this;
  }

 private:
  Setting m_s;
  std::function<std::string(const StudyConfig&)> m_value;
  std::function<std::vector<std::string>(const StudyConfig&)> m_list;
};

/// The canonical lines of a row that adds nothing to the design hash at its default value (so that studies made
/// before the row existed keep their hash) and `key=value` otherwise: for rows added to a section after its first
/// version. `field` is a FIELD-style accessor of a number or a boolean.
template <typename F>
std::function<Lines(const StudyConfig&)> unless_default(std::string key, F field) {
  return [key = std::move(key), field](const StudyConfig& c) -> Lines {
    static const StudyConfig defaults;
    if (field(c) == field(defaults)) return {};
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(field(c))>, bool>)
      return {{key, field(c) ? "1" : "0"}};
    else
      return {{key, canonical_number(field(c))}};
  };
}

/// A preset row: a string out of `names`, read before the other keys of its section; it sets other rows' values
/// (those are hashed), so it adds no line of its own.
template <typename F>
Row preset(const std::string& section, F field, std::vector<std::string> names,
           std::function<void(StudyConfig&, const std::string&)> apply) {
  Row row(section, "preset");
  row.string(field)
      .assign([names, apply](StudyConfig& c, const SettingValue& v) {
        const std::string& value = std::get<std::string>(v);
        if (std::find(names.begin(), names.end(), value) == names.end())
          throw SettingError(fmt::format("unknown preset '{}' (valid: {})", value, util::join(names)));
        apply(c, value);
      })
      .canonical([](const StudyConfig&) { return Lines{}; })
      .names(names)
      .first()
      .effect(SettingEffect::cases)
      .default_text("—");
  return row;
}

/// The four radius keys of a particle set (r_min, r_max, r_mean, r_sd) in `section`; `prefix` is the hash's
/// ("pile." or "oed."); `radii` is a FIELD-style accessor of the section's RadiusDistribution.
template <typename F>
void radius_rows(std::vector<Row>& rows, const std::string& section, const std::string& prefix, F radii) {
  rows.push_back(std::move(Row(section, "r_min")
                               .number(
                                   [radii](auto& c) -> auto& { return radii(c).r_min; }, radius_bounds())
                               .unit("m")
                               .cases(prefix + "r_min")
                               .doc("smallest radius r_L")));
  rows.push_back(std::move(Row(section, "r_max")
                               .number(
                                   [radii](auto& c) -> auto& { return radii(c).r_max; }, radius_bounds())
                               .unit("m")
                               .cases(prefix + "r_max")
                               .doc("largest radius r_U; more than `r_min`")));
  rows.push_back(std::move(Row(section, "r_mean")
                               .number(
                                   [radii](auto& c) -> auto& { return radii(c).mean; }, radius_bounds())
                               .unit("m")
                               .cases(prefix + "mean")
                               .doc("mean of the normal distribution before truncation, in [`r_min`, `r_max`]")));
  rows.push_back(
      std::move(Row(section, "r_sd")
                    .number(
                        [radii](auto& c) -> auto& { return radii(c).sd; }, between(0, false, k_max_radius, true))
                    .unit("m")
                    .cases(prefix + "sd")
                    .doc("standard deviation of the normal distribution before truncation; at least 1 % of that "
                         "distribution must lie in [`r_min`, `r_max`] (the radii are drawn by rejection)")));
}

/// The rules that tie a particle set's radius keys together (r_min < r_max, r_mean in [r_min, r_max], at least
/// k_min_radius_acceptance of the normal distribution inside [r_min, r_max]), checked when its section has been read.
void check_radii(const RadiusDistribution& radii, const SectionCheck& at);

/// The rows as settings (Row::finish), in order.
std::vector<Setting> finish_rows(std::vector<Row>& rows);

}  // namespace demsa::study
