#pragma once
// Small text helpers: the one trim, join and strict number parser of the orchestrator. (postprocess/text.hpp has
// its own for the file readers, since postprocess/ cannot use orchestrator/.)
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace demsa::util {

/// `text` without leading and trailing blanks (space, tab, CR, LF).
std::string trim(std::string_view text);

/// The items joined by `separator` ("a, b, c" by default).
std::string join(const std::vector<std::string>& items, std::string_view separator = ", ");
/// Whole numbers joined by `separator` ("3 5 7" by default: sample numbers).
std::string join(const std::vector<int>& items, std::string_view separator = " ");

/// The whole of `text` (blanks around it allowed) as a finite double; nullopt when it is empty, has trailing
/// characters, or is infinite or NaN.
std::optional<double> parse_number(std::string_view text);

/// The whole of `text` (blanks around it allowed) as a long; nullopt when it is not one or out of range.
std::optional<long> parse_long(std::string_view text);

/// `text` as one single-quoted bash word: `a b'c` -> `'a b'\''c'` (for the scripts demsa writes: run.sh, the
/// SLURM batch script).
std::string shell_quote(std::string_view text);

/// `text` split at every `separator` (an empty text gives one empty field; a trailing separator an empty last one).
std::vector<std::string> split(std::string_view text, char separator);

/// `message` with every "SomeOptions.FIELD" whose FIELD is a key of `names` written as its value
/// ("OedometerOptions.box_side = nan" -> "--box-side = nan" for {"box_side", "--box-side"}): the libraries' messages
/// name the field of their options struct that is wrong; a front end writes it in its own words. A longer field
/// ("Options.box_side_x") is not a match of "box_side".
std::string rename_fields(std::string message, const std::vector<std::pair<std::string, std::string>>& names);

}  // namespace demsa::util
