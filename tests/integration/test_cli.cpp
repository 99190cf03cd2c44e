// The command line's contract (docs/reference/command-line.md): every subcommand is listed, the version names LIGGGHTS,
// usage errors exit 2.
#include "support/test_support.hpp"

#include <gtest/gtest.h>

namespace demsa::test {
namespace {

TEST(Cli, HelpListsEverySubcommand) {
  const CommandResult r = run_demsa({"--help"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* sub :
       {"run", "status", "case", "analyze", "report", "calibrate", "design", "sensitivity", "postprocess", "compare"}) {
    EXPECT_NE(r.out.find(std::string("\n  ") + sub + " "), std::string::npos) << "missing " << sub << " in\n" << r.out;
  }
}

TEST(Cli, VersionNamesDemsaAndLiggghts) {
  const CommandResult r = run_demsa({"--version"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("demsa 0."), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("LIGGGHTS 3.8.0"), std::string::npos) << r.out;
  // Which LIGGGHTS a study runs, and why.
  EXPECT_NE(r.out.find("which a study runs: the one its [run] liggghts names"), std::string::npos) << r.out;
}

TEST(Cli, VersionSaysWhenLiggghtsIsMissing) {
  const CommandResult r = run_command({"env", "DEMSA_LIGGGHTS=/nonexistent/liggghts", DEMSA_BINARY, "--version"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("LIGGGHTS: not found"), std::string::npos) << r.out;
}

TEST(Cli, UnknownSubcommandIsAUsageError) {
  const CommandResult r = run_demsa({"frobnicate"});
  EXPECT_EQ(r.exit_code, 2);
}

TEST(Cli, NoSubcommandPrintsHelpAndExits2) {
  const CommandResult r = run_demsa({});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("Subcommands"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace demsa::test
