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

/// A contact parameter tied to another of its study (`[parameters] mu_pw = { same_as = "mu_pp" }`): a wall whose
/// material is not known apart from the particles'. It has no range and no column of the design: the design, the
/// metamodels, the Sobol' indices, the calibration and the planner see its partner alone, and every case gives it
/// its partner's value (params.liggghts, case.json).
struct ParameterTie {
  std::string name;     ///< the tied parameter: "mu_pw"
  std::string partner;  ///< the varied parameter whose value it takes: "mu_pp"
  int line = 0;         ///< line in the study file (for messages)
};

/// The tie of `name`, or nullptr when `name` is not tied.
const ParameterTie* find_tie(const std::vector<ParameterTie>& ties, std::string_view name);

/// What is wrong with `tie` in a study whose varied parameters are `varied` and whose ties are `ties` (`tie`
/// among them), or an empty string: a partner that is not a contact parameter, the parameter itself, a parameter
/// tied in turn (a chain), or one that is not varied.
std::string tie_problem(const ParameterTie& tie, const std::vector<ParameterTie>& ties,
                        const std::vector<std::string>& varied);

/// The symbol of the varied parameter `name` with those tied to it: "μ_PP = μ_PW" (`gnuplot`: in gnuplot's enhanced
/// text, "μ_{PP} = μ_{PW}"); the plain symbol when nothing is tied to it.
std::string symbol_with_ties(std::string_view name, const std::vector<ParameterTie>& ties, bool gnuplot = false);

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
