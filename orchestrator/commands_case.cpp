#include "orchestrator/commands.hpp"

namespace demsa {

void register_case_command(CLI::App& app, CliState& state) {
  register_not_built(app, state, "case",
                     "Regenerate one LIGGGHTS case folder for inspection, runnable by hand with run.sh");
}

}  // namespace demsa
