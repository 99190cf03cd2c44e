#include "orchestrator/commands.hpp"

namespace demsa {

void register_compare_command(CLI::App& app, CliState& state) {
  register_not_built(app, state, "compare", "Compare two dumps or case folders; exit 1 beyond tolerance");
}

}  // namespace demsa
