#pragma once
// Method choice by enum class: one table of (value, name) pairs per enum gives from_string (listing the valid
// names on error), to_string and the list of names (after Ceres's types.cc, without its macros).
#include "sobol/error.hpp"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace demsa::sobol {

template <typename Enum>
class EnumNames {
 public:
  /// `what` names the kind in messages ("metamodel"); `names` holds each value once with its canonical name;
  /// `aliases` are further names accepted by from_string.
  EnumNames(std::string what, std::vector<std::pair<Enum, std::string>> names,
            std::vector<std::pair<std::string, Enum>> aliases = {})
      : m_what(std::move(what)), m_names(std::move(names)), m_aliases(std::move(aliases)) {}

  /// The value of a canonical name or alias; nullopt for any other name.
  std::optional<Enum> find(const std::string& name) const {
    for (const auto& [value, text] : m_names)
      if (text == name) return value;
    for (const auto& [text, value] : m_aliases)
      if (text == name) return value;
    return std::nullopt;
  }

  /// The value of a canonical name or alias; throws InputError "unknown WHAT 'NAME' (valid: a, b, c)".
  Enum from_string(const std::string& name) const {
    if (const std::optional<Enum> value = find(name)) return *value;
    throw InputError(unknown(name));
  }

  /// "unknown WHAT 'NAME' (valid: a, b, c)".
  std::string unknown(const std::string& name) const {
    return "unknown " + m_what + " '" + name + "' (valid: " + valid() + ")";
  }

  /// The canonical name of a value ("" for a value not in the table, which is a programming error).
  std::string to_string(Enum value) const {
    for (const auto& [v, text] : m_names)
      if (v == value) return text;
    return {};
  }

  /// The canonical names, in table order.
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& entry : m_names) out.push_back(entry.second);
    return out;
  }

  /// "a, b, c".
  std::string valid() const {
    std::string out;
    for (const auto& entry : m_names) out += (out.empty() ? "" : ", ") + entry.second;
    return out;
  }

 private:
  std::string m_what;
  std::vector<std::pair<Enum, std::string>> m_names;
  std::vector<std::pair<std::string, Enum>> m_aliases;
};

}  // namespace demsa::sobol
