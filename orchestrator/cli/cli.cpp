#include "orchestrator/cli/cli.hpp"

#include "orchestrator/cli/commands.hpp"
#include "orchestrator/exec/cost.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/signals.hpp"
#include "orchestrator/version.hpp"
#include "postprocess/error.hpp"
#include "sobol/error.hpp"

#include <SQLiteCpp/Exception.h>
#include <fmt/core.h>

#include <exception>
#include <new>
#include <string>
#include <system_error>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::exec;

namespace {

int user_error(const std::string& message) {
  fmt::print(stderr, "demsa: error: {}\n", message);
  return k_exit_usage;
}

int internal_error(const std::string& message) {
  fmt::print(stderr, "demsa: internal error: {}\n", message);
  return k_exit_internal;
}

/// "demsa postprocess oedometer": the command line's subcommands, as far as they were parsed.
std::string command_name(const CLI::App& app) {
  std::string name = "demsa";
  const CLI::App* at = &app;
  while (true) {
    // The parsed subcommands (a filter would list every registered one, and name the first: `demsa run`).
    const std::vector<CLI::App*> subs = at->get_subcommands();
    if (subs.empty()) break;
    at = subs.front();
    name += " " + at->get_name();
  }
  return name;
}

}  // namespace

int report_error(const std::exception_ptr& error, const std::string& command) {
  // The libraries' own input errors (sobol, postprocess) know nothing of demsa's CLI; they are the user's to fix
  // like util::UserError.
  try {
    std::rethrow_exception(error);
  } catch (const UserError& e) {
    return user_error(e.what());
  } catch (const sobol::InputError& e) {  // sobol::DataError too
    return user_error(e.what());
  } catch (const sobol::NumericalError& e) {
    // A metamodel that cannot be fitted, or indices that cannot be computed, from the user's data (a singular
    // design, too few distinct samples, no convergence): the data's fault, fixed by more or other samples or
    // another metamodel, not by the machine.
    return user_error(e.what());
  } catch (const postprocess::ParseError& e) {
    return user_error(e.what());
  } catch (const postprocess::InputError& e) {
    return user_error(e.what());
  } catch (const InternalError& e) {  // util::IoError too
    return internal_error(e.what());
  } catch (const SQLite::Exception& e) {
    return internal_error(fmt::format("study store (SQLite): {}", e.what()));
  } catch (const std::system_error& e) {  // std::filesystem::filesystem_error names its paths
    return internal_error(e.what());
  } catch (const StopRequested&) {
    // A stop during case writing (util/signals.hpp); what was written is gone.
    const int sig = StopFlag::signal_number();
    fmt::print(stderr, "demsa: stopped by signal {}; nothing partial was left\n", sig);
    return sig > 0 ? k_exit_signal_base + sig : k_exit_internal;
  } catch (const std::bad_alloc&) {
    // The sizes a user gives are bounded where they are read; this is the backstop for any other allocation.
    return internal_error(
        fmt::format("out of memory while running `{}`: an input asks for more memory than this "
                    "machine has",
                    command.empty() ? std::string("demsa") : command));
  } catch (const std::exception& e) {
    return internal_error(e.what());
  } catch (...) {
    return internal_error("an exception that is not a std::exception");
  }
}

int run_cli(int argc, char** argv) {
  // Log lines go to standard error (util/log.hpp): standard output carries results, e.g. the JSON of `demsa
  // status --json`.
  CLI::App app{
      "demsa: sensitivity analysis and calibration of DEM models in LIGGGHTS\n"
      "(design of experiments, LIGGGHTS cases, observables, metamodels, Sobol' indices, calibration)",
      "demsa"};
  app.require_subcommand(0, 1);
  app.fallthrough(false);
  bool version = false;
  app.add_flag("--version", version, "Print demsa's version and the LIGGGHTS version found at run time");

  CliState state;
  register_run_command(app, state);
  register_status_command(app, state);
  register_analyze_command(app, state);
  register_case_commands(app, state);
  register_report_command(app, state);
  register_calibrate_command(app, state);
  register_design_command(app, state);
  register_sensitivity_command(app, state);
  register_postprocess_command(app, state);
  register_compare_command(app, state);
  register_export_vtk_command(app, state);
  register_predict_command(app, state);
  register_extend_command(app, state);
  register_refine_command(app, state);
  register_measure_command(app, state);
  register_plan_command(app, state);

  // Every error of every command ends here: the subcommands' callbacks run inside parse().
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // CLI11's own exit codes are not ours: every usage error is 2.
    if (e.get_exit_code() == 0) return k_exit_ok;
    fmt::print(stderr, "demsa: error: {}\nRun with --help for more information.\n", e.what());
    return k_exit_usage;
  } catch (...) {
    return report_error(std::current_exception(), command_name(app));
  }
  if (version) {
    fmt::print("demsa {}\n{}", k_version, liggghts_text());
    return k_exit_ok;
  }
  if (app.get_subcommands().empty()) {
    fmt::print("{}", app.help());
    return k_exit_usage;
  }
  return state.exit_code;
}

}  // namespace demsa::cli
