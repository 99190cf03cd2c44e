// `demsa compare A B`: particles of two dumps (or of the `*_final.dump` files of two case folders) matched by id;
// for piles also the angle of repose and h_P, each pile as its case measures it (`demsa postprocess pile CASE`): on
// its own pedestal and without its frozen base layer ([pile] base = "particles"), whose particles leave the counts
// and the displacements too. Exit 0 within tolerance, 1 beyond it (errors: cli.hpp).
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/pile/case_angle.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/dump.hpp"
#include "postprocess/dump_compare.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace demsa::cli {

using namespace demsa::util;

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

namespace {

struct CompareArgs {
  std::string a, b;
  pp::CompareOptions options;
  bool json = false;
  const CLI::Option* pedestal_radius = nullptr;  ///< given on the command line: overrides the cases' pedestals
  const CLI::Option* pedestal_top = nullptr;
};

/// How the pile of one dump is measured.
struct CasePile {
  pp::PileAngleOptions options;  ///< the pedestal and the measurement
  long base_particles = 0;       ///< ids 1..base_particles are the case's frozen base layer, left out (0: none)
};

/// The pile of the dump `dump`: its case's own pedestal, measurement and base layer when a case.json of a pile case
/// lies beside it (as `demsa postprocess pile CASE` measures it), else the command line's; a pedestal given on the
/// command line wins.
CasePile pile_of(const CompareArgs& args, const fs::path& dump) {
  CasePile pile{args.options.pile_options};
  const fs::path folder = dump.parent_path().empty() ? fs::path(".") : dump.parent_path();
  const fs::path file = folder / study::k_case_json;
  std::error_code ec;
  if (!fs::exists(file, ec)) return pile;
  const nlohmann::json doc = experiments::read_case_json(folder);
  const std::optional<std::string> name = experiments::case_string(doc, file, "experiment");
  if (name && *name != experiments::pile::experiment().name) return pile;
  experiments::pile::ChosenAngleOptions chosen;  // the case's measurement, but for a pedestal given here
  chosen.pedestal_radius = args.pedestal_radius != nullptr && args.pedestal_radius->count() > 0;
  chosen.pedestal_top = args.pedestal_top != nullptr && args.pedestal_top->count() > 0;
  chosen.options.pedestal_radius = pile.options.pedestal_radius;
  chosen.options.pedestal_top = pile.options.pedestal_top;
  experiments::pile::CaseAngle angle;
  try {
    angle = experiments::pile::case_angle(doc, file, chosen);
  } catch (const UserError& e) {
    throw UserError(
        name_options(e.what(), {{"pedestal_radius", "--pedestal-radius"}, {"pedestal_top", "--pedestal-top"}}));
  }
  pile.options = angle.options;
  pile.base_particles = angle.base_particles;
  return pile;
}

struct ComparedPair {
  fs::path a, b;
  pp::DumpComparison result;
  CasePile pile_a, pile_b;  ///< the pedestals the piles were measured on, and the base layers left out
};

nlohmann::json pedestal_json(const CasePile& pile) {
  return {{"radius_m", pile.options.pedestal_radius},
          {"top_m", pile.options.pedestal_top},
          {"base_particles", pile.base_particles}};
}

nlohmann::json to_json(const ComparedPair& c) {
  const pp::DumpComparison& r = c.result;
  nlohmann::json j = {{"a", c.a.string()},
                      {"b", c.b.string()},
                      {"particles_a", r.particles_a},
                      {"particles_b", r.particles_b},
                      {"common", r.common},
                      {"missing", r.missing},
                      {"extra", r.extra},
                      {"missing_ids", r.missing_ids},
                      {"extra_ids", r.extra_ids},
                      {"max_displacement_m", r.max_displacement},
                      {"max_displacement_id", r.max_displacement_id},
                      {"rms_displacement_m", r.rms_displacement},
                      {"radius_mismatches", r.radius_mismatches},
                      {"radius_mismatch_ids", r.radius_mismatch_ids},
                      {"max_radius_difference_m", r.max_radius_difference},
                      {"tolerance",
                       {{"position_m", r.options.position_tolerance},
                        {"radius_m", r.options.radius_tolerance},
                        {"angle_deg", r.options.angle_tolerance}}},
                      {"within_tolerance", r.within_tolerance()},
                      {"violations", r.violations}};
  if (r.pile)
    j["pile"] = {{"angle_a_deg", r.pile->angle_a},
                 {"angle_b_deg", r.pile->angle_b},
                 {"angle_difference_deg", r.pile->angle_difference},
                 {"height_a_m", r.pile->height_a},
                 {"height_b_m", r.pile->height_b},
                 {"height_difference_m", r.pile->height_difference},
                 {"pedestal_a", pedestal_json(c.pile_a)},
                 {"pedestal_b", pedestal_json(c.pile_b)}};
  else
    j["pile"] = nullptr;
  return j;
}

/// The `*_final.dump` files of a case folder, by name.
std::vector<std::string> final_dumps(const fs::path& dir) {
  std::vector<std::string> names;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name.size() > 11 && name.compare(name.size() - 11, 11, "_final.dump") == 0)
      names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

void print_text(const ComparedPair& c) {
  const pp::DumpComparison& r = c.result;
  fmt::print("A {}\nB {}\n", c.a.string(), c.b.string());
  fmt::print("  particles            {} in A, {} in B, {} common, {} missing in B, {} extra in B\n", r.particles_a,
             r.particles_b, r.common, r.missing, r.extra);
  fmt::print("  max displacement     {:.6g} m (id {})\n", r.max_displacement, r.max_displacement_id);
  fmt::print("  RMS displacement     {:.6g} m\n", r.rms_displacement);
  fmt::print("  radius mismatches    {} (largest difference {:.6g} m)\n", r.radius_mismatches, r.max_radius_difference);
  if (r.pile) {
    fmt::print("  angle of repose      {:.4f} deg vs {:.4f} deg (difference {:+.4f})\n", r.pile->angle_a,
               r.pile->angle_b, r.pile->angle_difference);
    fmt::print("  pile height h_P      {:.6g} m vs {:.6g} m (difference {:+.6g})\n", r.pile->height_a, r.pile->height_b,
               r.pile->height_difference);
    fmt::print("  pedestals            radius {:g} m, top {:g} m vs radius {:g} m, top {:g} m\n",
               c.pile_a.options.pedestal_radius, c.pile_a.options.pedestal_top, c.pile_b.options.pedestal_radius,
               c.pile_b.options.pedestal_top);
    if (c.pile_a.base_particles > 0 || c.pile_b.base_particles > 0)
      fmt::print("  base layers          {} vs {} particles, left out (case.json)\n", c.pile_a.base_particles,
                 c.pile_b.base_particles);
  }
  if (r.within_tolerance())
    fmt::print("  within tolerance\n");
  else
    for (const std::string& v : r.violations) fmt::print("  BEYOND TOLERANCE: {}\n", v);
}

int run_compare(const CompareArgs& args) {
  const fs::path a(args.a), b(args.b);
  std::error_code ec;
  for (const fs::path& p : {a, b})
    if (!fs::exists(p, ec)) throw UserError(p.string(), 0, "no such file or folder");
  const bool dir_a = fs::is_directory(a, ec), dir_b = fs::is_directory(b, ec);
  if (dir_a != dir_b)
    throw UserError(
        fmt::format("compare two dump files or two case folders, not one of each: {} and {}", args.a, args.b));

  std::vector<std::pair<fs::path, fs::path>> pairs;
  if (dir_a) {
    const std::vector<std::string> names = final_dumps(a);
    if (names.empty()) throw UserError(args.a, 0, "case folder has no *_final.dump");
    for (const std::string& name : names) {
      if (!fs::exists(b / name, ec)) throw UserError(args.b, 0, fmt::format("case folder has no {} (A has it)", name));
      pairs.emplace_back(a / name, b / name);
    }
  } else {
    pairs.emplace_back(a, b);
  }

  std::vector<ComparedPair> compared;
  for (const auto& [pa, pb] : pairs) {
    pp::CompareOptions options = args.options;
    if (pa.filename() == "pile_final.dump") options.pile = true;
    CasePile pile_a{options.pile_options}, pile_b{options.pile_options};
    if (options.pile) {
      // Each pile on its own case's pedestal: two cases of different studies stand on different ones.
      pile_a = pile_of(args, pa);
      pile_b = pile_of(args, pb);
      options.pile_options = pile_a.options;
      options.pile_options_b = pile_b.options;
    }
    validate_command_line(options, {{"position_tolerance", "--tol-pos"},
                                    {"radius_tolerance", "--tol-radius"},
                                    {"angle_tolerance", "--tol-angle"},
                                    {"pedestal_radius", "--pedestal-radius"},
                                    {"pedestal_top", "--pedestal-top"}});
    // A frozen base layer is not part of the pile: measured with it, its particles would count as the pile's and
    // their zero displacements would dilute the RMS.
    const pp::Particles particles_a = experiments::pile::without_base(pp::read_particles(pa), pile_a.base_particles);
    const pp::Particles particles_b = experiments::pile::without_base(pp::read_particles(pb), pile_b.base_particles);
    compared.push_back(
        {pa, pb, pp::compare_particles(particles_a, particles_b, options, pa.string(), pb.string()), pile_a, pile_b});
  }
  bool within = true;
  for (const ComparedPair& c : compared) within = within && c.result.within_tolerance();
  if (args.json) {
    nlohmann::json j = nlohmann::json::array();
    for (const ComparedPair& c : compared) j.push_back(to_json(c));
    const nlohmann::json out = {{"within_tolerance", within}, {"comparisons", j}};
    fmt::print("{}\n", out.dump(2));
  } else {
    for (const ComparedPair& c : compared) print_text(c);
  }
  return within ? k_exit_ok : k_exit_check_failed;
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
