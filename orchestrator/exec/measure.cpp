#include "orchestrator/exec/measure.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/error.hpp"

#include <fmt/core.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <fstream>

namespace demsa::exec {

std::map<std::string, double> measure_case(const std::filesystem::path& folder) {
  return measure_case(folder, experiments::read_case_json(folder));
}

std::map<std::string, double> measure_case(const std::filesystem::path& folder, const nlohmann::json& doc) {
  return experiments::of_case(doc, folder / study::k_case_json).measure(folder, doc);
}

CaseMeasurement measure_case_described(const std::filesystem::path& folder) {
  const nlohmann::json doc = experiments::read_case_json(folder);
  const experiments::Experiment& experiment = experiments::of_case(doc, folder / study::k_case_json);
  CaseMeasurement m;
  m.experiment = std::string(experiment.name);
  std::map<std::string, double> values;
  try {
    values = experiment.measure(folder, doc);
  } catch (const postprocess::InputError& e) {
    // What cannot be measured names the case it is about ("no direction has 3 boundary points ...: not a pile"
    // named nothing), unless the message already does.
    const std::string what = e.what();
    if (what.rfind(folder.string(), 0) == 0) throw;
    throw postprocess::InputError(fmt::format("{}: {}", folder.string(), what));
  }
  for (const auto& [name, value] : values) m.values.push_back({experiments::describe_observable(name), value});
  return m;
}

experiments::LabComparison compare_case_with_lab_file(const std::filesystem::path& folder,
                                                      const std::filesystem::path& file,
                                                      std::filesystem::path picture) {
  const nlohmann::json doc = experiments::read_case_json(folder);
  const experiments::Experiment& experiment = experiments::of_case(doc, folder / study::k_case_json);
  const experiments::Experiment* kind = experiments::for_lab_file(file);
  if (!experiment.compare_with_lab_file || kind != &experiment)
    throw util::UserError(fmt::format("{}: not a laboratory file of a {} case (the case {})", file.string(),
                                      experiment.name, folder.string()));
  if (picture.empty()) picture = folder / "lab_overlay.png";
  check_overlay_path(picture, file, folder, experiment);
  return experiment.compare_with_lab_file(folder, doc, file, picture);
}

void check_overlay_path(const std::filesystem::path& picture, const std::filesystem::path& lab_file,
                        const std::filesystem::path& folder, const experiments::Experiment& experiment) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto refuse = [&](const std::string& why) {
    throw util::UserError(fmt::format("MeasureReportOptions.overlay {}: {}", picture.string(), why));
  };
  const fs::path parent = picture.parent_path().empty() ? fs::path(".") : picture.parent_path();
  if (!fs::is_directory(parent, ec)) refuse(fmt::format("its folder {} does not exist", parent.string()));
  if (::access(parent.c_str(), W_OK) != 0) refuse(fmt::format("its folder {} cannot be written", parent.string()));
  const fs::file_status status = fs::symlink_status(picture, ec);
  if (status.type() == fs::file_type::not_found) return;
  if (fs::is_directory(status)) refuse("is a folder: name the PNG file to write");
  if (fs::equivalent(picture, lab_file, ec)) refuse("is the photograph itself, which it would overwrite");
  for (const std::string& output : experiment.run_outputs())
    if (fs::equivalent(picture, folder / output, ec)) refuse(fmt::format("is the case's own {}", output));
  // An existing file is replaced only when it is a PNG (an overlay written before), never a study file, a dump or a
  // photograph of another kind that a typing error names.
  if (!fs::is_regular_file(status)) refuse("exists and is not a regular file");
  std::ifstream in(picture, std::ios::binary);
  std::array<char, 8> head{};
  in.read(head.data(), head.size());
  static constexpr std::array<char, 8> k_png{'\x89', 'P', 'N', 'G', '\r', '\n', '\x1a', '\n'};
  if (in.gcount() != 8 || head != k_png) refuse("exists and is not a PNG: demsa replaces only a PNG there");
}

