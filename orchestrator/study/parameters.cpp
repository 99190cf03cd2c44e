#include "orchestrator/study/parameters.hpp"

#include <fmt/core.h>

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

}  // namespace demsa::study
