// `demsa extend DIR --samples N` (docs/how-to/refine.md): grows a study's design to N points, keeping it space-filling;
// the next `demsa run` runs the new cases (the finished ones are never run again).
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/exec/runner.hpp"

#include <fmt/core.h>

#include <memory>
#include <string>

namespace demsa::cli {

namespace {

struct ExtendArgs {
  std::string dir;
  long samples = 0;
};

int do_extend(const ExtendArgs& args) {
  const exec::Extension extension = with_option_names({{"samples", "--samples"}}, [&] {
    return exec::extend_study({args.dir, static_cast<int>(args.samples)});
  });
  fmt::print("{}", exec::extension_text(extension));
  return 0;
}

}  // namespace

void register_extend_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<ExtendArgs>();
  CLI::App* extend = app.add_subcommand(
      "extend",
      "Grow a study's design to N samples, keeping it space-filling (LHS: maximin extension; Sobol': the "
      "next points of the sequence); finished cases are kept");
  extend->add_option("dir", args->dir, "Study folder")->required();
  extend->add_option("--samples", args->samples, "Design samples after the extension (at least the current number)")
      ->required()
      ->check(integer_in(2, 100000));
  extend->callback([&state, args] { state.exit_code = do_extend(*args); });
}

}  // namespace demsa::cli