namespace {

MeasureReport lab_comparison_report(const std::filesystem::path& folder, const std::filesystem::path& photograph,
                                    const std::filesystem::path& overlay) {
  const experiments::LabComparison c = compare_case_with_lab_file(folder, photograph, overlay);
  nlohmann::ordered_json j;
  j["case"] = folder.string();
  j["photograph"] = photograph.string();
  j["mismatch_m2"] = c.mismatch_m2;
  j["region"] = c.region;
  j["overlay"] = c.picture.string();
  MeasureReport r;
  r.json = j.dump(2) + "\n";
  r.text = fmt::format("case {} against {}\n", folder.string(), photograph.string());
  r.text += fmt::format("  mismatch area  {:.1f} mm² {} (where the case and the photograph disagree about material)\n",
                        c.mismatch_m2 * 1e6, c.region);
  r.text += fmt::format("  superimposed   {}\n", c.picture.string());
  return r;
}

MeasureReport lab_file_report(const std::filesystem::path& file, const experiments::Experiment& e) {
  const experiments::LabMeasurement m = e.measure_lab_file(file);
  nlohmann::ordered_json j;
  j["file"] = file.string();
  j["experiment"] = std::string(e.name);
  nlohmann::ordered_json values = nlohmann::ordered_json::object();
  nlohmann::ordered_json units = nlohmann::ordered_json::object();
  nlohmann::ordered_json uncertainty = nlohmann::ordered_json::object();
  for (const experiments::LabValue& v : m.values) {
    values[v.name] = v.value;
    units[v.name] = experiments::describe_observable(v.name).stored_unit;
    if (v.uncertainty) uncertainty[v.name] = *v.uncertainty;
  }
  j["observables"] = values;
  j["units"] = units;
  j["uncertainty"] = uncertainty;
  j["notes"] = m.notes;
  MeasureReport r;
  r.json = j.dump(2) + "\n";
  r.text = fmt::format("file {} ({})\n", file.string(), e.name);
  std::size_t width = 0;
  for (const experiments::LabValue& v : m.values) width = std::max(width, v.name.size());
  for (const experiments::LabValue& v : m.values) {
    const study::Observable o = experiments::describe_observable(v.name);
    const std::string band = v.uncertainty ? fmt::format("± {:<10.3g}", *v.uncertainty) : std::string(12, ' ');
    r.text += fmt::format("  {:<{}}  {:>14.8g} {} {:<3}  {}\n", v.name, width, v.value, band, o.stored_unit, o.label);
  }
  for (const std::string& note : m.notes) r.text += fmt::format("  ({})\n", note);
  return r;
}

}  // namespace

MeasureReport measure_report(const MeasureReportOptions& options) {
  const std::filesystem::path& path = options.path;
  if (!options.lab_file.empty()) return lab_comparison_report(path, options.lab_file, options.overlay);
  if (std::filesystem::is_regular_file(path)) {
    const experiments::Experiment* e = experiments::for_lab_file(path);
    if (!e)
      throw util::UserError(
          fmt::format("{}: not a case folder, and no experiment measures files of this kind", path.string()));
    return lab_file_report(path, *e);
  }
  const CaseMeasurement m = measure_case_described(path);
  nlohmann::ordered_json j;
  j["case"] = path.string();
  j["experiment"] = m.experiment;
  nlohmann::ordered_json values = nlohmann::ordered_json::object();
  nlohmann::ordered_json units = nlohmann::ordered_json::object();
  for (const MeasuredValue& v : m.values) {
    values[v.observable.name] = v.value;
    units[v.observable.name] = v.observable.stored_unit;
  }
  j["observables"] = values;
  j["units"] = units;
  MeasureReport r;
  r.json = j.dump(2) + "\n";
  r.text = fmt::format("case {} ({})\n", path.string(), m.experiment);
  std::size_t width = 0;
  for (const MeasuredValue& v : m.values) width = std::max(width, v.observable.name.size());
  for (const MeasuredValue& v : m.values)
    r.text += fmt::format("  {:<{}}  {:>14.8g} {:<3}  {}\n", v.observable.name, width, v.value,
                          v.observable.stored_unit, v.observable.label);
  return r;
}

}  // namespace demsa::exec
