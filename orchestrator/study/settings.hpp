#pragma once
// Every setting of the study file, once: one row per key with its section, type, default, admissible range, unit,
// effect on an existing study and documentation line. The parser (config.cpp) reads the file through these rows,
// the unknown-key hints list them, design_hash() hashes the rows that change the cases or their measurement, and
// the key-by-key reference of docs/reference/study-file.md is settings_markdown().
#include "orchestrator/study/config.hpp"
#include "sobol/design.hpp"

#include <filesystem>
#include <functional>
#include <map>
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
  std::string section;  ///< "timestep", "run.slurm" (a table inside [run]), or an experiment's own section
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
  std::string name;   ///< "timestep", "run.slurm"
  std::string intro;  ///< markdown before its table (may be empty)
  std::string notes;  ///< markdown after its table (may be empty)
};

/// Where a section's cross-key rules point when they fail: the section just read, the lines of its keys.
class SectionCheck {
 public:
  virtual ~SectionCheck() = default;
  virtual const std::string& section() const = 0;
  /// True when the file gives `key` in this section.
  virtual bool given(const std::string& key) const = 0;
  /// Throws util::UserError "FILE:LINE: [section] key: message" at the key's line (the section's line when the file
  /// does not give the key).
  [[noreturn]] virtual void fail(const std::string& key, const std::string& message) const = 0;
};

/// What the settings table knows of one experiment: its name (the value of `[study] experiment`), the sections it
/// owns and the rules that tie their keys together. The experiment's rows are rows of the table like any other.
struct ExperimentSchema {
  std::string name;                   ///< the value of `[study] experiment` that selects it
  std::string summary;                ///< for the docs of `[study] experiment`: "angle of repose of a pile (§3)"
  std::vector<std::string> sections;  ///< the sections only this experiment reads (usually one, of its name)
  /// Checks one of its sections once every key of it is read; throws through `at`. May be empty.
  std::function<void(const StudyConfig&, const SectionCheck& at)> check;
  /// Keys an earlier demsa read in its sections, each with the hint that follows "unknown key 'KEY'".
  std::map<std::string, std::string> retired_keys;
};

/// The one table of every study setting: the sections in the order of the docs, the rows section by section, and
/// the experiments whose sections they are. The parser (config.cpp) reads a file through it, the unknown-key hints
/// list its keys, design_hash() hashes its rows and docs/reference/study-file.md is its markdown(). The core sections
/// are core_settings(); the full table, with every experiment, is orchestrator/experiments/registry.hpp's.
class SettingsTable {
 public:
  /// `sections` in docs order (rows of a section not listed are a programming error); `rows` in table order;
  /// `experiments` in the order of the docs of `[study] experiment`, whose row gets their names as its choices.
  SettingsTable(std::vector<SettingSection> sections, std::vector<Setting> rows,
                std::vector<ExperimentSchema> experiments);

  /// Every section, in the order of the docs.
  const std::vector<SettingSection>& sections() const { return m_sections; }
  /// Every setting, section by section in the order of sections().
  const std::vector<Setting>& rows() const { return m_rows; }
  const std::vector<ExperimentSchema>& experiments() const { return m_experiments; }

  /// The row of `key` in `section`, or nullptr.
  const Setting* find(const std::string& section, const std::string& key) const;
  /// The experiment named `name`, or nullptr.
  const ExperimentSchema* experiment(const std::string& name) const;
  /// The experiment that owns `section`, or nullptr for a core section.
  const ExperimentSchema* owner(const std::string& section) const;

  /// The keys of `section` in table order, followed by the names of its sub-tables ("slurm" in [run]); for a table
  /// row's own section ("parameters.E") the keys of that table.
  std::vector<std::string> keys(const std::string& section) const;

  /// The hint that follows "unknown key 'KEY' in [SECTION]": " (did you mean 'X'? valid: a, b, c)" or
  /// " (valid: a, b, c)"; "" for a section without rows.
  std::string unknown_key_hint(const std::string& section, const std::string& key) const;

  /// The canonical text design_hash() hashes: the lines of every row whose effect is cases, in table order (rows of
  /// an experiment's sections only for that experiment), then the lines of every measurement row whose value
  /// differs from its default.
  std::string hash_text(const StudyConfig& config) const;
  /// The lines of hash_text() that change the cases themselves (effect cases): two configs with the same one write
  /// the same LIGGGHTS inputs and differ at most in how their cases are measured.
  std::string cases_hash_text(const StudyConfig& config) const;

  /// The rows of effect cases or measurement whose values differ between `before` and `after`, one
  /// "[section] key: BEFORE -> AFTER" each.
  std::vector<std::string> changed(const StudyConfig& before, const StudyConfig& after) const;

  /// The key-by-key reference of docs/reference/study-file.md (between its settings-table markers): per section a
  /// heading, its intro, one table row per setting and its notes.
  std::string markdown() const;

  /// Reads and validates study text; `file` is the name used in messages. Throws util::UserError
  /// "study.toml:LINE: ..." for unknown keys, wrong types and impossible values. The config points at this table.
  StudyConfig parse(const std::string& text, const std::filesystem::path& file) const;
  /// Reads a study file (parse()); also "FILE: ..." for a folder or a file larger than k_max_study_file_bytes.
  StudyConfig load(const std::filesystem::path& file) const;

 private:
  bool applies(const Setting& s, const std::string& experiment) const;

  std::vector<SettingSection> m_sections;
  std::vector<Setting> m_rows;
  std::vector<ExperimentSchema> m_experiments;
};

/// The core of the table: every section that is not an experiment's ([study], [design], [parameters], [material],
/// [contact], [timestep], [run], [run.slurm], [analysis]) with its rows. `experiment_sections` (in order) are
/// placed where the docs show the experiments' sections, after [contact]; their rows come from the experiments.
std::vector<SettingSection> core_sections(const std::vector<SettingSection>& experiment_sections);
std::vector<Setting> core_settings();

}  // namespace demsa::study
