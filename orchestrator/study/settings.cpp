#include "orchestrator/study/settings.hpp"

#include "orchestrator/study/parameters.hpp"
#include "orchestrator/util/log.hpp"
#include "sobol/design.hpp"
#include "sobol/enum_names.hpp"
#include "sobol/error.hpp"
#include "sobol/metamodel.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/scaling.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

namespace demsa::study {

namespace {

using Lines = std::vector<std::pair<std::string, std::string>>;

std::string join(const std::vector<std::string>& items, const std::string& separator = ", ") {
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : separator) + item;
  return out;
}

/// The names as markdown code, joined: "`a`, `b`".
std::string code_list(const std::vector<std::string>& names) {
  std::vector<std::string> quoted;
  for (const std::string& name : names) quoted.push_back(fmt::format("`{}`", name));
  return join(quoted);
}

/// The shortest text that reads back as the same double, in fixed or exponent notation (1e+08 rather than
/// 100000000, 2500 rather than 2.5e+03): for docs and messages.
std::string shortest(double v) {
  const std::string fixed = fmt::format("{}", v);
  for (int digits = 1; digits <= 17; ++digits) {
    const std::string g = fmt::format("{:.{}g}", v, digits);
    if (std::stod(g) == v) return g.size() < fixed.size() ? g : fixed;
  }
  return fixed;
}
/// The hash's number format since the first version: 17 significant digits.
std::string canonical_number(double v) { return fmt::format("{:.17g}", v); }

SettingBounds greater(double v, std::string reason = {}) { return {SettingBound{v, false}, std::nullopt, reason}; }
SettingBounds at_least(double v) { return {SettingBound{v, true}, std::nullopt, {}}; }
SettingBounds between(double low, bool low_in, double high, bool high_in, std::string reason = {}) {
  return {SettingBound{low, low_in}, SettingBound{high, high_in}, std::move(reason)};
}
const SettingBounds k_positive = greater(0);
const SettingBounds k_non_negative = at_least(0);

// Upper bounds of the settings that size what demsa holds in memory, each far above any DEM study and low enough
// that what it asks for exists: a typo of a few digits (or a 64-bit value) is refused at its line instead of ending
// in std::bad_alloc or being narrowed.
constexpr double k_max_samples = 100000;
constexpr double k_max_particles = 1e7;
constexpr double k_max_steps = 1e12;
constexpr double k_max_base_samples = 1 << 20;
constexpr double k_max_bootstrap = 100000;

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
      return fmt::format("[{}]", join(quoted));
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
      return fmt::format("[{}]", join(values));
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
      throw SettingError(fmt::format("unknown value '{}' (valid: {})", value, join(names)));
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

#define FIELD(path) \
  [](auto& c) -> auto& { return c.path; }

void apply_pile_preset(PileSettings& pile, const std::string& preset) {
  // Paper Table 2: particle sets 1 and 2.
  if (preset == "set1") {
    pile.particles = 6000;
    pile.radii = RadiusDistribution{1.0e-3, 3.5e-3, 2.0e-3, 0.5e-3};
  } else {
    pile.particles = 8000;
    pile.radii = RadiusDistribution{0.8e-3, 2.5e-3, 1.5e-3, 0.35e-3};
  }
  pile.preset = preset;
}

void apply_oedometer_preset(OedometerSettings& oedometer, const std::string& preset) {
  // Paper §4: assembly one has 4642 particles and the void ratio 0.66, with the pore volume computed on a
  // 10 x 10 x 5 cm^3 sample: V_P = 500 cm^3 - V_S. (The paper's formula reads e_1 = V_S / V_P, but a solid
  // fraction of 1/1.66 = 0.60 is a sphere packing under load and 0.40 is not, so e = V_P / V_S as usual.) The
  // paper gives no radii; these give that solid volume in expectation:
  //   V_S = 500 cm^3 / (1 + 0.66) = 301.2 cm^3, so E[r^3] = V_S / (4642 * 4/3 pi) = 15.49 mm^3.
  // Radii are N(mu, sd) truncated to [a, b] = [2.0, 3.0] mm with sd = 0.25 mm, i.e. density proportional to
  // phi((r - mu)/sd) on [a, b]; E[r^3] = int_a^b r^3 phi dr / int_a^b phi dr (trapezoid rule, 2e5 intervals).
  // mu = 2.466 mm gives E[r] = 2.4737 mm and E[r^3] = 15.496 mm^3: V_S = 301.30 cm^3 and e = 500 / 301.30 - 1 =
  // 0.6595 (mu = 2.47 mm would give 0.653). The former radii, 2.5 to 3.5 mm around 3 mm (E[r^3] = 27.4 mm^3),
  // put V_S = 533 cm^3 above the 500 cm^3 of the sample.
  oedometer.preset = preset;
  oedometer.particles = 4642;
  oedometer.radii = k_paper_oedometer_radii;
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
          throw SettingError(fmt::format("unknown preset '{}' (valid: {})", value, join(names)));
        apply(c, value);
      })
      .canonical([](const StudyConfig&) { return Lines{}; })
      .names(names)
      .first()
      .effect(SettingEffect::cases)
      .default_text("—");
  return row;
}

/// The four radius keys of a particle set; `prefix` is the hash's ("pile." or "oed.").
template <typename F>
void radius_rows(std::vector<Row>& rows, const std::string& section, const std::string& prefix, F radii) {
  rows.push_back(std::move(Row(section, "r_min")
                               .number(
                                   [radii](auto& c) -> auto& { return radii(c).r_min; }, k_positive)
                               .unit("m")
                               .cases(prefix + "r_min")
                               .doc("smallest radius r_L")));
  rows.push_back(std::move(Row(section, "r_max")
                               .number(
                                   [radii](auto& c) -> auto& { return radii(c).r_max; }, k_positive)
                               .unit("m")
                               .cases(prefix + "r_max")
                               .doc("largest radius r_U; more than `r_min`")));
  rows.push_back(std::move(Row(section, "r_mean")
                               .number(
                                   [radii](auto& c) -> auto& { return radii(c).mean; }, k_positive)
                               .unit("m")
                               .cases(prefix + "mean")
                               .doc("mean of the normal distribution before truncation, in [`r_min`, `r_max`]")));
  rows.push_back(std::move(Row(section, "r_sd")
                               .number(
                                   [radii](auto& c) -> auto& { return radii(c).sd; }, k_positive)
                               .unit("m")
                               .cases(prefix + "sd")
                               .doc("standard deviation of the normal distribution before truncation")));
}

const Setting& material_row(const std::vector<Setting>& rows, const std::string& key) {
  for (const Setting& s : rows)
    if (s.section == "material" && s.key == key) return s;
  assert(false && "no [material] row for a contact parameter");
  return rows.front();
}

