// The report options of a run beside the run's own (exec/run_report.hpp, RunReportOptions::validate): JSON and the
// probe only with a dry run, a dry run never with submit_only, a study file that exists; each refusal names the
// fields.
#include "orchestrator/exec/run_report.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace demsa::exec;
using demsa::util::UserError;

namespace demsa::test {
namespace {

RunOptions run_of(const std::filesystem::path& study, bool dry_run, bool submit_only) {
  RunOptions run;
  run.study_file = study;
  run.dry_run = dry_run;
  run.submit_only = submit_only;
  return run;
}

TEST(RunReportOptions, RefusedCombinationsNameTheFields) {
  const TempDir tmp;
  const std::filesystem::path study = tmp.path() / "study.toml";
  std::ofstream(study) << "";
  EXPECT_EQ(message_of<UserError>([&] { RunReportOptions{}.validate(run_of(study, true, true)); }),
            "RunOptions.submit_only and RunOptions.dry_run: a dry run submits nothing; use one of them");
  EXPECT_EQ(message_of<UserError>([&] {
              RunReportOptions{true, 0.0}.validate(run_of(study, false, false));
            }),
            "RunReportOptions.json goes with RunOptions.dry_run: the estimate of a study as JSON");
  EXPECT_EQ(message_of<UserError>([&] {
              RunReportOptions{false, 5.0}.validate(run_of(study, false, false));
            }),
            "RunReportOptions.probe goes with RunOptions.dry_run: a short run of the first case that measures the "
            "study's own rate");
  EXPECT_EQ(message_of<UserError>([&] { RunReportOptions{}.validate(run_of(tmp.path() / "no.toml", false, false)); }),
            (tmp.path() / "no.toml").string() + ": no such study file");
  EXPECT_NO_THROW(RunReportOptions{}.validate(run_of(study, false, false)));
  EXPECT_NO_THROW(RunReportOptions{}.validate(run_of(study, false, true)));
  EXPECT_NO_THROW((RunReportOptions{true, 5.0}.validate(run_of(study, true, false))));
}

TEST(RunReportOptions, AProbeTooShortToMeasureIsRefused) {
  const TempDir tmp;
  const std::filesystem::path study = tmp.path() / "study.toml";
  std::ofstream(study) << "";
  EXPECT_THROW(RunReportOptions({false, 1e-6}).validate(run_of(study, true, false)), UserError);
}

}  // namespace
}  // namespace demsa::test
