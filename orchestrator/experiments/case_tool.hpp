#pragma once
// An experiment's own tool (`demsa postprocess NAME`; Experiment::case_tool): the measurement of one case's files
// outside a study run, with options of its own. The experiment declares the options as a table bound to the tool's
// members (name, help, check, default shown or not); the command line builds its options from the table, fills them,
// and runs the tool, which returns what it prints. A mistake in the values is a util::UserError naming the field of
// the library's options ("PileAngleOptions.levels"); `message_names` says which option sets each field, for the
// command line to name it.
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace demsa::experiments {

/// The rule a tool option's value follows (the command line checks it as it checks its own options).
struct ToolCheck {
  enum class Kind { none, positive, non_negative, range, member };
  Kind kind = Kind::none;
  double low = 0.0, high = 0.0;      ///< range: a finite number in [low, high]
  std::vector<std::string> members;  ///< member: one of these words

  static ToolCheck positive() { return {Kind::positive, 0.0, 0.0, {}}; }
  static ToolCheck non_negative() { return {Kind::non_negative, 0.0, 0.0, {}}; }
  static ToolCheck range(double low, double high) { return {Kind::range, low, high, {}}; }
  static ToolCheck member(std::vector<std::string> words) { return {Kind::member, 0.0, 0.0, std::move(words)}; }
};

/// A value of the tool the option sets (a member of the tool: valid as long as the tool is); bool* is a flag.
using ToolTarget = std::variant<double*, int*, std::string*, std::vector<std::string>*, std::vector<double>*, bool*>;

/// One option of a tool: ToolOption("--levels", "Number of ...", &levels).checked(ToolCheck::range(2, 1e5)).
struct ToolOption {
  std::string name;  ///< "--levels", or a positional's name in capitals ("DUMP")
  std::string help;
  ToolTarget target;
  ToolCheck check;
  bool required = false;
  bool show_default = false;  ///< the help shows the value the target holds
  char delimiter = '\0';      ///< a list's separator within one value (',')

  ToolOption(std::string name_, std::string help_, ToolTarget target_)
      : name(std::move(name_)), help(std::move(help_)), target(target_) {}
  ToolOption&& checked(ToolCheck c) && {
    check = std::move(c);
    return std::move(*this);
  }
  ToolOption&& needed() && {
    required = true;
    return std::move(*this);
  }
  ToolOption&& with_default() && {
    show_default = true;
    return std::move(*this);
  }
  ToolOption&& split_at(char separator) && {
    delimiter = separator;
    return std::move(*this);
  }
};

/// One experiment's tool: its options and its run.
class CaseTool {
 public:
  virtual ~CaseTool() = default;
  /// The options, in the order the help lists them.
  virtual std::vector<ToolOption> options() = 0;
  /// The option (its name as in options()) that sets each field the tool's messages may name: {"levels", "--levels"}.
  virtual std::vector<std::pair<std::string, std::string>> message_names() const = 0;
  /// Measures with the options' values (`given`: the names of the options given, which then win over what a case
  /// records); returns the text to print. Warnings go to `warn`.
  virtual std::string run(const std::set<std::string>& given, const std::function<void(const std::string&)>& warn) = 0;
};

/// How an experiment offers its tool (Experiment::case_tool).
struct CaseToolEntry {
  std::string_view description;         ///< one line for --help
  std::unique_ptr<CaseTool> (*make)();  ///< a tool with its defaults
};

}  // namespace demsa::experiments