std::vector<Setting> build_settings() {
  using E = SettingEffect;
  const SettingBounds k_steps = between(1, true, k_max_steps, true,
                                        "LIGGGHTS reads step counts through variables "
                                        "printed with 15 significant digits");
  std::vector<Row> rows;
  const auto add = [&](Row& row) { rows.push_back(std::move(row)); };

  // [study]
  add(Row("study", "name").string(FIELD(name)).non_empty().required().default_text("— (required)").doc("study name"));
  add(Row("study", "experiment")
          .choice(FIELD(experiment),
                  std::vector<std::pair<std::string, Experiment>>{{"pile", Experiment::pile},
                                                                  {"oedometer", Experiment::oedometer}})
          .required()
          .default_text("— (required)")
          .cases("experiment")
          .doc("`pile` (paper §3) or `oedometer` (paper §4)"));
  add(Row("study", "seed")
          .integer(FIELD(seed), at_least(0))
          .range(">= 0")
          .cases("seed")
          .doc("one seed for the design, the radii (GSL MT19937) and the initial positions"));

  // [design]: the names are sobol's (design_kind_from_string, which also accepts "lhs-centered"), every kind of which
  // a study can use; the study keeps the canonical name, so that both spellings give the same design hash.
  add(Row("design", "method")
          .string(FIELD(design))
          .assign([](StudyConfig& c, const SettingValue& v) {
            try {
              c.design = sobol::to_string(sobol::design_kind_from_string(std::get<std::string>(v)));
            } catch (const sobol::InputError& e) {
              throw SettingError(e.what());
            }
          })
          .names(sobol::design_kind_names())
          .cases("design")
          .doc("the design of experiments on the parameter ranges: Latin hypercubes (plain, centred, optimised for "
               "maximin distance or centred L2 discrepancy) or a scrambled Sobol' sequence"));
  add(Row("design", "samples")
          .integer(FIELD(samples),
                   between(2, true, k_max_samples, true,
                           "the analysis needs at least 2 samples, one case alone is `demsa case`; each sample is "
                           "a case folder"))
          .range(fmt::format("[2, {}]; at most {} for `lhs-maximin` and `lhs-cl2`", k_max_samples,
                             k_max_optimised_lhs_samples))
          .cases("samples")
          .doc("number of samples (the paper: 160 pile, 200 oedometer); the optimised Latin hypercubes keep an "
               "N × N matrix of the sample pairs. Raising it in an existing study extends the design (the finished "
               "cases are kept, docs/refine.md); lowering it is refused"));

  // DEM noise: replicate cases at the first P design points (cases/case_writer.hpp: CaseRequest::assembly_seed). The
  // replicates are case rows of their own (study/store.hpp), so a design that grows keeps them.
  add(Row("design", "replicates")
          .table(
              {"points", "repeats"},
              [](const StudyConfig& c) {
                if (!c.replicates.enabled()) return std::string("none");
                return fmt::format("{{ points = {}, repeats = {} }}", c.replicates.points, c.replicates.repeats);
              },
              [](const StudyConfig& c) {
                Lines lines;  // none when off: a study without replicates keeps its design hash
                if (c.replicates.enabled()) {
                  lines.emplace_back("replicates.points", std::to_string(c.replicates.points));
                  lines.emplace_back("replicates.repeats", std::to_string(c.replicates.repeats));
                }
                return lines;
              })
          .effect(E::cases)
          .default_text("none")
          .range("points in [1, samples], repeats in [2, 1000]")
          .doc("DEM noise: `{ points = P, repeats = R }` runs, at the first P design points, R cases each whose "
               "particle packing (radii and positions) is drawn with another assembly seed, everything else equal (a "
               "Rayleigh time step follows the packing's smallest radius, as in any case); "
               "the design point's own case is the first of the R, so the study runs P (R − 1) cases more. The "
               "analysis measures each observable's noise variance from them (pooled within-point variance), sets "
               "the GP nugget from it and reports the noise share; the replicates do not enter the metamodels' "
               "training. Raising P or R in an existing study adds the missing replicate cases (those run are "
               "kept); lowering either, or removing the setting, is refused"));

  // [parameters]: one table row per contact parameter; the admissible values are those of its [material] row.
  for (const ContactParameter& p : contact_parameters()) {
    const std::string key(p.key);
    Row row("parameters", key);
    row.table(
           {"low", "high", "scale"},
           [key](const StudyConfig& c) {
             for (const ParameterRange& r : c.parameters)
               if (r.name == key)
                 return fmt::format("{{ low = {}, high = {}, scale = \"{}\" }}", shortest(r.bounds.low),
                                    shortest(r.bounds.high), sobol::to_string(r.bounds.scale));
             return std::string("not varied");
           },
           [key](const StudyConfig& c) {
             Lines lines;
             for (const ParameterRange& r : c.parameters) {
               if (r.name != key) continue;
               lines.emplace_back("p." + key + ".low", canonical_number(r.bounds.low));
               lines.emplace_back("p." + key + ".high", canonical_number(r.bounds.high));
               lines.emplace_back("p." + key + ".scale", sobol::to_string(r.bounds.scale));
             }
             return lines;
           })
        .effect(E::cases)
        .unit(p.unit == "-" ? "" : std::string(p.unit))
        .default_text("not varied")
        .doc(fmt::format("range of {} ({}): `{{ low, high, scale }}`", p.label, p.symbol));
    add(row);
  }

  // [material]
  add(Row("material", "E")
          .number(FIELD(material.E), k_positive)
          .unit("Pa")
          .cases("m.E")
          .doc("Young's modulus; LIGGGHTS accepts [5e6, 1e9] Pa only (see `soft_particles`, `hard_particles`)"));
  add(Row("material", "nu")
          .number(FIELD(material.nu), between(0, false, 0.5, false))
          .cases("m.nu")
          .doc("Poisson ratio"));
  add(Row("material", "mu_pp")
          .number(FIELD(material.mu_pp), k_non_negative)
          .cases("m.mu_pp")
          .doc("particle–particle Coulomb friction"));
  add(Row("material", "mu_pw")
          .number(FIELD(material.mu_pw), k_non_negative)
          .cases("m.mu_pw")
          .doc("particle–wall Coulomb friction"));
  add(Row("material", "e_r")
          .number(FIELD(material.e_r), between(0, false, 1, true))
          .cases("m.e_r")
          .doc("coefficient of restitution"));
  add(Row("material", "mu_r_pp")
          .number(FIELD(material.mu_r_pp), k_non_negative)
          .cases("m.mu_r_pp")
          .doc("particle–particle rolling coefficient of `[contact] rolling_model` (μ_r of `cdt`, dimensionless; μ_R "
               "of `viscous` in `viscous_unit`)"));
  add(Row("material", "mu_r_pw")
          .number(FIELD(material.mu_r_pw), k_non_negative)
          .cases("m.mu_r_pw")
          .doc("particle–wall rolling coefficient of `[contact] rolling_model`"));
  add(Row("material", "density")
          .number(FIELD(material.density), k_positive)
          .unit("kg/m³")
          .cases("m.density")
          .doc("particle density (not in the paper)"));
  add(Row("material", "gravity")
          .number(FIELD(material.gravity), k_positive)
          .unit("m/s²")
          .cases("m.gravity")
          .doc("\\|g\\|"));
  add(Row("material", "soft_particles")
          .boolean(FIELD(material.soft_particles))
          .cases("m.soft")
          .doc("allow E < 5e6 Pa (LIGGGHTS `soft_particles yes`)"));
  add(Row("material", "hard_particles")
          .boolean(FIELD(material.hard_particles))
          .cases("m.hard")
          .doc("allow E > 1e9 Pa (LIGGGHTS `hard_particles yes`)"));

  // [pile]
  add(preset("pile", FIELD(pile.preset), {"set1", "set2"},
             [](StudyConfig& c, const std::string& name) { apply_pile_preset(c.pile, name); })
          .doc("`set1` (6000 particles, radii [1, 3.5] mm, mean 2, sd 0.5) or `set2` (8000, [0.8, 2.5] mm, 1.5, "
               "0.35): paper Table 2. Other keys override it"));
  add(Row("pile", "particles")
          .integer(FIELD(pile.particles),
                   between(1, true, k_max_particles, true,
                           "the case writer holds every particle, and the text of its data file, in memory"))
          .cases("pile.particles")
          .doc("number of particles"));
  radius_rows(
      rows, "pile", "pile.", [](auto& c) -> auto& { return c.pile.radii; });
  add(Row("pile", "disc_radius")
          .number(FIELD(pile.disc_radius), k_positive)
          .unit("m")
          .cases("pile.disc_radius")
          .doc("r_fu, radius of the filling discs; at least `r_max`"));
  add(Row("pile", "fill_height")
          .number(FIELD(pile.fill_height), k_positive)
          .unit("m")
          .cases("pile.fill_height")
          .doc("h_fu above the pedestal top: discs below are present at start, later ones are appended there; a case "
               "whose pile grows into the layer of a new disc (a particle centre above h_fu − r_U) stops with an "
               "error naming this key"));
  add(Row("pile", "pedestal_radius")
          .number(FIELD(pile.pedestal_radius), k_positive)
          .unit("m")
          .cases("pile.pedestal_radius")
          .doc("r_cy"));
  add(Row("pile", "pedestal_height")
          .number(FIELD(pile.pedestal_height), k_positive)
          .unit("m")
          .cases("pile.pedestal_height")
          .doc("h_cy (the pedestal top)"));
  add(Row("pile", "settle_time")
          .number(FIELD(pile.settle_time), k_non_negative)
          .unit("s")
          .cases("pile.settle_time")
          .doc("settling after the last disc: the cap; a pile still moving then is recorded as unsettled and flagged "
               "by `demsa status` and the report"));
  // The settling rows replaced `ke_stop` (0: settle for settle_time). At their defaults they give the hash text of
  // that version (`pile.ke_stop=0`, nothing more), so its studies keep their hash and their fixed settling time.
  const auto unless_default = [](std::string key, auto field) {
    return [key = std::move(key), field](const StudyConfig& c) -> Lines {
      static const StudyConfig defaults;
      if (field(c) == field(defaults)) return {};
      if constexpr (std::is_same_v<std::remove_cvref_t<decltype(field(c))>, bool>)
        return {{key, field(c) ? "1" : "0"}};
      else
        return {{key, canonical_number(field(c))}};
    };
  };
  add(Row("pile", "settle_speed")
          .number(FIELD(pile.settle_speed), k_non_negative)
          .cases("pile.settle_speed")
          .canonical([](const StudyConfig& c) -> Lines {
            if (c.pile.settle_speed == 0) return {{"pile.ke_stop", canonical_number(0)}};
            return {{"pile.settle_speed", canonical_number(c.pile.settle_speed)}};
          })
          .doc("the pile is settled once the particles on the pedestal (centre above its top, within its radius) "
               "move slower than `settle_speed` × √(\\|g\\| r_min) (the share `settle_quantile` of them at "
               "least) at every check for `settle_window`; 0 = settle for `settle_time` (the paper's schedule)"));
  add(Row("pile", "settle_quantile")
          .number(FIELD(pile.settle_quantile), between(0, false, 1, true))
          .cases("pile.settle_quantile")
          .canonical(unless_default("pile.settle_quantile", FIELD(pile.settle_quantile)))
          .doc("share of the particles on the pedestal that must be slow; 1 = every one (the fastest is judged)"));
  add(Row("pile", "settle_window")
          .number(FIELD(pile.settle_window), k_positive)
          .unit("s")
          .cases("pile.settle_window")
          .canonical(unless_default("pile.settle_window", FIELD(pile.settle_window)))
          .doc("how long the settling criterion must hold"));
  add(Row("pile", "settle_check_time")
          .number(FIELD(pile.settle_check_time), k_positive)
          .unit("s")
          .cases("pile.settle_check_time")
          .doc("how often the settling criterion is checked and fallen particles removed (also after every disc)"));
  add(Row("pile", "remove_fallen")
          .boolean(FIELD(pile.remove_fallen))
          .cases("pile.remove_fallen")
          .canonical(unless_default("pile.remove_fallen", FIELD(pile.remove_fallen)))
          .doc("delete particles whose centre is below the pedestal top and outside its radius (§3.2's filter "
               "applied during the run); they are counted as removed, not lost"));
  add(Row("pile", "domain_half_width")
          .number(FIELD(pile.domain_half_width), k_positive)
          .unit("m")
          .cases("pile.domain_half_width")
          .doc("simulation box half width; particles leaving it are lost. Must exceed `disc_radius` + `r_max` and "
               "`pedestal_radius`"));
  add(Row("pile", "target_angle")
          .number(FIELD(pile.target_angle), between(0, false, 90, false))
          .unit("deg")
          .doc("φ̂ of E_φ = (φ̂ − φ)²: the calibration target of `demsa calibrate` and the report (not stored with "
               "the cases)"));
  add(Row("pile", "directions")
          .integer(FIELD(pile.directions), between(1, true, 100000, true))
          .measurement("pile.directions")
          .doc("φ_N of §3.3: the angle of a finished pile is measured in this many directions"));
  add(Row("pile", "levels")
          .integer(FIELD(pile.levels), between(2, true, 100000, true))
          .measurement("pile.levels")
          .doc("height levels at which the angle is measured: between 0.2 h_P and 0.75 h_P (paper), 0.25 h_P and "
               "0.8 h_P (robust)"));
  add(Row("pile", "angle_estimator")
          .choice(FIELD(pile.angle_estimator),
                  std::vector<std::pair<std::string, std::string>>{{"paper", "paper"}, {"robust", "robust"}})
          .measurement("pile.angle_estimator")
          .doc("`paper`: §3.3 (outermost particle per direction and level, orthogonal line, mean over directions), "
               "which reads up to 1° low on rough flanks; `robust`: surface points at the exact level heights and a "
               "Theil–Sen line per direction, within 0.5° on synthetic cones with 1–2 mm of surface roughness "
               "(docs/benchmarks.md, angle estimators)"));

  // [oedometer]
  add(preset("oedometer", FIELD(oedometer.preset), {"paper"},
             [](StudyConfig& c, const std::string& name) { apply_oedometer_preset(c.oedometer, name); })
          .doc("`paper`: assembly one of §4: 4642 particles, radii [2.0, 3.0] mm, mean 2.466, sd 0.25, whose "
               "expected solid volume V_S = 301 cm³ gives the paper's void ratio e = V_P/V_S = 0.66 on a 10 × 10 × "
               "5 cm³ sample (the paper gives no radii). Other keys override it"));
  add(Row("oedometer", "particles")
          .integer(FIELD(oedometer.particles),
                   between(1, true, k_max_particles, true,
                           "the case writer holds every particle, and the text of its data file, in memory"))
          .cases("oed.particles")
          .doc("number of particles"));
  radius_rows(
      rows, "oedometer", "oed.", [](auto& c) -> auto& { return c.oedometer.radii; });
  add(Row("oedometer", "box_side")
          .number(FIELD(oedometer.box_side), k_positive)
          .unit("m")
          .cases("oed.box_side")
          .doc("side of the square box; more than 2 `r_max`"));
  add(Row("oedometer", "box_height")
          .number(FIELD(oedometer.box_height), k_positive)
          .unit("m")
          .cases("oed.box_height")
          .doc("box height; a case whose settled packing top plus `plate_gap` lies above it stops after the fill "
               "with an error naming this key (both plate modes)"));
  add(Row("oedometer", "fill_time")
          .number(FIELD(oedometer.fill_time), k_positive)
          .unit("s")
          .cases("oed.fill_time")
          .doc("pouring and settling before loading"));
  add(Row("oedometer", "loads")
          .numbers(FIELD(oedometer.loads))
          .check([](const SettingValue& v) {
            const auto& loads = std::get<std::vector<double>>(v);
            if (loads.empty()) throw SettingError("needs at least one load");
            for (std::size_t i = 0; i < loads.size(); ++i) {
              if (!(loads[i] > 0))
                throw SettingError(fmt::format("load {} is {} N; loads must be > 0", i + 1, loads[i]));
              if (i > 0 && !(loads[i] > loads[i - 1]))
                throw SettingError(fmt::format("loads must increase: {} N follows {} N", loads[i], loads[i - 1]));
            }
          })
          .range("at least one, > 0, increasing")
          .unit("N")
          .cases("oed.load")
          .doc("the loads L_n"));
  add(Row("oedometer", "measured_settlements")
          .numbers(FIELD(oedometer.measured_settlements))
          .range("none, or one per load after the first")
          .unit("m")
          .measurement("oed.measured_settlement")
          .doc("s̃_i for loads 2..n relative to load 1: a finished case stores its error E_0 against them"));
  add(Row("oedometer", "plate_mode")
          .choice(FIELD(oedometer.plate_mode),
                  std::vector<std::pair<std::string, PlateMode>>{{"servo", PlateMode::servo},
                                                                 {"trial-step", PlateMode::trial_step}})
          .cases("oed.mode")
          .doc("`servo` (`fix mesh/surface/stress/servo`) or `trial-step` (the paper's algorithm)"));
  add(Row("oedometer", "plate_gap")
          .number(FIELD(oedometer.plate_gap), k_non_negative)
          .unit("m")
          .cases("oed.plate_gap")
          .doc("the plate starts this far above the settled packing"));
  add(Row("oedometer", "load_tolerance")
          .number(FIELD(oedometer.load_tolerance), k_positive)
          .unit("N")
          .cases("oed.tol")
          .doc("\\|F − L\\| that counts as reached (paper R_pr)"));
  add(Row("oedometer", "servo_vel_max")
          .number(FIELD(oedometer.servo_vel_max), k_positive)
          .unit("m/s")
          .cases("oed.vmax")
          .doc("servo speed limit; must be below skin/(2 dt)"));
  add(Row("oedometer", "servo_kp")
          .number(FIELD(oedometer.servo_kp), k_non_negative)
          .cases("oed.kp")
          .doc("servo proportional gain"));
  add(Row("oedometer", "servo_ki")
          .number(FIELD(oedometer.servo_ki), k_non_negative)
          .cases("oed.ki")
          .doc("servo integral gain"));
  add(Row("oedometer", "servo_kd")
          .number(FIELD(oedometer.servo_kd), k_non_negative)
          .cases("oed.kd")
          .doc("servo derivative gain"));
  add(Row("oedometer", "servo_max_steps")
          .integer(FIELD(oedometer.servo_max_steps), k_steps)
          .unit("steps")
          .cases("oed.smax")
          .doc("servo: a load not reached by then is recorded as not converged"));
  add(Row("oedometer", "servo_check_steps")
          .integer(FIELD(oedometer.servo_check_steps), k_steps)
          .unit("steps")
          .cases("oed.scheck")
          .doc("servo: force averaged and the load checked every this many steps (rounded up to a multiple of 10)"));
  add(Row("oedometer", "rest_velocity")
          .number(FIELD(oedometer.rest_velocity), k_positive)
          .unit("m/s")
          .cases("oed.vrest")
          .doc("servo: the plate is at rest when its mean speed over a check is below this"));
  add(Row("oedometer", "trial_steps")
          .integer(FIELD(oedometer.trial_steps), k_steps)
          .unit("steps")
          .cases("oed.ns")
          .doc("trial-step: n_s"));
  add(Row("oedometer", "relax_steps")
          .integer(FIELD(oedometer.relax_steps), k_steps)
          .unit("steps")
          .cases("oed.nl")
          .doc("trial-step: n_L"));
  add(Row("oedometer", "trial_reduction")
          .number(FIELD(oedometer.trial_reduction), between(0, false, 1, false))
          .cases("oed.mt")
          .doc("trial-step: m_T"));
  add(Row("oedometer", "trial_step0")
          .number(FIELD(oedometer.trial_step0), k_positive)
          .unit("m")
          .cases("oed.d0")
          .doc("trial-step: δ_T0 (the paper's 0.0075 mm)"));
  add(Row("oedometer", "trial_floor")
          .number(FIELD(oedometer.trial_floor), between(0, false, 1, true))
          .cases("oed.floor")
          .doc("trial-step: smallest trial step as a fraction of δ_T0"));
  add(Row("oedometer", "max_trials")
          .integer(FIELD(oedometer.max_trials), between(1, true, 1e6, true))
          .cases("oed.maxtrials")
          .doc("trial-step: trials per load before it is recorded as not converged"));

  // [timestep]
  add(Row("timestep", "mode")
          .choice(FIELD(timestep.mode),
                  std::vector<std::pair<std::string, TimestepMode>>{{"rayleigh", TimestepMode::rayleigh},
                                                                    {"fixed", TimestepMode::fixed}})
          .cases("dt.mode")
          .doc("`rayleigh`: dt = `fraction` × T_R of the smallest particle of the sample; `fixed`: dt = `value`"));
  add(Row("timestep", "fraction")
          .number(FIELD(timestep.fraction),
                  between(0, false, 0.3, true, "a time step above 0.3 Rayleigh times is unstable for Hertz contacts"))
          .cases("dt.fraction")
          .doc("dt as a fraction of the Rayleigh time T_R"));
  add(Row("timestep", "value")
          .number(FIELD(timestep.value), k_positive)
          .unit("s")
          .default_text("— (required with `mode = \"fixed\"`)")
          .cases("dt.value")
          .doc("fixed time step"));
  add(Row("timestep", "skin")
          .number(FIELD(timestep.skin), k_positive)
          .unit("m")
          .cases("dt.skin")
          .doc("neighbor list skin; a moving mesh may travel at most skin/2 per step"));

  // [run]
  add(Row("run", "executor")
          .choice(FIELD(run.executor),
                  std::vector<std::pair<std::string, ExecutorKind>>{{"local", ExecutorKind::local},
                                                                    {"slurm", ExecutorKind::slurm}})
          .doc("where cases run: this machine or a SLURM cluster"));
  add(Row("run", "ranks")
          .integer(FIELD(run.ranks), between(1, true, 1e6, true))
          .cases("ranks")
          .doc("MPI ranks per case; results depend on it, so every case of a study uses the same count"));
  add(Row("run", "parallel")
          .integer(FIELD(run.parallel), between(0, true, 1e6, true))
          .doc("cases at once (local); 0 = cores / ranks"));
  add(Row("run", "oversubscribe").boolean(FIELD(run.oversubscribe)).doc("allow parallel × ranks > cores"));
  add(Row("run", "timeout").number(FIELD(run.timeout), k_non_negative).unit("s").doc("per case; 0 = none"));
  add(Row("run", "retries")
          .integer(FIELD(run.retries), between(0, true, 1000, true))
          .doc("extra attempts after a failure"));
  add(Row("run", "lost_fraction")
          .number(FIELD(run.lost_fraction), between(0, true, 1, true))
          .doc("a case that loses more than this fraction of its particles fails"));
  add(Row("run", "liggghts").string(FIELD(run.liggghts)).non_empty().doc("LIGGGHTS executable (name on PATH or path)"));
  add(Row("run", "mpirun").string(FIELD(run.mpirun)).non_empty().doc("MPI launcher"));

  // [run.slurm]
  add(Row("run.slurm", "mode")
          .choice(FIELD(run.slurm.mode), std::vector<std::pair<std::string, SlurmMode>>{{"array", SlurmMode::array},
                                                                                        {"pack", SlurmMode::pack}})
          .doc("`array`: one job array per batch of cases; `pack`: one allocation of `throttle` cases × `ranks` "
               "CPUs that runs the cases as `srun --exclusive` job steps (for clusters that cap jobs per user)"));
  add(Row("run.slurm", "partition")
          .string(FIELD(run.slurm.partition))
          .doc("sbatch `--partition` (empty: the cluster's default)"));
  add(Row("run.slurm", "account")
          .string(FIELD(run.slurm.account))
          .doc("sbatch `--account` (empty: the cluster's default)"));
  add(Row("run.slurm", "time_limit").string(FIELD(run.slurm.time_limit)).doc("sbatch `--time` per case"));
  add(Row("run.slurm", "throttle")
          .integer(FIELD(run.slurm.throttle), between(0, true, 1e6, true))
          .doc("`%N` array throttle, 0 = none"));
  add(Row("run.slurm", "sbatch_options")
          .strings(FIELD(run.slurm.sbatch_options))
          .doc("extra sbatch options, verbatim"));
  add(Row("run.slurm", "prologue")
          .string(FIELD(run.slurm.prologue))
          .doc("shell lines before mpirun (e.g. `module load ...`)"));
  add(Row("run.slurm", "poll_interval")
          .number(FIELD(run.slurm.poll_interval), k_positive)
          .unit("s")
          .doc("time between squeue polls"));

  // [analysis]
  add(Row("analysis", "metamodels")
          .strings(FIELD(analysis.metamodels))
          .check([](const SettingValue& v) {
            // The metamodels sobol/ builds: one list, so the study file accepts exactly what the analysis can fit.
            const std::vector<std::string> models = sobol::metamodel_names();
            for (const std::string& m : std::get<std::vector<std::string>>(v))
              if (std::find(models.begin(), models.end(), m) == models.end())
                throw SettingError(fmt::format("unknown metamodel '{}' (valid: {})", m, join(models)));
          })
          .range(fmt::format("any of {}", code_list(sobol::metamodel_names())))
          .doc("metamodels to fit: `rsm1`–`rsm3` are polynomials of total degree 1–3"));
  add(Row("analysis", "second_order").boolean(FIELD(analysis.second_order)).doc("also S2"));
  add(Row("analysis", "bootstrap")
          .integer(FIELD(analysis.bootstrap), between(0, true, k_max_bootstrap, true,
                                                      "each resample refits every metamodel and computes its indices"))
          .doc("bootstrap resamples for confidence intervals (for the `gp` metamodel with `interval = "
               "\"gp-posterior\"`: posterior draws)"));
  add(Row("analysis", "interval")
          .choice(FIELD(analysis.interval),
                  std::vector<sobol::MetamodelInterval>{sobol::MetamodelInterval::gp_posterior,
                                                        sobol::MetamodelInterval::design_bootstrap},
                  sobol::metamodel_interval_from_string, [](sobol::MetamodelInterval i) { return sobol::to_string(i); })
          .doc("interval of metamodel indices: `design-bootstrap` refits every metamodel on resampled samples; "
               "`gp-posterior` takes the `gp` metamodel's from draws of its posterior (Le Gratiet et al. 2014; it "
               "narrows where points are added, but at the fitted hyperparameters it covered the true indices less "
               "often than its level, docs/benchmarks.md; the other metamodels keep the design bootstrap)"));
  add(Row("analysis", "confidence")
          .number(FIELD(analysis.confidence), between(0, false, 1, false))
          .doc("confidence level"));
  add(Row("analysis", "base_samples")
          .integer(FIELD(analysis.base_samples),
                   between(16, true, k_max_base_samples, true,
                           "the indices' QMC design holds N (2d + 2) points in memory, about 1 GB at 2^20 for 7 "
                           "parameters"))
          .assign([](StudyConfig& c, const SettingValue& v) {
            // Sobol' points are balanced in blocks of 2^m (Owen 2020, "On dropping the first Sobol' point"; Saltelli
            // et al. 2010 use N = 2^m): another N loses accuracy, so the analysis uses the next power of two.
            const long given = std::get<long>(v);
            long used = 1;
            while (used < given) used *= 2;
            if (used != given)
              util::log::warn("[analysis] base_samples = {} is not a power of two; the analysis uses {}", given, used);
            c.analysis.base_samples = static_cast<int>(used);
          })
          .doc("QMC base N for metamodel-based indices; rounded up to a power of two (Sobol' points are balanced in "
               "blocks of 2^m)"));
  add(Row("analysis", "gp_kernel")
          .choice(FIELD(analysis.gp_kernel),
                  std::vector<sobol::GpKernel>{sobol::GpKernel::squared_exponential, sobol::GpKernel::matern52},
                  sobol::gp_kernel_from_string, [](sobol::GpKernel k) { return sobol::to_string(k); })
          .doc("correlation of the `gp` metamodel"));
  add(Row("analysis", "gp_trend")
          .choice(FIELD(analysis.gp_trend),
                  std::vector<sobol::GpTrend>{sobol::GpTrend::constant, sobol::GpTrend::linear},
                  sobol::gp_trend_from_string, [](sobol::GpTrend t) { return sobol::to_string(t); })
          .doc("trend of the `gp` metamodel: `linear` is universal Kriging"));
  add(Row("analysis", "gp_nugget")
          .boolean(FIELD(analysis.gp_nugget))
          .doc("estimate a nugget: the GP smooths the noise of DEM responses instead of interpolating it"));

  // [contact]: the rolling model; at their defaults (`cdt`) the rows add nothing to the hash, so the studies made
  // before the section existed keep their hash.
  add(Row("contact", "rolling_model")
          .choice(FIELD(contact.rolling_model),
                  std::vector<std::pair<std::string, RollingModel>>{{"cdt", RollingModel::cdt},
                                                                    {"epsd", RollingModel::epsd},
                                                                    {"epsd2", RollingModel::epsd2},
                                                                    {"epsd3", RollingModel::epsd3},
                                                                    {"viscous", RollingModel::viscous}})
          .cases("contact.rolling_model")
          .canonical([](const StudyConfig& c) -> Lines {
            if (c.contact.rolling_model == RollingModel::cdt) return {};
            return {{"contact.rolling_model", std::string(rolling_model_name(c.contact.rolling_model))}};
          })
          .doc("rolling resistance of every pair and wall contact (LIGGGHTS `rolling_friction`); `viscous` is the "
               "paper's model B and needs the LIGGGHTS of `scripts/build-liggghts.sh`; `mu_r_pp`/`mu_r_pw` are "
               "its coefficients (see below)"));
  add(Row("contact", "rolling_damping")
          .number(FIELD(contact.rolling_damping), between(0, true, 1, true))
          .cases("contact.rolling_damping")
          .canonical(unless_default("contact.rolling_damping", FIELD(contact.rolling_damping)))
          .doc("`epsd`, `epsd3`: viscous damping ratio η_r of the rolling dashpot "
               "(`coefficientRollingViscousDamping`, dimensionless; Ai et al. 2011 use 0.3)"));
  add(Row("contact", "rolling_stiffness")
          .number(FIELD(contact.rolling_stiffness), at_least(1))
          .cases("contact.rolling_stiffness")
          .canonical(unless_default("contact.rolling_stiffness", FIELD(contact.rolling_stiffness)))
          .doc("`epsd3`: prefactor of the rolling stiffness k_r = factor × k_n μ_r² R*² (`rollingStiffness`, "
               "dimensionless, >= 1 in SI; `epsd` fixes it at 2.25, Ai et al. 2011)"));
  add(Row("contact", "viscous_unit")
          .choice(FIELD(contact.viscous_unit),
                  std::vector<std::pair<std::string, ViscousUnit>>{{"s*m", ViscousUnit::s_m},
                                                                   {"mm*ms", ViscousUnit::mm_ms}})
          .cases("contact.viscous_unit")
          .canonical([](const StudyConfig& c) -> Lines {
            if (c.contact.viscous_unit == ViscousUnit::s_m) return {};
            return {{"contact.viscous_unit", "mm*ms"}};
          })
          .doc("`viscous`: the unit of `mu_r_pp`, `mu_r_pw` and their `[parameters]` ranges: SI `s*m`, or the "
               "paper's `mm*ms` (Table 3; 1 mm·ms = 1e-6 s·m, converted when the case is written)"));

  std::vector<Setting> settings;
  for (Row& row : rows) settings.push_back(std::move(row).finish());
  // The parameter ranges obey the rules of their [material] values.
  for (Setting& s : settings) {
    if (s.section != "parameters") continue;
    const Setting& m = material_row(settings, s.key);
    s.bounds = m.bounds;
    s.range_text = fmt::format("`low` < `high`, both {}{}; `scale` is `uniform` (default) or `log` (`low` > 0)",
                               m.bounds.low && m.bounds.high ? "in " : "", m.range_text);
  }
  return settings;
}

