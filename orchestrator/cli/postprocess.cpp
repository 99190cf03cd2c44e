// `demsa postprocess NAME ...`: the observables of one case outside a study run, by the tool of the experiment NAME
// (experiments/case_tool.hpp: `demsa postprocess pile DUMP`, `demsa postprocess oedometer PLATEFILE...`), as text or
// JSON. The experiments declare their tools' options; this file turns them into CLI11 options, runs the tool and
// prints what it returns.
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"

#include <fmt/core.h>

#include <memory>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace demsa::cli {

using namespace demsa::util;

namespace {

CLI::Validator validator(const experiments::ToolCheck& check) {
  using K = experiments::ToolCheck::Kind;
  switch (check.kind) {
    case K::positive:
      return positive_number();
    case K::non_negative:
      return non_negative_number();
    case K::range:
      return number_in(check.low, check.high);
    case K::member:
      return CLI::IsMember(check.members);
    case K::none:
      break;
  }
  return {};
}

/// The tool's option as a CLI11 option or flag of `sub`; the names of those given are read back after parsing.
void add_tool_option(CLI::App* sub, const experiments::ToolOption& o, std::vector<CLI::Option*>& added) {
  CLI::Option* option = std::visit(
      [&](auto* target) -> CLI::Option* {
        if constexpr (std::is_same_v<decltype(target), bool*>)
          return sub->add_flag(o.name, *target, o.help);
        else
          return sub->add_option(o.name, *target, o.help);
      },
      o.target);
  if (o.required) option->required();
  if (o.delimiter != '\0') option->delimiter(o.delimiter);
  if (o.check.kind != experiments::ToolCheck::Kind::none) option->check(validator(o.check));
  if (o.show_default) option->capture_default_str();
  added.push_back(option);
}

void register_tool(CLI::App* postprocess, const experiments::Experiment& experiment) {
  std::shared_ptr<experiments::CaseTool> tool = experiment.case_tool.make();
  CLI::App* sub =
      postprocess->add_subcommand(std::string(experiment.name), std::string(experiment.case_tool.description));
  auto added = std::make_shared<std::vector<CLI::Option*>>();
  for (const experiments::ToolOption& o : tool->options()) add_tool_option(sub, o, *added);
  sub->callback([tool, added] {
    std::set<std::string> given;
    for (const CLI::Option* option : *added)
      if (option->count() > 0) given.insert(option->get_name());
    const OptionNames names = tool->message_names();
    fmt::print("{}", with_option_names(names, [&] { return tool->run(given, warnings_with_option_names(names)); }));
  });
}

}  // namespace

void register_postprocess_command(CLI::App& app, CliState& state) {
  (void)state;
  CLI::App* sub = app.add_subcommand("postprocess",
                                     "Observable (pile angle, oedometer settlements) from a dump or "
                                     "plate log");
  sub->require_subcommand(1);
  for (const experiments::Experiment* experiment : experiments::all())
    if (experiment->case_tool.make != nullptr) register_tool(sub, *experiment);
}

}  // namespace demsa::cli
