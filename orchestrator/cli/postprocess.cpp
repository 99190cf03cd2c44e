// `demsa postprocess pile DUMP` and `demsa postprocess oedometer PLATEFILE...`: the observables of one case
// (paper §3.3 angle of repose, §4 settlements), as text or JSON. A pile of a case folder is measured with the
// pedestal and the measurement settings its case.json records (cases/case_writer.cpp), as `demsa run` measured it
// (exec/measure.cpp); options given on the command line override them.
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/oedometer/measurement_json.hpp"
#include "orchestrator/experiments/oedometer/oedometer.hpp"
#include "orchestrator/experiments/pile/angle_json.hpp"
#include "orchestrator/experiments/pile/case_angle.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "postprocess/dump.hpp"
#include "postprocess/oedometer.hpp"
#include "postprocess/pile_angle.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace demsa::cli {

using namespace demsa::util;

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

namespace {

/// A dump given directly, or the `pile_final.dump` of a case folder.
fs::path resolve_dump(const std::string& arg, const char* final_name) {
  const fs::path p(arg);
  std::error_code ec;
  if (fs::is_directory(p, ec)) {
    const fs::path dump = p / final_name;
    if (!fs::exists(dump, ec)) throw UserError(arg, 0, fmt::format("case folder has no {}", final_name));
    return dump;
  }
  if (!fs::exists(p, ec)) throw UserError(arg, 0, "no such file or folder");
  return p;
}

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

/// Takes the pile's pedestal and measurement settings from the case.json of the case that holds `dump` (the folder
/// given, or the dump's own folder; experiments::pile::case_angle); command-line options win. Returns the case.json
/// read, or "" when there is none: then the options stand, defaults included, with a warning when the pedestal was
/// not given.
std::string apply_case_settings(const PileArgs& a, const fs::path& dump, pp::PileAngleOptions& options,
                                long& base_particles) {
  const fs::path folder = dump.parent_path().empty() ? fs::path(".") : dump.parent_path();
  const fs::path file = folder / study::k_case_json;
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    if (!given(a.pedestal_radius) || !given(a.pedestal_top))
      log::warn(
          "{}: no {} beside the dump: measured on the pedestal of the options (radius {} m, top at z = {} m); "
          "give --pedestal-radius and --pedestal-top if the pile stood on another",
          dump.string(), study::k_case_json, options.pedestal_radius, options.pedestal_top);
    return {};
  }
  experiments::pile::ChosenAngleOptions chosen;
  chosen.options = options;
  chosen.pedestal_radius = given(a.pedestal_radius);
  chosen.pedestal_top = given(a.pedestal_top);
  chosen.directions = given(a.directions);
  chosen.levels = given(a.levels);
  chosen.estimator = given(a.estimator_option);
  experiments::pile::CaseAngle angle;
  try {
    angle = experiments::pile::case_angle(experiments::read_case_json(folder), file, chosen);
  } catch (const UserError& e) {
    throw UserError(name_options(e.what(), k_pile_option_names));
  }
  options = angle.options;
  base_particles = angle.base_particles;
  try {
    options.validate();
  } catch (const std::invalid_argument& e) {
    throw UserError(file.string(), 0, e.what());
  }
  return file.string();
}

void run_pile(const PileArgs& a) {
  pp::PileAngleOptions options = a.options;
  options.point = pp::boundary_point_kind_from_string(a.point);
  options.estimator = pp::angle_estimator_from_string(a.estimator);
  const fs::path dump = resolve_dump(a.dump, experiments::pile::k_final_dump);
  long base_particles = 0;
  const std::string case_json = apply_case_settings(a, dump, options, base_particles);
  const pp::Particles particles = experiments::pile::without_base(pp::read_particles(dump), base_particles);
  pp::PileAngleResult r;
  try {
    r = pp::measure_pile_angle(particles, options);
  } catch (const pp::InputError& e) {
    throw UserError(dump.string(), 0, e.what());
  }
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

/// True when the file's column header is the `# step ...` of a plate history.
bool looks_like_history(const fs::path& path) {
  const std::string name = path.filename().string();
  if (name.find("history") != std::string::npos) return true;
  if (name.find("states") != std::string::npos) return false;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return false;
  char line[4096];
  bool history = false;
  while (std::fgets(line, sizeof line, f) != nullptr) {
    std::string s(line);
    if (s.rfind("#", 0) != 0) break;
    const std::size_t k = s.find_first_not_of("# \t");
    if (k != std::string::npos && s.compare(k, 5, "step ") == 0) history = true;
  }
  std::fclose(f);
  return history;
}

void run_oedometer(const OedometerArgs& a) {
  std::optional<fs::path> states_file, history_file, dump_file;
  if (!a.dump.empty()) dump_file = resolve_dump(a.dump, experiments::oedometer::k_final_dump);
  for (const std::string& arg : a.files) {
    const fs::path p(arg);
    std::error_code ec;
    if (fs::is_directory(p, ec)) {  // a case folder: its plate files and final dump
      namespace oedometer = experiments::oedometer;
      if (fs::exists(p / oedometer::k_plate_states, ec)) states_file = p / oedometer::k_plate_states;
      if (fs::exists(p / oedometer::k_plate_history, ec)) history_file = p / oedometer::k_plate_history;
      if (!dump_file && fs::exists(p / oedometer::k_final_dump, ec)) dump_file = p / oedometer::k_final_dump;
      if (!states_file && !history_file)
        throw UserError(arg, 0, "case folder has neither plate_states.txt nor plate_history.txt");
      continue;
    }
    if (!fs::exists(p, ec)) throw UserError(arg, 0, "no such file or folder");
    (looks_like_history(p) ? history_file : states_file) = p;
  }
  std::optional<pp::PlateHistory> history;
  if (history_file) history = pp::read_plate_history(*history_file);
  std::vector<pp::PlateState> states;
  if (states_file)
    states = pp::read_plate_states(*states_file);
  else
    states = pp::states_from_history(*history, a.load_tolerance);

  pp::OedometerOptions options = a.options;
  options.measured_settlements = a.measured;
  if (dump_file) options.solid_volume = pp::solid_volume(pp::read_particles(*dump_file, 1));
  validate_command_line(options, {{"box_side", "--box-side"},
                                  {"floor_z", "--floor-z"},
                                  {"measured_settlements", "--measured"},
                                  {"solid_volume", "the solid volume of --dump"}});
  const std::string source = (states_file ? *states_file : *history_file).string();
  pp::OedometerResult r;
  try {
    r = pp::measure_oedometer(states, options, std::move(history));
  } catch (const pp::InputError& e) {
    throw UserError(source, 0, e.what());
  }
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
