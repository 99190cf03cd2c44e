#include "orchestrator/util/text.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace demsa::util {

namespace {
constexpr std::string_view k_blanks = " \t\r\n";
}

std::string trim(std::string_view text) {
  const std::size_t begin = text.find_first_not_of(k_blanks);
  if (begin == std::string_view::npos) return {};
  const std::size_t end = text.find_last_not_of(k_blanks);
  return std::string(text.substr(begin, end - begin + 1));
}

std::string join(const std::vector<std::string>& items, std::string_view separator) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += separator;
    out += items[i];
  }
  return out;
}

std::string join(const std::vector<int>& items, std::string_view separator) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += separator;
    out += std::to_string(items[i]);
  }
  return out;
}

std::optional<double> parse_number(std::string_view text) {
  const std::string t = trim(text);
  if (t.empty()) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<long> parse_long(std::string_view text) {
  const std::string t = trim(text);
  if (t.empty()) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(t.c_str(), &end, 10);
  if (end != t.c_str() + t.size() || errno == ERANGE) return std::nullopt;
  return v;
}

std::string shell_quote(std::string_view text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\'')
      out += "'\\''";
    else
      out += c;
  }
  return out + "'";
}

std::vector<std::string> split(std::string_view text, char separator) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t at = text.find(separator, start);
    if (at == std::string_view::npos) {
      fields.emplace_back(text.substr(start));
      return fields;
    }
    fields.emplace_back(text.substr(start, at - start));
    start = at + 1;
  }
}

std::string rename_fields(std::string message, const std::vector<std::pair<std::string, std::string>>& names) {
  const auto identifier = [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; };
  for (const auto& [field, replacement] : names) {
    const std::string key = "Options." + field;
    for (std::size_t at = message.find(key); at != std::string::npos; at = message.find(key, at)) {
      const std::size_t end = at + key.size();
      if (end < message.size() && identifier(message[end])) {
        at = end;
        continue;
      }
      std::size_t begin = at;  // back over the struct's name: "OedometerOptions"
      while (begin > 0 && identifier(message[begin - 1])) --begin;
      message.replace(begin, end - begin, replacement);
      at = begin + replacement.size();
    }
  }
  return message;
}

}  // namespace demsa::util
