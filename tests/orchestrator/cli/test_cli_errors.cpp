// run_cli()'s one catch (cli::report_error): which exceptions are the user's (exit 2, "demsa: error: ...") and which
// the machine's (exit 3, "demsa: internal error: ..."), and that the message is printed once, unchanged.
#include "orchestrator/cli/cli.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/error.hpp"
#include "sobol/error.hpp"

#include <SQLiteCpp/Exception.h>
#include <gtest/gtest.h>

#include <cerrno>
#include <filesystem>
#include <new>
#include <string>
#include <system_error>

namespace demsa::test {
namespace {

struct Reported {
  int status;
  std::string err;
};

template <typename E>
Reported report(const E& error, const std::string& command = "") {
  testing::internal::CaptureStderr();
  const int status = cli::report_error(std::make_exception_ptr(error), command);
  return {status, testing::internal::GetCapturedStderr()};
}

TEST(CliReportError, UserErrorsExit2WithTheirMessage) {
  const Reported user = report(util::UserError("study.toml", 14, "mu_pw: low > high"));
  EXPECT_EQ(user.status, util::k_exit_usage);
  EXPECT_EQ(user.err, "demsa: error: study.toml:14: mu_pw: low > high\n");

  const Reported input = report(sobol::InputError("unknown metamodel 'quartic' (valid: rsm1, rsm2)"));
  EXPECT_EQ(input.status, util::k_exit_usage);
  EXPECT_EQ(input.err, "demsa: error: unknown metamodel 'quartic' (valid: rsm1, rsm2)\n");

  const Reported data = report(sobol::DataError(2, 0, "duplicates the point of sample 1", 0));
  EXPECT_EQ(data.status, util::k_exit_usage);
  EXPECT_EQ(data.err, "demsa: error: sample 3, input 1: duplicates the point of sample 1\n");

  const Reported parse = report(postprocess::ParseError("pile.dump", 4, "'x' is not an integer"));
  EXPECT_EQ(parse.status, util::k_exit_usage);
  EXPECT_EQ(parse.err, "demsa: error: pile.dump:4: 'x' is not an integer\n");

  const Reported pp_input = report(postprocess::InputError("no particle of type 1 on the pedestal"));
  EXPECT_EQ(pp_input.status, util::k_exit_usage);
  EXPECT_EQ(pp_input.err, "demsa: error: no particle of type 1 on the pedestal\n");
}

TEST(CliReportError, MetamodelThatCannotBeFittedIsTheDatasToFix) {
  const Reported r = report(sobol::NumericalError("the design matrix is singular"));
  EXPECT_EQ(r.status, util::k_exit_usage);
  EXPECT_EQ(r.err, "demsa: error: the design matrix is singular\n");
}

TEST(CliReportError, MachineFailuresExit3AndSayWhatFailed) {
  const Reported io = report(util::IoError("study/analysis/analysis.json: cannot write: No space left on device"));
  EXPECT_EQ(io.status, util::k_exit_internal);
  EXPECT_EQ(io.err, "demsa: internal error: study/analysis/analysis.json: cannot write: No space left on device\n");

  const Reported internal = report(util::InternalError("sbatch: not found"));
  EXPECT_EQ(internal.status, util::k_exit_internal);
  EXPECT_EQ(internal.err, "demsa: internal error: sbatch: not found\n");

  const Reported sqlite = report(SQLite::Exception("database disk image is malformed", 11));
  EXPECT_EQ(sqlite.status, util::k_exit_internal);
  EXPECT_EQ(sqlite.err, "demsa: internal error: study store (SQLite): database disk image is malformed\n");

  const Reported fork = report(std::system_error(EAGAIN, std::generic_category(), "fork"));
  EXPECT_EQ(fork.status, util::k_exit_internal);
  EXPECT_EQ(fork.err.rfind("demsa: internal error: fork: ", 0), 0u) << fork.err;

  const Reported fs_error = report(std::filesystem::filesystem_error("cannot create directories", "study/analysis",
                                                                     std::make_error_code(std::errc::file_exists)));
  EXPECT_EQ(fs_error.status, util::k_exit_internal);
  EXPECT_NE(fs_error.err.find("study/analysis"), std::string::npos) << fs_error.err;

  // Out of memory names the command that ran out, not the bare what() of std::bad_alloc.
  const Reported memory = report(std::bad_alloc(), "demsa sensitivity");
  EXPECT_EQ(memory.status, util::k_exit_internal);
  EXPECT_EQ(memory.err,
            "demsa: internal error: out of memory while running `demsa sensitivity`: an input asks for more memory "
            "than this machine has\n");

  // A library's own std::invalid_argument is a programming error, not the user's: exit 3.
  const Reported other = report(std::invalid_argument("dir is empty: a study folder is required"));
  EXPECT_EQ(other.status, util::k_exit_internal);
  EXPECT_EQ(other.err, "demsa: internal error: dir is empty: a study folder is required\n");

  const Reported unknown = report(42);
  EXPECT_EQ(unknown.status, util::k_exit_internal);
  EXPECT_EQ(unknown.err.rfind("demsa: internal error: ", 0), 0u) << unknown.err;
}

}  // namespace
}  // namespace demsa::test
