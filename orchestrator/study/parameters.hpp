#pragma once
// Every fact about a contact parameter and an observable, once: the study file, the
// case writer, the analysis and the report read names, symbols, labels and units from these two tables.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::study {

/// One contact parameter of the paper's tuple P = (E, ν, μ_PP, μ_PW, e_r, μ_R,PP, μ_R,PW) (paper eq. 1).
struct ContactParameter {
  std::string_view key;       ///< name in the study file, design.csv and params.liggghts: "mu_r_pp"
  std::string_view symbol;    ///< the paper's symbol: "μ_R,PP"
  std::string_view gnuplot;   ///< the symbol in gnuplot's enhanced text: "μ_{R,PP}"
  std::string_view label;     ///< words: "particle-particle rolling friction"
  std::string_view unit;      ///< SI unit, "-" when dimensionless
  std::string_view liggghts;  ///< LIGGGHTS property it sets: "coefficientRollingFriction (11)"
};

/// The seven contact parameters, in the paper's order.
std::span<const ContactParameter> contact_parameters();

/// The entry of `key`, or nullptr for a name that is not a contact parameter.
const ContactParameter* find_contact_parameter(std::string_view key);

/// The keys of contact_parameters(), in order.
const std::vector<std::string>& contact_parameter_names();

/// One observable a study measures (paper §3.3, §4): each experiment lists its own
/// (orchestrator/experiments/experiment.hpp).
struct Observable {
  std::string name;         ///< column in observables.csv and the store: "angle", "settlement_2"
  std::string label;        ///< words: "angle of repose", "settlement s_2"
  std::string unit;         ///< unit as shown: "°", "mm"
  double factor = 1.0;      ///< shown value = stored (SI) value × factor (m -> mm)
  std::string stored_unit;  ///< the unit of the stored value (observables.csv, the store, `demsa measure`): "m", "°"
};

}  // namespace demsa::study
