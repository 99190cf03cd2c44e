#pragma once
// What more than one command of cli/ needs: the Sobol' tables that `demsa run` and `demsa analyze` print, and the
// checks of number options and of library options that come from the command line (`demsa postprocess`, `demsa
// compare`).
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "orchestrator/util/text.hpp"

#include <CLI/CLI.hpp>

#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace demsa::cli {

/// The exit status of a command a signal stopped: 128 + N after signal N (the shell's convention), else "check
/// failed" (a study left unfinished by should_stop).
int interrupted_status();

/// Checks of number options with rules a user reads ("--box-side: -1: must be > 0"): CLI11's own Range,
/// PositiveNumber and NonNegativeNumber print DBL_MAX in 309 digits and let nan through. CLI11 puts the option's name
/// before the message and run_cli() "demsa: error:" before that.
CLI::Validator finite_number();
CLI::Validator positive_number();
CLI::Validator non_negative_number();
/// A finite number in [low, high].
CLI::Validator number_in(double low, double high);
/// A whole number in [low, high] ("--batch: 2.5: must be a whole number in [1, 100000]").
CLI::Validator integer_in(long low, long high);

/// The old spelling of a renamed option, kept for one version: hidden from --help, it sets the same value as the new
/// one and warns "--output is deprecated ...: use --out" each time it is given.
template <typename T>
CLI::Option* add_deprecated_option(CLI::App* sub, const std::string& old_name, const std::string& new_name, T& target) {
  return sub->add_option(old_name, target, "Deprecated spelling of " + new_name)
      ->group("")
      ->each([old_name, new_name](const std::string&) {
        util::log::warn("{} is deprecated and will be removed in the next version: use {}", old_name, new_name);
      });
}

/// The command-line option that sets each field of a library's options struct: {"box_side", "--box-side"}.
using OptionNames = std::vector<std::pair<std::string, std::string>>;

/// `message` with every "SomeOptions.FIELD" of `names` written as its option ("OedometerOptions.box_side = nan" ->
/// "--box-side = nan"; util::rename_fields): a user knows the options, not the library's fields.
inline std::string name_options(std::string message, const OptionNames& names) {
  return util::rename_fields(std::move(message), names);
}

/// Runs a library call; a util::UserError it throws is thrown again with the fields it names written as their options
/// (`names`).
template <typename Call>
auto with_option_names(const OptionNames& names, Call&& call) {
  try {
    return call();
  } catch (const util::UserError& e) {
    throw util::UserError(name_options(e.what(), names));
  }
}

/// A library's warning sink that writes the fields it names as their options and warns.
inline std::function<void(const std::string&)> warnings_with_option_names(OptionNames names) {
  return
      [names = std::move(names)](const std::string& message) { util::log::warn("{}", name_options(message, names)); };
}

/// Runs `options.validate()` on options filled from the command line. The postprocess library reports a bad option
/// as std::invalid_argument, a programming error for its other callers; here the value came from the user, so it is
/// a util::UserError (exit 2), not an internal failure, and names the option (`names`) rather than the field.
template <typename Options>
void validate_command_line(const Options& options, const OptionNames& names = {}) {
  try {
    options.validate();
  } catch (const std::invalid_argument& e) {
    throw util::UserError(name_options(e.what(), names));
  }
}

}  // namespace demsa::cli
