// `demsa postprocess pile DUMP` and `demsa postprocess oedometer PLATEFILE...`: the observables of one case
// (paper §3.3 angle of repose, §4 settlements), as text or JSON. A pile of a case folder is measured with the
// pedestal and the measurement settings its case.json records (cases/case_writer.cpp), as `demsa run` measured it
// (exec/measure.cpp); options given on the command line override them.
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/experiments/oedometer/measurement_json.hpp"
#include "orchestrator/experiments/oedometer/plate_files.hpp"
#include "orchestrator/experiments/pile/angle_json.hpp"
#include "orchestrator/experiments/pile/dump_angle.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "postprocess/oedometer.hpp"
#include "postprocess/pile_angle.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace demsa::cli {

using namespace demsa::util;

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

namespace {

struct PileArgs {
  std::string dump;
  pp::PileAngleOptions options;
  std::string point = "centre";
  std::string estimator = "paper";
  bool json = false;
  // Given on the command line (then they override the case's case.json).
  const CLI::Option* pedestal_radius = nullptr;
  const CLI::Option* pedestal_top = nullptr;
  const CLI::Option* directions = nullptr;
  const CLI::Option* levels = nullptr;
  const CLI::Option* estimator_option = nullptr;
  const CLI::Option* level_low = nullptr;
  const CLI::Option* level_high = nullptr;
  double level_low_value = pp::k_paper_level_low;    ///< --level-low
  double level_high_value = pp::k_paper_level_high;  ///< --level-high
};

bool given(const CLI::Option* option) { return option != nullptr && option->count() > 0; }

/// The option of each field of postprocess::PileAngleOptions.
const OptionNames k_pile_option_names{{"pedestal_radius", "--pedestal-radius"},
                                      {"pedestal_top", "--pedestal-top"},
                                      {"axis_x", "--axis-x"},
                                      {"axis_y", "--axis-y"},
                                      {"particle_type", "--type"},
                                      {"directions", "--directions"},
                                      {"levels", "--levels"},
                                      {"level_low", "--level-low"},
                                      {"level_high", "--level-high"},
                                      {"min_points", "--min-points"},
                                      {"target_angle", "--target-angle"}};

/// Runs a library call with its messages naming the options rather than the fields.
template <typename Call>
auto with_option_names(const OptionNames& names, Call&& call) {
  try {
    return call();
  } catch (const UserError& e) {
    throw UserError(name_options(e.what(), names));
  }
}

void run_pile(const PileArgs& a) {
  experiments::pile::DumpAngleRequest request;
  request.dump = a.dump;
  request.chosen.options = a.options;
  request.chosen.options.point = pp::boundary_point_kind_from_string(a.point);
  request.chosen.options.estimator = pp::angle_estimator_from_string(a.estimator);
  request.chosen.pedestal_radius = given(a.pedestal_radius);
  request.chosen.pedestal_top = given(a.pedestal_top);
  request.chosen.directions = given(a.directions);
  request.chosen.levels = given(a.levels);
  request.chosen.estimator = given(a.estimator_option);
  request.warn = [](const std::string& message) { log::warn("{}", name_options(message, k_pile_option_names)); };
  const experiments::pile::DumpAngle measured =
      with_option_names(k_pile_option_names, [&] { return experiments::pile::measure_dump_angle(request); });
  const pp::PileAngleResult& r = measured.result;
  const pp::PileAngleOptions& options = measured.options;
  const fs::path& dump = measured.dump;
  const std::string& case_json = measured.case_json;
  if (a.json) {
    fmt::print("{}\n", experiments::pile::angle_result_json(r, dump.string(), case_json).dump(2));
    return;
  }
  fmt::print("dump                   {}\n", dump.string());
  fmt::print("pedestal               radius {:.6g} m, top at z = {:.6g} m ({})\n", options.pedestal_radius,
             options.pedestal_top, case_json.empty() ? std::string("options") : case_json);
  fmt::print("estimator              {}\n", pp::to_string(options.estimator));
  fmt::print("particles on pedestal  {} of {}\n", r.particles_on_pedestal, r.particles_total);
  fmt::print("pile height h_P        {:.6g} m\n", r.pile_height);
  fmt::print("levels                 {} between {:.4g} m and {:.4g} m above the pedestal top\n", r.level_heights.size(),
             r.level_heights.front(), r.level_heights.back());
  fmt::print("directions used        {} of {}\n", r.directions_used, options.directions);
  fmt::print("angle of repose        {:.3f} deg (sd {:.3f}, range {:.3f} .. {:.3f})\n", r.angle, r.angle_sd,
             r.angle_min, r.angle_max);
  fmt::print("E_phi vs {:.4g} deg     {:.4f} deg^2\n", options.target_angle, r.angle_error);
}

struct OedometerArgs {
  std::vector<std::string> files;
  std::vector<double> measured;
  pp::OedometerOptions options;
  std::string dump;
  double load_tolerance = 0.03;
  bool json = false;
};

void run_oedometer(const OedometerArgs& a) {
  experiments::oedometer::PlateFilesRequest request;
  request.files = a.files;
  request.dump = a.dump;
  request.options = a.options;
  request.options.measured_settlements = a.measured;
  request.load_tolerance = a.load_tolerance;
  const experiments::oedometer::PlateFiles measured =
      with_option_names({{"box_side", "--box-side"},
                         {"floor_z", "--floor-z"},
                         {"measured_settlements", "--measured"},
                         {"solid_volume", "the solid volume of --dump"}},
                        [&] { return experiments::oedometer::measure_plate_files(request); });
  const pp::OedometerResult& r = measured.result;
  const std::optional<fs::path>& states_file = measured.states_file;
  const std::optional<fs::path>& dump_file = measured.dump_file;
  const std::string& source = measured.source;
  if (a.json) {
    nlohmann::json j = experiments::oedometer::measurement_json(r);
    j["states_file"] = states_file ? nlohmann::json(states_file->string()) : nlohmann::json(nullptr);
    j["dump"] = dump_file ? nlohmann::json(dump_file->string()) : nlohmann::json(nullptr);
    fmt::print("{}\n", j.dump(2));
    return;
  }
  fmt::print("load states from {}\n", source);
  fmt::print("{:>10} {:>14} {:>12} {:>14} {:>12} {:>10} {}\n", "load_N", "plate_z_m", "force_N", "settlement_m",
             "stress_Pa", "void_ratio", "converged");
  for (const pp::OedometerStep& s : r.steps)
    fmt::print("{:>10.6g} {:>14.8g} {:>12.6g} {:>14.6g} {:>12.6g} {:>10} {}\n", s.load_N, s.plate_z_m, s.force_N,
               s.settlement_m, s.stress_Pa, s.void_ratio ? fmt::format("{:.4f}", *s.void_ratio) : std::string("-"),
               s.converged ? "yes" : "NO");
  if (r.settlement_error) fmt::print("E_0 = {:.6g} m\n", *r.settlement_error);
  if (r.history && !r.history->accepted.empty())
    fmt::print("trial steps: {} accepted, {} rejected\n", r.trials_accepted, r.trials_rejected);
  if (!r.all_converged) fmt::print("warning: not every load step converged\n");
}

}  // namespace

