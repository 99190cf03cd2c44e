#include "orchestrator/exec/measure.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"
#include "postprocess/error.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <array>
#include <fstream>

namespace demsa::exec {

std::map<std::string, double> measure_case(const std::filesystem::path& folder) {
  const nlohmann::json doc = experiments::read_case_json(folder);
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
    throw util::UserError(fmt::format("--overlay {}: {}", picture.string(), why));
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

}  // namespace demsa::exec
