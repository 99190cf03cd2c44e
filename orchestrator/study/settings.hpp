#pragma once
// Every setting of the study file, once: one row per key with its section, type, default, admissible range, unit,
// effect on an existing study and documentation line. The parser (config.cpp) reads the file through these rows,
// the unknown-key hints list them, design_hash() hashes the rows that change the cases or their measurement, and
// the key-by-key reference of docs/study-file.md is settings_markdown().
#include "orchestrator/study/config.hpp"
#include "sobol/design.hpp"

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace demsa::study {

enum class SettingType {
  number,       ///< a finite number (TOML integer or float)
  integer,      ///< a TOML integer
  boolean,      ///< true or false
  string,       ///< any string
  string_list,  ///< an array of strings
  number_list,  ///< an array of numbers
  enumeration,  ///< a string out of Setting::choices
  table,        ///< an inline table with the keys Setting::choices (the parameter ranges)
};
std::string to_string(SettingType type);

/// What a changed value does to an existing study.
enum class SettingEffect {
  cases,        ///< changes the design or the cases: enters the design hash
  measurement,  ///< changes how finished cases are measured: enters the design hash too
  none,         ///< may change in an existing study ([run], [analysis], the study name, ...)
};
std::string to_string(SettingEffect effect);

/// One end of an admissible interval.
struct SettingBound {
  double value = 0.0;
  bool inclusive = true;
};

/// The interval the parser checks a number or integer against (every element of a number list).
struct SettingBounds {
  std::optional<SettingBound> low;
  std::optional<SettingBound> high;
  std::string reason;     ///< why, appended to the message after ": " (may be empty)
  bool integral = false;  ///< the bounds of an integer row (text() writes them as integers)
  bool contains(double value) const;
  /// "> 0", ">= 1", "(0, 0.5)", "[0, 1]"; "" without bounds.
  std::string text() const;
  /// "must be > 0", "must lie in (0, 0.5)"; "" without bounds.
  std::string rule() const;
};

/// The most samples of the optimised Latin hypercubes (`lhs-maximin`, `lhs-cl2`): their optimisers keep N x N tables
/// of the sample pairs, and sobol::make_design refuses more (the study refuses them at their line instead).
inline constexpr int k_max_optimised_lhs_samples = sobol::k_max_optimised_lhs_samples;

/// A value as the parser read it, by type: number -> double, integer -> long, boolean -> bool, string and
/// enumeration -> std::string, lists -> vectors.
using SettingValue = std::variant<double, long, bool, std::string, std::vector<double>, std::vector<std::string>>;

/// A value a row refuses for a reason its bounds cannot express; the parser adds "file:line: [section] key: ".
struct SettingError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One key of the study file.
struct Setting {
  std::string section;  ///< "pile", "run.slurm" (a table inside [run])
  std::string key;
  SettingType type = SettingType::number;
  std::vector<std::string> choices;  ///< enumeration: the valid names; table: its keys
  std::string default_text;          ///< the default as the docs show it
  std::string range_text;            ///< the admissible values in words (docs)
  SettingBounds bounds;              ///< number, integer, number list: checked by the parser
  std::string unit;                  ///< SI unit, "" when dimensionless
  SettingEffect effect = SettingEffect::none;
  std::string doc;        ///< one documentation line (markdown)
  bool required = false;  ///< the file must give it
  bool first = false;     ///< read before the other keys of its section (presets: explicit keys override them)
  std::string hash_key;   ///< its name in the canonical text of design_hash()
  /// Stores a value of `type`, already type- and bounds-checked, into the config; throws SettingError for values
  /// the bounds cannot judge. Empty for a table row: the parser reads it with dedicated code.
  std::function<void(StudyConfig&, const SettingValue&)> assign;
  /// The value in the config, as a user would write it (docs, messages).
  std::function<std::string(const StudyConfig&)> show;
  /// The canonical "key=value" lines of the value for design_hash() (possibly none).
  std::function<std::vector<std::pair<std::string, std::string>>(const StudyConfig&)> canonical;
};

/// A section of the study file, in file order, with its prose for the docs.
struct SettingSection {
  std::string name;   ///< "pile", "run.slurm"
  std::string intro;  ///< markdown before its table (may be empty)
  std::string notes;  ///< markdown after its table (may be empty)
};

/// Every section, in the order of the docs: [study], [design], [parameters], [material], [pile], [oedometer],
/// [timestep], [run], [run.slurm], [analysis].
const std::vector<SettingSection>& setting_sections();

/// Every setting, section by section in the order of setting_sections().
const std::vector<Setting>& study_settings();

/// The row of `key` in `section`, or nullptr.
const Setting* find_setting(const std::string& section, const std::string& key);

/// The keys of `section` in table order, followed by the names of its sub-tables ("slurm" in [run]); for a table
/// row's own section ("parameters.E") the keys of that table.
std::vector<std::string> setting_keys(const std::string& section);

/// The hint that follows "unknown key 'KEY' in [SECTION]": " (did you mean 'X'? valid: a, b, c)" or
/// " (valid: a, b, c)"; "" for a section without rows.
std::string unknown_key_hint(const std::string& section, const std::string& key);

/// The canonical text design_hash() hashes: the lines of every row whose effect is cases, in table order (rows of
/// [pile] or [oedometer] only for that experiment), then the lines of every measurement row whose value differs
/// from its default.
std::string design_hash_text(const StudyConfig& config);

/// The rows of effect cases or measurement whose values differ between `before` and `after`, one
/// "[section] key: BEFORE -> AFTER" each.
std::vector<std::string> changed_settings(const StudyConfig& before, const StudyConfig& after);

/// The key-by-key reference of docs/study-file.md (between its settings-table markers): per section a heading, its
/// intro, one table row per setting and its notes.
std::string settings_markdown();

}  // namespace demsa::study
