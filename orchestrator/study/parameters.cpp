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

constexpr std::string_view k_settlement_prefix = "settlement_";

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

std::string settlement_name(std::size_t k) { return fmt::format("{}{}", k_settlement_prefix, k); }

std::optional<std::size_t> settlement_index(std::string_view name) {
  if (name.substr(0, k_settlement_prefix.size()) != k_settlement_prefix) return std::nullopt;
  const std::string_view digits = name.substr(k_settlement_prefix.size());
  std::size_t k = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), k);
  if (digits.empty() || error != std::errc{} || end != digits.data() + digits.size() || k == 0) return std::nullopt;
  return k;
}

Observable describe_observable(std::string_view name) {
  const std::string n(name);
  if (name == k_angle) return {n, "angle of repose", "°", 1.0};
  if (name == k_angle_sd) return {n, "spread of the angle over directions", "°", 1.0};
  if (name == k_pile_height) return {n, "pile height", "mm", 1e3};
  if (name == k_particles_on_pedestal) return {n, "particles on the pedestal", "", 1.0};
  if (name == k_settlement_error) return {n, "settlement error E_0", "mm", 1e3};
  if (const auto k = settlement_index(name)) return {n, fmt::format("settlement s_{}", *k), "mm", 1e3};
  return {n, n, "", 1.0};
}

}  // namespace demsa::study
