#include "orchestrator/study/failure_class.hpp"

#include <fmt/core.h>

#include <array>
#include <stdexcept>
#include <utility>

namespace demsa::study {

namespace {

constexpr std::array<std::pair<FailureClass, const char*>, 10> k_names{{
    {FailureClass::none, "none"},
    {FailureClass::nonzero_exit, "nonzero-exit"},
    {FailureClass::signal, "signal"},
    {FailureClass::timeout, "timeout"},
    {FailureClass::liggghts_error, "liggghts-error"},
    {FailureClass::lost_particles, "lost-particles"},
    {FailureClass::energy_blowup, "energy-blowup"},
    {FailureClass::missing_dump, "missing-dump"},
    {FailureClass::plate_not_converged, "plate-not-converged"},
    {FailureClass::measurement, "measurement"},
}};

}  // namespace

std::string to_string(FailureClass value) {
  for (const auto& [cls, name] : k_names)
    if (cls == value) return name;
  return "unknown";
}

FailureClass failure_class_from_string(const std::string& name) {
  std::string valid;
  for (const auto& [cls, text] : k_names) {
    if (name == text) return cls;
    if (!valid.empty()) valid += ", ";
    valid += text;
  }
  throw std::invalid_argument(fmt::format("unknown failure class '{}' (valid: {})", name, valid));
}

}  // namespace demsa::study
