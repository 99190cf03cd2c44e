#include "orchestrator/study/parameters.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <charconv>

namespace demsa::study {

namespace {

// Paper eq. 1 and Table 3; LIGGGHTS 3.8.0 property names from liggghts_templates/contact.liggghts (matrices in
// the order 11 12 21 22: particle-particle, particle-wall, wall-particle, wall-wall).
constexpr std::array<ContactParameter, 7> k_contact_parameters{{
    {"E", "E", "E", "Young's modulus", "Pa", "youngsModulus"},
    {"nu", "ν", "ν", "Poisson ratio", "-", "poissonsRatio"},
    {"mu_pp", "μ_PP", "μ_{PP}", "particle-particle friction", "-", "coefficientFriction (11)"},
    {"mu_pw", "μ_PW", "μ_{PW}", "particle-wall friction", "-", "coefficientFriction (12, 21, 22)"},
    {"e_r", "e_r", "e_r", "coefficient of restitution", "-", "coefficientRestitution"},
    {"mu_r_pp", "μ_R,PP", "μ_{R,PP}", "particle-particle rolling friction", "-", "coefficientRollingFriction (11)"},
    {"mu_r_pw", "μ_R,PW", "μ_{R,PW}", "particle-wall rolling friction", "-", "coefficientRollingFriction (12, 21, 22)"},
}};

}  // namespace

std::span<const ContactParameter> contact_parameters() { return k_contact_parameters; }

const ContactParameter* find_contact_parameter(std::string_view key) {
  for (const ContactParameter& p : k_contact_parameters)
    if (p.key == key) return &p;
  return nullptr;
}

const std::vector<std::string>& contact_parameter_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const ContactParameter& p : k_contact_parameters) out.emplace_back(p.key);
    return out;
  }();
  return names;
}

const ParameterTie* find_tie(const std::vector<ParameterTie>& ties, std::string_view name) {
  for (const ParameterTie& t : ties)
    if (t.name == name) return &t;
  return nullptr;
}

std::string tie_problem(const ParameterTie& tie, const std::vector<ParameterTie>& ties,
                        const std::vector<std::string>& varied) {
  if (!find_contact_parameter(tie.partner)) {
    std::string valid;
    for (const std::string& n : contact_parameter_names())
      if (n != tie.name) valid += (valid.empty() ? "" : ", ") + n;
    return fmt::format("same_as = \"{}\": not a contact parameter (valid: {})", tie.partner, valid);
  }
  if (tie.partner == tie.name)
    return fmt::format("same_as = \"{}\": a parameter cannot be tied to itself", tie.partner);
  if (const ParameterTie* next = find_tie(ties, tie.partner))
    return fmt::format("same_as = \"{}\": {} is itself tied to {} (line {}); tie {} to {} directly", tie.partner,
                       tie.partner, next->partner, next->line, tie.name, next->partner);
  if (std::find(varied.begin(), varied.end(), tie.partner) == varied.end())
    return fmt::format(
        "same_as = \"{}\": {} is not varied; give it a range {{ low, high }} in [parameters], or set both in "
        "[material]",
        tie.partner, tie.partner);
  return {};
}

std::string symbol_with_ties(std::string_view name, const std::vector<ParameterTie>& ties, bool gnuplot) {
  const auto symbol = [gnuplot](std::string_view key) {
    const ContactParameter* p = find_contact_parameter(key);
    return p ? std::string(gnuplot ? p->gnuplot : p->symbol) : std::string(key);
  };
  std::string text = symbol(name);
  for (const ParameterTie& t : ties)
    if (t.partner == name) text += " = " + symbol(t.name);
  return text;
}

}  // namespace demsa::study
