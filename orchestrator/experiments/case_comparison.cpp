#include "orchestrator/experiments/case_comparison.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/dump.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace demsa::experiments {

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

namespace {

/// The experiment that measures an angle of repose on the final dump named `file_name`, or nullptr.
const Experiment* angle_of_final_dump(const std::string& file_name) {
  for (const Experiment* e : all())
    if (e->case_angle != nullptr && e->final_dump == file_name) return e;
  return nullptr;
}

/// The angle of the dump `dump`: its case's own pedestal, measurement and base layer when a case.json of an
/// experiment that measures angles lies beside it (as `demsa postprocess` measures it), else the request's; a pedestal
/// the request chose wins.
CaseAngle angle_of(const CaseComparisonRequest& request, const fs::path& dump) {
  CaseAngle angle{request.options.pile_options};
  const fs::path folder = dump.parent_path().empty() ? fs::path(".") : dump.parent_path();
  const fs::path file = folder / study::k_case_json;
  std::error_code ec;
  if (!fs::exists(file, ec)) return angle;
  const nlohmann::json doc = read_case_json(folder);
  const Experiment* experiment = nullptr;
  if (const std::optional<std::string> name = case_string(doc, file, "experiment")) {
    experiment = find(*name);
  } else {  // a case.json that names no experiment: the measuring experiment's hook refuses it by name
    experiment = angle_of_final_dump(dump.filename().string());
    for (const Experiment* e : all())
      if (experiment == nullptr && e->case_angle != nullptr) experiment = e;
  }
  if (experiment == nullptr || experiment->case_angle == nullptr) return angle;
  ChosenAngleOptions chosen;  // the case's measurement, but for a pedestal chosen by the request
  chosen.pedestal_radius = request.pedestal_radius;
  chosen.pedestal_top = request.pedestal_top;
  chosen.options.pedestal_radius = angle.options.pedestal_radius;
  chosen.options.pedestal_top = angle.options.pedestal_top;
  return experiment->case_angle(doc, file, chosen);
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

nlohmann::json pedestal_json(const CaseAngle& angle) {
  return {{"radius_m", angle.options.pedestal_radius},
          {"top_m", angle.options.pedestal_top},
          {"base_particles", angle.base_particles}};
}

nlohmann::json to_json(const ComparedDumps& c) {
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
                 {"pedestal_a", pedestal_json(c.angle_a)},
                 {"pedestal_b", pedestal_json(c.angle_b)}};
  else
    j["pile"] = nullptr;
  return j;
}

}  // namespace

CaseComparison compare_cases(const CaseComparisonRequest& request) {
  const fs::path a(request.a), b(request.b);
  std::error_code ec;
  for (const fs::path& p : {a, b})
    if (!fs::exists(p, ec)) throw util::UserError(p.string(), 0, "no such file or folder");
  const bool dir_a = fs::is_directory(a, ec), dir_b = fs::is_directory(b, ec);
  if (dir_a != dir_b)
    throw util::UserError(
        fmt::format("compare two dump files or two case folders, not one of each: {} and {}", request.a, request.b));

  std::vector<std::pair<fs::path, fs::path>> pairs;
  if (dir_a) {
    const std::vector<std::string> names = final_dumps(a);
    if (names.empty()) throw util::UserError(request.a, 0, "case folder has no *_final.dump");
    for (const std::string& name : names) {
      if (!fs::exists(b / name, ec))
        throw util::UserError(request.b, 0, fmt::format("case folder has no {} (A has it)", name));
      pairs.emplace_back(a / name, b / name);
    }
  } else {
    pairs.emplace_back(a, b);
  }

  CaseComparison comparison;
  for (const auto& [pa, pb] : pairs) {
    pp::CompareOptions options = request.options;
    if (angle_of_final_dump(pa.filename().string()) != nullptr) options.pile = true;
    CaseAngle angle_a{options.pile_options}, angle_b{options.pile_options};
    if (options.pile) {
      // Each pile on its own case's pedestal: two cases of different studies stand on different ones.
      angle_a = angle_of(request, pa);
      angle_b = angle_of(request, pb);
      options.pile_options = angle_a.options;
      options.pile_options_b = angle_b.options;
    }
    try {
      options.validate();
    } catch (const std::invalid_argument& e) {
      throw util::UserError(e.what());
    }
    // A base layer is not part of the pile: measured with it, its particles would count as the pile's and their zero
    // displacements would dilute the RMS.
    const pp::Particles particles_a = without_base(pp::read_particles(pa), angle_a.base_particles);
    const pp::Particles particles_b = without_base(pp::read_particles(pb), angle_b.base_particles);
    comparison.pairs.push_back(
        {pa, pb, pp::compare_particles(particles_a, particles_b, options, pa.string(), pb.string()), angle_a, angle_b});
    comparison.within_tolerance = comparison.within_tolerance && comparison.pairs.back().result.within_tolerance();
  }
  return comparison;
}

nlohmann::json case_comparison_json(const CaseComparison& comparison) {
  nlohmann::json j = nlohmann::json::array();
  for (const ComparedDumps& c : comparison.pairs) j.push_back(to_json(c));
  return {{"within_tolerance", comparison.within_tolerance}, {"comparisons", j}};
}

std::string case_comparison_text(const CaseComparison& comparison) {
  std::string text;
  for (const ComparedDumps& c : comparison.pairs) {
    const postprocess::DumpComparison& r = c.result;
    text += fmt::format("A {}\nB {}\n", c.a.string(), c.b.string());
    text += fmt::format("  particles            {} in A, {} in B, {} common, {} missing in B, {} extra in B\n",
                        r.particles_a, r.particles_b, r.common, r.missing, r.extra);
    text += fmt::format("  max displacement     {:.6g} m (id {})\n", r.max_displacement, r.max_displacement_id);
    text += fmt::format("  RMS displacement     {:.6g} m\n", r.rms_displacement);
    text += fmt::format("  radius mismatches    {} (largest difference {:.6g} m)\n", r.radius_mismatches,
                        r.max_radius_difference);
    if (r.pile) {
      text += fmt::format("  angle of repose      {:.4f} deg vs {:.4f} deg (difference {:+.4f})\n", r.pile->angle_a,
                          r.pile->angle_b, r.pile->angle_difference);
      text += fmt::format("  pile height h_P      {:.6g} m vs {:.6g} m (difference {:+.6g})\n", r.pile->height_a,
                          r.pile->height_b, r.pile->height_difference);
      text += fmt::format("  pedestals            radius {:g} m, top {:g} m vs radius {:g} m, top {:g} m\n",
                          c.angle_a.options.pedestal_radius, c.angle_a.options.pedestal_top,
                          c.angle_b.options.pedestal_radius, c.angle_b.options.pedestal_top);
      if (c.angle_a.base_particles > 0 || c.angle_b.base_particles > 0)
        text += fmt::format("  base layers          {} vs {} particles, left out (case.json)\n",
                            c.angle_a.base_particles, c.angle_b.base_particles);
    }
    if (r.within_tolerance())
      text += "  within tolerance\n";
    else
      for (const std::string& v : r.violations) text += fmt::format("  BEYOND TOLERANCE: {}\n", v);
  }
  return text;
}

}  // namespace demsa::experiments
