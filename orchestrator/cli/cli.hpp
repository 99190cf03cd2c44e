#pragma once
// The command line of README "Usage". main() calls run_cli() and returns its status; each subcommand is registered
// by its own commands_*.cpp file through the functions in commands.hpp.
namespace demsa::cli {

/// Parses the command line, runs one subcommand, and returns the exit status (0 ok, 1 check failed, 2 usage or
/// input error). Every exception a user can cause is caught here, once, and printed as "demsa: error: ...".
int run_cli(int argc, char** argv);

}  // namespace demsa::cli
