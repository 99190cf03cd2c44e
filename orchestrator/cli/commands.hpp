#pragma once
// One registration function per subcommand family; each lives in its own commands_<name>.cpp.
#include <CLI/CLI.hpp>

namespace demsa::cli {

/// What a subcommand's callback reports back to run_cli().
struct CliState {
  int exit_code = 0;
};

void register_run_commands(CLI::App& app, CliState& state);         // run, status, analyze
void register_case_command(CLI::App& app, CliState& state);         // case
void register_report_commands(CLI::App& app, CliState& state);      // report, calibrate
void register_design_command(CLI::App& app, CliState& state);       // design
void register_sensitivity_command(CLI::App& app, CliState& state);  // sensitivity
void register_postprocess_command(CLI::App& app, CliState& state);  // postprocess
void register_compare_command(CLI::App& app, CliState& state);      // compare

}  // namespace demsa::cli
