#pragma once
// One registration function per subcommand; each lives in cli/<command>.cpp. A callback throws on error (run_cli()
// prints it once and picks the exit status) and otherwise sets CliState::exit_code.
#include <CLI/CLI.hpp>

namespace demsa::cli {

/// What a subcommand's callback reports back to run_cli().
struct CliState {
  int exit_code = 0;
};

void register_run_command(CLI::App& app, CliState& state);        // run.cpp
void register_status_command(CLI::App& app, CliState& state);     // status.cpp
void register_analyze_command(CLI::App& app, CliState& state);    // analyze.cpp
void register_case_commands(CLI::App& app, CliState& state);      // case.cpp: case and the experiments' hidden drivers
void register_report_command(CLI::App& app, CliState& state);     // report.cpp
void register_calibrate_command(CLI::App& app, CliState& state);  // calibrate.cpp
void register_design_command(CLI::App& app, CliState& state);     // design.cpp
void register_sensitivity_command(CLI::App& app, CliState& state);  // sensitivity.cpp
void register_postprocess_command(CLI::App& app, CliState& state);  // postprocess.cpp
void register_compare_command(CLI::App& app, CliState& state);      // compare.cpp
void register_export_vtk_command(CLI::App& app, CliState& state);   // export_vtk.cpp
void register_predict_command(CLI::App& app, CliState& state);      // predict.cpp
void register_extend_command(CLI::App& app, CliState& state);       // extend.cpp
void register_refine_command(CLI::App& app, CliState& state);       // refine.cpp
void register_measure_command(CLI::App& app, CliState& state);      // measure.cpp
void register_plan_command(CLI::App& app, CliState& state);         // plan.cpp

}  // namespace demsa::cli
