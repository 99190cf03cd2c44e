#pragma once
// Small text helpers shared by the readers of LIGGGHTS's text files (log, plate files).
#include <string>
#include <vector>

namespace demsa::postprocess {

/// The whitespace-separated words of a line.
std::vector<std::string> split_words(const std::string& line);

/// Parses the whole of `s` as a double (a leading '+' allowed). False when `s` is empty, has trailing characters,
/// or (with `finite_only`) is infinite or NaN.
bool parse_double(const std::string& s, double& value, bool finite_only = false);

}  // namespace demsa::postprocess
