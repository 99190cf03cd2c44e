#include "orchestrator/study/failure_class.hpp"

#include "sobol/enum_names.hpp"

#include <stdexcept>

namespace demsa::study {

namespace {

const sobol::EnumNames<FailureClass>& failure_class_names() {
  static const sobol::EnumNames<FailureClass> names{"failure class",
                                                    {{FailureClass::none, "none"},
                                                     {FailureClass::nonzero_exit, "nonzero-exit"},
                                                     {FailureClass::signal, "signal"},
                                                     {FailureClass::timeout, "timeout"},
                                                     {FailureClass::liggghts_error, "liggghts-error"},
                                                     {FailureClass::lost_particles, "lost-particles"},
                                                     {FailureClass::energy_blowup, "energy-blowup"},
                                                     {FailureClass::missing_dump, "missing-dump"},
                                                     {FailureClass::plate_not_converged, "plate-not-converged"},
                                                     {FailureClass::measurement, "measurement"}}};
  return names;
}

}  // namespace

std::string to_string(FailureClass value) {
  const std::string name = failure_class_names().to_string(value);
  return name.empty() ? "unknown" : name;
}

FailureClass failure_class_from_string(const std::string& name) {
  if (const auto value = failure_class_names().find(name)) return *value;
  // A name read back from the store or from a test, not typed by a user: a programming or data error.
  throw std::invalid_argument(failure_class_names().unknown(name));
}

}  // namespace demsa::study
