// `demsa status` (docs/reference/command-line.md; exec/status.hpp): counts by state, failures with their class, ETA; on
// a SLURM study that no demsa runs, first collects the tasks that have ended.
#include "orchestrator/exec/status.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <memory>
#include <string>

namespace demsa::cli {

using namespace demsa::util;

namespace {

struct StatusArgs {
  std::string dir;
  bool json = false;
};

int do_status(const StatusArgs& args) {
  const exec::StudyStatus status = exec::study_status(args.dir);
  if (args.json)
    fmt::print("{}\n", exec::study_status_json(status).dump(2));
  else
    fmt::print("{}", exec::study_status_text(status));
  return k_exit_ok;
}

}  // namespace

void register_status_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<StatusArgs>();
  CLI::App* status = app.add_subcommand(
      "status", "Counts by state, failures with their class, ETA; on a SLURM study, first collects ended tasks");
  status->add_option("dir", args->dir, "Study folder")->required();
  status->add_flag("--json", args->json, "Machine-readable output");
  status->callback([&state, args] { state.exit_code = do_status(*args); });
}

}  // namespace demsa::cli
