#include "orchestrator/commands.hpp"

namespace demsa {

void register_sensitivity_command(CLI::App& app, CliState& state) {
  register_not_built(app, state, "sensitivity", "Metamodels and Sobol' indices from a CSV of samples and responses");
}

}  // namespace demsa
