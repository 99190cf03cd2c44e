#include "orchestrator/cli/cli.hpp"

#include "orchestrator/cli/commands.hpp"
#include "orchestrator/exec/liggghts_locator.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/version.hpp"

#include <fmt/core.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <exception>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::exec;

namespace {

void print_version() {
  fmt::print("demsa {}\n", k_version);
  if (const auto info = query_liggghts()) {
    if (info->version.empty())
      fmt::print("LIGGGHTS: found at {}, but its version could not be read from `-h`\n", info->executable);
    else
      fmt::print("LIGGGHTS {} ({})\n", info->version, info->executable);
  } else {
    fmt::print(
        "LIGGGHTS: not found (no `liggghts` on PATH and DEMSA_LIGGGHTS not set); install it with "
        "scripts/install-deps.sh\n");
  }
}

}  // namespace

int run_cli(int argc, char** argv) {
  // Log lines (SLURM warnings, submissions) go to standard error: standard output carries results, e.g. the JSON
  // of `demsa status --json`.
  if (!spdlog::get("demsa")) spdlog::set_default_logger(spdlog::stderr_color_mt("demsa"));
  CLI::App app{
      "demsa: sensitivity analysis and calibration of DEM models in LIGGGHTS\n"
      "(design of experiments, LIGGGHTS cases, observables, metamodels, Sobol' indices, calibration)",
      "demsa"};
  app.require_subcommand(0, 1);
  app.fallthrough(false);
  bool version = false;
  app.add_flag("--version", version, "Print demsa's version and the LIGGGHTS version found at run time");

  CliState state;
  register_run_commands(app, state);
  register_case_command(app, state);
  register_report_commands(app, state);
  register_design_command(app, state);
  register_sensitivity_command(app, state);
  register_postprocess_command(app, state);
  register_compare_command(app, state);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // CLI11's own exit codes are not ours: every usage error is 2.
    app.exit(e);
    return e.get_exit_code() == 0 ? k_exit_ok : k_exit_usage;
  } catch (const std::exception& e) {
    fmt::print(stderr, "demsa: error: {}\n", e.what());
    return k_exit_usage;
  }
  if (version) {
    print_version();
    return k_exit_ok;
  }
  if (app.get_subcommands().empty()) {
    fmt::print("{}", app.help());
    return k_exit_usage;
  }
  return state.exit_code;
}

}  // namespace demsa::cli
