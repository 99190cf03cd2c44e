#include "orchestrator/commands.hpp"

namespace demsa {

void register_postprocess_command(CLI::App& app, CliState& state) {
  register_not_built(app, state, "postprocess",
                     "Observable (pile angle, oedometer settlements) from a dump or plate log");
}

}  // namespace demsa
