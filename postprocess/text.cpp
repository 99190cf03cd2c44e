#include "postprocess/text.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

namespace demsa::postprocess {

std::vector<std::string> split_words(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  std::string word;
  while (in >> word) out.push_back(word);
  return out;
}

bool parse_double(const std::string& s, double& value, bool finite_only) {
  const char* b = s.data();
  const char* e = b + s.size();
  if (b != e && *b == '+') ++b;
  const auto [ptr, ec] = std::from_chars(b, e, value);
  return ec == std::errc() && ptr == e && b != e && (!finite_only || std::isfinite(value));
}

}  // namespace demsa::postprocess
