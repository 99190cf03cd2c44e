#include "orchestrator/commands.hpp"

namespace demsa {

void register_run_commands(CLI::App& app, CliState& state) {
  register_not_built(app, state, "run", "Run a whole study, resumable: skips finished cases, retries failed ones");
  register_not_built(app, state, "status", "Counts by state, failures with their class, ETA");
  register_not_built(app, state, "analyze",
                     "Metamodels and Sobol' indices on a study's observables (writes analysis/)");
}

}  // namespace demsa