#undef FIELD

std::string fnv1a_64(const std::string& text) {
  std::uint64_t h = 1469598103934665603ULL;
  for (const unsigned char ch : text) {
    h ^= ch;
    h *= 1099511628211ULL;
  }
  return fmt::format("{:016x}", h);
}

bool applies_to(const Setting& s, Experiment experiment) {
  if (s.section == "pile") return experiment == Experiment::pile;
  if (s.section == "oedometer") return experiment == Experiment::oedometer;
  return true;
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

/// [contact]: one paragraph per rolling model (docs/study-file.md).
const char* const k_contact_intro =
    "Every pair and wall contact is Hertz normal (`model hertz`, damping from `e_r`) with Mindlin tangential "
    "(`tangential history`, capped by Coulomb friction) and one rolling model, written into `pair_style gran` "
    "and every `fix wall/gran` of both experiments. The coefficients `mu_r_pp` and `mu_r_pw` (`[material]` and "
    "`[parameters]`) are the chosen model's rolling coefficient; its meaning and unit depend on the model.";
const char* const k_contact_notes =
    "- `cdt` (default; LIGGGHTS `src/rolling_model_cdt.h`, doc `gran_rolling_friction_cdt`; Ai et al. 2011 "
    "model A): a constant torque μ_r k_n δ_n R* against the tangential relative rotation. `mu_r_*` is the "
    "dimensionless coefficientRollingFriction μ_r (a lever arm of μ_r R*). Stock LIGGGHTS.\n"
    "- `epsd` (`src/rolling_model_epsd.h`; Ai et al. 2011 model C, elastic-plastic spring-dashpot): a rolling "
    "spring k_r = 2.25 k_n μ_r² R*² capped at μ_r \\|F_n\\| R*, plus a dashpot of damping ratio `rolling_damping` "
    "(coefficientRollingViscousDamping η_r, dimensionless) while the spring is not at its cap. `mu_r_*`: μ_r, "
    "dimensionless. Stock LIGGGHTS.\n"
    "- `epsd2` (`src/rolling_model_epsd2.h`; Iwashita and Oda 1998): the spring of `epsd` with k_r = k_t R*² "
    "(k_t the tangential stiffness), capped at μ_r \\|F_n\\| R*, no dashpot. `mu_r_*`: μ_r, dimensionless. Stock "
    "LIGGGHTS.\n"
    "- `epsd3` (`src/rolling_model_epsd3.h`): `epsd` with k_r = `rolling_stiffness` × k_n μ_r² R*² "
    "(rollingStiffness, dimensionless, >= 1 in SI) and the dashpot ratio `rolling_damping`. `mu_r_*`: μ_r, "
    "dimensionless. Stock LIGGGHTS.\n"
    "- `viscous` (the paper's eq. 8: Ai et al. 2011 model B; `liggghts/rolling_model_viscous.h` of this "
    "repository, doc `liggghts/rolling_model_viscous.md`): the torque μ_R \\|F_n\\| ω_t against the tangential "
    "relative angular velocity ω_t, so that `mu_r_*` is μ_R with units of length × time "
    "(coefficientRollingViscosity in s·m). Give it in SI (`viscous_unit = \"s*m\"`) or in the paper's mm·ms "
    "(`viscous_unit = \"mm*ms\"`: Table 3's μ_R,PP ∈ [0.45, 4.5] and μ_R,PW ∈ [0.8, 5] mm·ms are [0.45e-6, "
    "4.5e-6] and [0.8e-6, 5e-6] s·m; 1 mm·ms = 1e-6 s·m); the case writer converts to s·m. Explicitly "
    "integrated the torque is stiff (unstable once μ_R \\|F_n\\| dt / I* > 2); each contact therefore applies "
    "over one step the exact exponential decay of ω_t that its torque causes, its one-step fraction capped at "
    "1/8 (the header's comment gives the derivation), which equals model B whenever the rolling relaxes over "
    "more than about 8 steps. A purely viscous torque gives no static rolling resistance (ω = 0, no torque). Not "
    "in stock LIGGGHTS: build it with `scripts/build-liggghts.sh` (README); demsa refuses a `viscous` study "
    "before any case runs when the LIGGGHTS it found lacks the model.";

const std::vector<SettingSection>& setting_sections() {
  static const std::vector<SettingSection> sections{
      {"study", "", ""},
      {"design", "", ""},
      {"parameters",
       "Keys are the paper's tuple P (eq. 1). Each is a table `{ low, high, scale }`. The ranges must be physical, "
       "by the rules of the `[material]` values. An `E` range (or a fixed `[material]` `E`) that reaches above 1e9 "
       "Pa needs `[material] hard_particles = true`, and one below 5e6 Pa needs `soft_particles = true`: LIGGGHTS "
       "refuses such moduli in SI units otherwise, so the study file is refused when it is read. Parameters not "
       "listed take their `[material]` value. Whatever the order in the file, the parameters are kept in the "
       "paper's order; at least one is required.",
       ""},
      {"material", "",
       "The rolling coefficients `mu_r_pp` and `mu_r_pw` are those of `[contact] rolling_model`: dimensionless "
       "for `cdt` (the default), `epsd`, `epsd2` and `epsd3`, length × time for the paper's `viscous` model B "
       "(in the unit of `[contact] viscous_unit`)."},
      {"contact", k_contact_intro, k_contact_notes},
      {"pile", "Defaults: particle set 1 of the paper's Table 2.",
       "Discs: ring k of a disc has radius 2 r_U k; disc k of the column is at pedestal top + r_U + 2 r_U k; one "
       "more disc is appended every sqrt(4 r_U/\\|g\\|).\n\n"
       "Settling and removal (both off by default: the paper's schedule; the quickstart and the paper presets turn "
       "them on): every `settle_check_time` (and after every disc) the particles whose centre lies below "
       "the pedestal top and outside its radius are deleted (`remove_fallen`; §3.2's filter, applied during the run: "
       "they cannot come back) and counted; they are stored as `removed_off_pedestal` and are not lost atoms. The "
       "pile is settled once no more than the share 1 − `settle_quantile` of the particles on the pedestal move "
       "faster than `settle_speed` √(\\|g\\| r_min) at every check for `settle_window`; a pile that reaches "
       "`settle_time` still moving is measured, stored with `settled` = 0 and flagged by `demsa status` and the "
       "report. One-at-a-time runs (set 1, E = 1e8 Pa, ν = 0.3, μ_PP = 1.3, μ_PW = 1.15, e_r = 0.4, baseline "
       "μ_R,PP = μ_R,PW = 0.275, `cdt`; the quickstart's settling and removal; one LIGGGHTS run each; angle by "
       "§3.3):\n\n"
       "| pedestal radius, particles | baseline angle (h_P) | doubled particles | μ_R,PP 0.05 → 0.5 | μ_R,PW 0.05 → "
       "0.5 |\n"
       "|---|---|---|---|---|\n"
       "| 25 mm, 300 | 22.5° (15 mm)¹ | 25.4° (15 mm)¹ | 18.3° → 23.1° | 12.7° → 26.3° |\n"
       "| 35 mm, 700 (the quickstart before 2400 on 50 mm) | 23.8° (19 mm) | 23.1° (18 mm) | 21.7° (unsettled) → 27.9° "
       "| 20.2° → 26.5° |\n"
       "| 40 mm, 1000 | 25.9° (21 mm) | 27.2° (24 mm) | not run | 20.0° → 26.4° |\n\n"
       "At these sizes particle-wall rolling friction moves the angle as much as particle-particle rolling friction. ¹ "
       "with `settle_quantile` = 1.\n\n"
       "How the pile is poured decides the ranking more than its size. One-at-a-time runs of 2400 particles on the "
       "paper's 50 mm pedestal (E = 1e7 Pa, the rest as above, removal on unless said; one run each; angle by §3.3; "
       "share of Δ² over the parameters run; atom-steps: mean of the four rolling runs):\n\n"
       "| pour | μ_R,PP 0.05 → 0.5 | μ_R,PW 0.05 → 0.5 | μ_PP 0.7 → 1.9 | share of Δ² (μ_R,PW / μ_R,PP / μ_PP) | "
       "atom-steps |\n"
       "|---|---|---|---|---|---|\n"
       "| a wide dump: 16 discs of 45 mm radius, all in the column at the start (150 mm) | 22.6° → 29.8° | "
       "22.5° → 29.4° | 26.9° → 26.2° | 0.47 / 0.52 / 0.01 | 7.6e7 |\n"
       "| the same, nothing removed | 21.1° → 28.2° | 21.0° → 27.1° | not run | 0.42 / 0.58 | 9.9e7 |\n"
       "| a tall column: 38 discs of 25 mm, all in the column (280 mm) | 11.7° → 18.4° | 12.0° → 19.2° | not run | "
       "0.54 / 0.46 | 7.0e7 |\n"
       "| a central stream: discs of 25 mm, 9 in the column, 29 appended at 60 mm | 23.0° → 38.3° | 29.7° → 34.3° "
       "| not run | 0.08 / 0.92 | 1.9e8 |\n"
       "| **a central stream: discs of 32 mm, 9 in the column, 14 appended at 60 mm (the quickstart)** | 24.7° → "
       "37.0° | 28.2° → 32.8° | 28.8° → 33.3° | 0.11 / 0.79 / 0.10 | 1.3e8 |\n"
       "| the same with `fill_height` 80 mm and `settle_speed` 0.05 | 22.7° → 33.1° | 22.6° → 30.8° | not run | "
       "0.38 / 0.62 | 1.2e8 |\n\n"
       "Particles that land as a sheet on the pedestal top stop on their particle-wall contacts; a stream onto the "
       "pile's top builds the cone by avalanches over particles, as the paper pours (discs of 20 mm on its 50 mm "
       "pedestal, one every sqrt(4 r_U/\\|g\\|)), and ranks μ_R,PP first as the larger piles of the paper's "
       "schedule do (at 2400 particles, 25.7° → 37.4° for μ_R,PP against 29.2° → 33.6° for μ_R,PW). The quickstart's "
       "own 20 samples (E in [1e7, 1e8] Pa) rank μ_R,PP first: S1 of the angle 0.63–0.70 (ST 0.68–0.71) against "
       "0.20–0.22 (ST 0.20–0.27) for μ_R,PW over its four metamodels, S1 of E at most 0.002. Its baseline at E = 1e7 "
       "Pa measured 30.9°, 31.5° and 31.9° with three packings (study seeds 20240501, 7 and 11; robust estimator "
       "33.0°, 33.3°, 33.9°); with 4800 particles 31.0° (robust 32.1°, unsettled at the cap); at E = 1e8 Pa 32.3° "
       "(robust 33.7°)."},
      {"oedometer", "Defaults: assembly one of the paper's §4 (`preset = \"paper\"`).", ""},
      {"timestep", "",
       "T_R = π r_min sqrt(ρ/G) / (0.1631 ν + 0.8766), G = E / (2 (1 + ν)). A case is refused (with the reason) "
       "when dt > 0.3 T_R, when E lies outside [5e6, 1e9] Pa without the matching `[material]` flag, or when a "
       "servo plate's `servo_vel_max` ≥ skin / (2 dt)."},
      {"run", "", ""},
      {"run.slurm", "", ""},
      {"analysis", "", ""},
  };
  return sections;
}

const std::vector<Setting>& study_settings() {
  static const std::vector<Setting> settings = [] {
    std::vector<Setting> rows = build_settings();
    // Section by section in the order of setting_sections() (stable: the table order within a section).
    std::vector<Setting> ordered;
    for (const SettingSection& section : setting_sections())
      for (Setting& s : rows)
        if (s.section == section.name) ordered.push_back(std::move(s));
    assert(ordered.size() == rows.size() && "a row of an unlisted section");
    return ordered;
  }();
  return settings;
}

const Setting* find_setting(const std::string& section, const std::string& key) {
  for (const Setting& s : study_settings())
    if (s.section == section && s.key == key) return &s;
  return nullptr;
}

std::vector<std::string> setting_keys(const std::string& section) {
  // The keys of a table row ("parameters.E": low, high, scale).
  if (const std::size_t dot = section.rfind('.'); dot != std::string::npos)
    if (const Setting* s = find_setting(section.substr(0, dot), section.substr(dot + 1));
        s && s->type == SettingType::table)
      return s->choices;
  std::vector<std::string> keys;
  for (const Setting& s : study_settings())
    if (s.section == section) keys.push_back(s.key);
  const std::string prefix = section + ".";
  for (const SettingSection& sub : setting_sections())
    if (sub.name.rfind(prefix, 0) == 0) keys.push_back(sub.name.substr(prefix.size()));
  return keys;
}

std::string unknown_key_hint(const std::string& section, const std::string& key) {
  // Keys an earlier demsa knew.
  if (section == "pile" && key == "ke_stop")
    return " (it was replaced by `settle_speed` and `settle_window`: a pile is settled once the particles on the "
           "pedestal are slow, whatever rolls on the ground; remove `ke_stop`, see docs/study-file.md)";
  const std::vector<std::string> keys = setting_keys(section);
  if (keys.empty()) return {};
  // The nearest key by edit distance, if it is near enough to be a typo, or a key this one begins (or that begins it).
  std::string best;
  std::size_t best_distance = std::string::npos;
  for (const std::string& k : keys) {
    const std::size_t d = edit_distance(key, k);
    const bool prefix = !key.empty() && (k.rfind(key, 0) == 0 || key.rfind(k, 0) == 0);
    const std::size_t score = prefix ? std::min<std::size_t>(d, 1) : d;
    if (score < best_distance) {
      best_distance = score;
      best = k;
    }
  }
  const std::size_t near_enough = std::max<std::size_t>(2, key.size() / 3);
  const std::string valid = "valid: " + join(keys);
  if (best_distance <= near_enough) return fmt::format(" (did you mean '{}'? {})", best, valid);
  return " (" + valid + ")";
}

std::string design_hash_text(const StudyConfig& config) {
  // The rows of effect cases give exactly the text of the first version (same keys, order and number format), so a
  // study keeps its hash. The measurement rows came later: a value at its default adds nothing, so studies that
  // never changed them keep their hash too; a study made before, with a non-default measurement value, is refused
  // once as changed (`demsa run --new` starts it again).
  std::string text;
  const auto add = [&](const Setting& s) {
    for (const auto& [key, value] : s.canonical(config)) text += key + "=" + value + "\n";
  };
  for (const Setting& s : study_settings())
    if (s.effect == SettingEffect::cases && applies_to(s, config.experiment)) add(s);
  StudyConfig defaults;
  defaults.experiment = config.experiment;
  for (const Setting& s : study_settings())
    if (s.effect == SettingEffect::measurement && applies_to(s, config.experiment) &&
        s.canonical(config) != s.canonical(defaults))
      add(s);
  return text;
}

std::string design_hash(const StudyConfig& config) { return fnv1a_64(design_hash_text(config)); }

std::vector<std::string> changed_settings(const StudyConfig& before, const StudyConfig& after) {
  std::vector<std::string> changed;
  for (const Setting& s : study_settings()) {
    if (s.effect == SettingEffect::none) continue;
    if (s.canonical(before) == s.canonical(after)) continue;
    changed.push_back(fmt::format("[{}] {}: {} -> {}", s.section, s.key, s.show(before), s.show(after)));
  }
  return changed;
}

std::string settings_markdown() {
  std::string md;
  for (const SettingSection& section : setting_sections()) {
    const bool sub = section.name.find('.') != std::string::npos;
    md += fmt::format("{} [{}]\n\n", sub ? "###" : "##", section.name);
    if (!section.intro.empty()) md += section.intro + "\n\n";
    md += "| key | type | default | admissible | unit | effect | meaning |\n|---|---|---|---|---|---|---|\n";
    for (const Setting& s : study_settings()) {
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

}  // namespace demsa::study
