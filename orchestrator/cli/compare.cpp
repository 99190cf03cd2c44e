// `demsa compare A B`: particles of two dumps (or of the `*_final.dump` files of two case folders) matched by id;
// for piles also the angle of repose and h_P, each pile as its case measures it (`demsa postprocess pile CASE`): on
// its own pedestal and without its frozen base layer ([pile] base = "particles"), whose particles leave the counts
// and the displacements too. Exit 0 within tolerance, 1 beyond it (errors: cli.hpp).
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/experiments/case_comparison.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/dump_compare.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <memory>
#include <string>

namespace demsa::cli {

using namespace demsa::util;

namespace pp = demsa::postprocess;

namespace {

struct CompareArgs {
  std::string a, b;
  pp::CompareOptions options;
  bool json = false;
  const CLI::Option* pedestal_radius = nullptr;  ///< given on the command line: overrides the cases' pedestals
  const CLI::Option* pedestal_top = nullptr;
};

int run_compare(const CompareArgs& args) {
  experiments::CaseComparisonRequest request;
  request.a = args.a;
  request.b = args.b;
  request.options = args.options;
  request.pedestal_radius = args.pedestal_radius != nullptr && args.pedestal_radius->count() > 0;
  request.pedestal_top = args.pedestal_top != nullptr && args.pedestal_top->count() > 0;
  const experiments::CaseComparison comparison = with_option_names({{"position_tolerance", "--tol-pos"},
                                                                    {"radius_tolerance", "--tol-radius"},
                                                                    {"angle_tolerance", "--tol-angle"},
                                                                    {"pedestal_radius", "--pedestal-radius"},
                                                                    {"pedestal_top", "--pedestal-top"}},
                                                                   [&] { return experiments::compare_cases(request); });
  if (args.json)
    fmt::print("{}\n", experiments::case_comparison_json(comparison).dump(2));
  else
    fmt::print("{}", experiments::case_comparison_text(comparison));
  return comparison.within_tolerance ? k_exit_ok : k_exit_check_failed;
}

}  // namespace

void register_compare_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<CompareArgs>();
  CLI::App* sub = app.add_subcommand(
      "compare",
      "Compare two dumps or case folders (particles by id; piles also by angle and h_P); exit 1 beyond "
      "tolerance");
  sub->add_option("A", args->a, "Reference dump file or case folder")->required();
  sub->add_option("B", args->b, "Dump file or case folder compared with A")->required();
  sub->add_option("--tol-pos", args->options.position_tolerance,
                  "Largest accepted displacement of a particle, and of h_P [m]")
      ->check(non_negative_number())
      ->capture_default_str();
  sub->add_option("--tol-angle", args->options.angle_tolerance, "Largest accepted angle-of-repose difference [deg]")
      ->check(non_negative_number())
      ->capture_default_str();
  sub->add_option("--tol-radius", args->options.radius_tolerance, "Radius difference that counts as a mismatch [m]")
      ->check(non_negative_number())
      ->capture_default_str();
  sub->add_flag("--pile", args->options.pile,
                "Also compare the angle of repose and h_P (automatic for pile_final.dump)");
  args->pedestal_radius =
      sub->add_option("--pedestal-radius", args->options.pile_options.pedestal_radius,
                      "Pedestal radius for piles [m] (default: each case's own, from its case.json)")
          ->check(positive_number())
          ->capture_default_str();
  args->pedestal_top = sub->add_option("--pedestal-top", args->options.pile_options.pedestal_top,
                                       "z of the pedestal top for piles [m] (default: each case's own)")
                           ->capture_default_str();
  sub->add_flag("--json", args->json, "Print the comparison as JSON");
  sub->callback([args, &state] { state.exit_code = run_compare(*args); });
}

}  // namespace demsa::cli
