#pragma once
// The command line of docs/reference/command-line.md. main() calls run_cli() and returns its status; each subcommand is
// registered by its own cli/<command>.cpp file through the functions in commands.hpp.
#include <exception>
#include <string>

namespace demsa::cli {

/// Parses the command line, runs one subcommand, and returns the exit status (util/errors.hpp: 0 ok, 1 check
/// failed, 2 usage or input error, 3 internal failure, 128+N stopped by signal N). Every exception is caught here,
/// once, and printed on one line:
///   "demsa: error: MESSAGE" (exit 2): util::UserError, sobol::InputError and DataError, sobol::NumericalError (a
///       metamodel or index that cannot be computed from the user's data is the data's to fix),
///       postprocess::ParseError and InputError, a CLI11 parse error;
///   "demsa: internal error: MESSAGE" (exit 3): util::InternalError and IoError, SQLite::Exception,
///       std::system_error (std::filesystem::filesystem_error), std::bad_alloc, any other exception.
int run_cli(int argc, char** argv);

/// What run_cli() does with an exception a command threw: prints it on standard error as above and returns its exit
/// status (k_exit_usage or k_exit_internal). `command` ("demsa run") names what ran out of memory on std::bad_alloc.
int report_error(const std::exception_ptr& error, const std::string& command = "");

}  // namespace demsa::cli
