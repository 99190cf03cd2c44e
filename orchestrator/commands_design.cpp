#include "orchestrator/commands.hpp"

namespace demsa {

void register_design_command(CLI::App& app, CliState& state) {
  register_not_built(app, state, "design", "Write a design (lhs, sobol, saltelli) as CSV, for any simulator");
}

}  // namespace demsa
