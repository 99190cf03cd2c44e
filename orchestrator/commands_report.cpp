#include "orchestrator/commands.hpp"

namespace demsa {

void register_report_commands(CLI::App& app, CliState& state) {
  register_not_built(app, state, "report", "Plots and report.md for a study");
  register_not_built(app, state, "calibrate",
                     "Parameters that best match measured values, optionally verified by a real run");
}

}  // namespace demsa