void register_postprocess_command(CLI::App& app, CliState& state) {
  (void)state;
  CLI::App* sub = app.add_subcommand("postprocess",
                                     "Observable (pile angle, oedometer settlements) from a dump or "
                                     "plate log");
  sub->require_subcommand(1);

  auto pile = std::make_shared<PileArgs>();
  CLI::App* p = sub->add_subcommand("pile", "Angle of repose and pile height of a pile dump (paper §3.3)");
  p->add_option("DUMP", pile->dump,
                "Final pile dump, or a case folder holding pile_final.dump; a case.json beside the dump gives the "
                "pedestal and the measurement settings of the case")
      ->required();
  pile->pedestal_radius = p->add_option("--pedestal-radius", pile->options.pedestal_radius,
                                        "Pedestal radius r_cy [m] (default: the case's case.json, else this value)")
                              ->check(positive_number())
                              ->capture_default_str();
  pile->pedestal_top = p->add_option("--pedestal-top", pile->options.pedestal_top,
                                     "z of the pedestal top [m] (default: the case's case.json, else this value)")
                           ->capture_default_str();
  p->add_option("--axis-x", pile->options.axis_x, "x of the pile axis [m]")->capture_default_str();
  p->add_option("--axis-y", pile->options.axis_y, "y of the pile axis [m]")->capture_default_str();
  p->add_option("--type", pile->options.particle_type, "Atom type of the particles (0 = all atoms)")
      ->check(non_negative_number())
      ->capture_default_str();
  pile->directions = p->add_option("--directions", pile->options.directions,
                                   "Number of directions phi_N (default: the case's case.json, else this value)")
                         ->check(number_in(1, 100000))
                         ->capture_default_str();
  pile->levels = p->add_option("--levels", pile->options.levels,
                               "Number of height levels between --level-low and --level-high (default: the case's "
                               "case.json, else this value)")
                     ->check(number_in(2, 100000))
                     ->capture_default_str();
  pile->level_low = p->add_option("--level-low", pile->level_low_value,
                                  fmt::format("Lowest level as a fraction of h_P (default: {} for --estimator robust)",
                                              pp::k_robust_level_low))
                        ->check(number_in(0.0, 1.0))
                        ->capture_default_str();
  pile->level_high =
      p->add_option("--level-high", pile->level_high_value,
                    fmt::format("Highest level as a fraction of h_P (default: {} for --estimator robust)",
                                pp::k_robust_level_high))
          ->check(number_in(0.0, 1.0))
          ->capture_default_str();
  p->add_option("--min-points", pile->options.min_points, "Directions with fewer boundary points are skipped")
      ->check(number_in(2, 100000))
      ->capture_default_str();
  p->add_option("--point", pile->point, "Fitted point of a boundary particle: centre or surface")
      ->check(CLI::IsMember({"surface", "centre", "center"}))
      ->capture_default_str();
  pile->estimator_option =
      p->add_option("--estimator", pile->estimator,
                    "Angle estimator: paper (§3.3) or robust (Theil-Sen lines on surface points; default: the "
                    "case's case.json, else this value)")
          ->check(CLI::IsMember(pp::angle_estimator_names()))
          ->capture_default_str();
  p->add_option("--target-angle", pile->options.target_angle, "Target angle for E_phi [deg]")->capture_default_str();
  p->add_flag("--json", pile->json, "Print the whole result (lines and boundary particles included) as JSON");
  p->callback([pile] {
    // Levels on the command line hold for either estimator (an end not given at its default, the paper's); without
    // them each estimator measures on its own band (PileAngleOptions leaves them unset).
    if (given(pile->level_low) || given(pile->level_high)) {
      pile->options.level_low = pile->level_low_value;
      pile->options.level_high = pile->level_high_value;
    }
    validate_command_line(pile->options, k_pile_option_names);
    run_pile(*pile);
  });

  auto oedo = std::make_shared<OedometerArgs>();
  CLI::App* o =
      sub->add_subcommand("oedometer", "Settlements, stress, void ratio and E_0 from the plate files (paper §4)");
  o->add_option("PLATEFILE", oedo->files, "plate_states.txt and/or plate_history.txt, or a case folder holding them")
      ->required();
  o->add_option("--measured", oedo->measured,
                "Measured settlements [m] for the loads after the first (comma- or space-separated)")
      ->delimiter(',');
  o->add_option("--box-side", oedo->options.box_side, "Inner side of the square box [m]")
      ->check(positive_number())
      ->capture_default_str();
  o->add_option("--floor-z", oedo->options.floor_z, "z of the box floor [m]")->capture_default_str();
  o->add_option("--dump", oedo->dump, "Dump whose type-1 particles give the solid volume for the void ratio");
  o->add_option("--load-tolerance", oedo->load_tolerance,
                "Without plate_states.txt: |force - load| that counts as converged [N]")
      ->check(non_negative_number())
      ->capture_default_str();
  o->add_flag("--json", oedo->json, "Print the result (with the plate history) as JSON");
  o->callback([oedo] { run_oedometer(*oedo); });
}

}  // namespace demsa::cli
