#include "orchestrator/experiments/case_record.hpp"

#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/setting_row.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"
#include "postprocess/text.hpp"

#include <fmt/core.h>

#include <charconv>

#include <cmath>
#include <fstream>
#include <limits>
#include <vector>

namespace demsa::experiments {

namespace fs = std::filesystem;

std::filesystem::path final_dump_path(const std::string& given, std::string_view final_name) {
  namespace fs = std::filesystem;
  const fs::path p(given);
  std::error_code ec;
  if (fs::is_directory(p, ec)) {
    const fs::path dump = p / final_name;
    if (!fs::exists(dump, ec)) throw util::UserError(given, 0, fmt::format("case folder has no {}", final_name));
    return dump;
  }
  if (!fs::exists(p, ec)) throw util::UserError(given, 0, "no such file or folder");
  return p;
}

nlohmann::json read_case_json(const fs::path& case_dir) {
  const fs::path file = case_dir / study::k_case_json;
  std::error_code ec;
  if (!fs::is_directory(case_dir, ec)) {
    if (!fs::exists(fs::symlink_status(case_dir, ec)))
      throw util::UserError(case_dir.string(), 0, "no such case folder");
    if (const std::optional<std::string> kind = postprocess::special_file_kind(case_dir))
      throw util::UserError(case_dir.string(), 0, postprocess::special_file_message(*kind));
    throw util::UserError(case_dir.string(), 0, "a file, not a case folder");
  }
  if (!fs::exists(file, ec))
    throw util::UserError(case_dir.string(), 0, fmt::format("not a case folder (no {})", study::k_case_json));
  if (const std::optional<std::string> kind = postprocess::special_file_kind(file))
    throw util::UserError(file.string(), 0, postprocess::special_file_message(*kind));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw util::UserError(file.string(), 0, "cannot be read");
  std::string text(k_max_case_json_bytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw util::UserError(file.string(), 0, "cannot be read");
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > k_max_case_json_bytes)
    throw util::UserError(file.string(), 0,
                          fmt::format("larger than {} bytes; a case.json is a few kB", k_max_case_json_bytes));
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw util::UserError(file.string(), 0, fmt::format("not valid JSON: {}", e.what()));
  }
  if (!doc.is_object()) throw util::UserError(file.string(), 0, "not a case description (a JSON object)");
  return doc;
}

namespace {

/// The node at `path` (keys separated by '.'; in a list, a key is the element's index from 0), or nullptr when a key
/// is missing or a step is neither an object nor a list.
const nlohmann::json* find(const nlohmann::json& doc, const std::string& path) {
  const nlohmann::json* node = &doc;
  for (const std::string& key : util::split(path, '.')) {
    if (node->is_array()) {
      std::size_t index = 0;
      const auto [end, ec] = std::from_chars(key.data(), key.data() + key.size(), index);
      if (key.empty() || ec != std::errc{} || end != key.data() + key.size() || index >= node->size()) return nullptr;
      node = &(*node)[index];
      continue;
    }
    if (!node->is_object() || !node->contains(key)) return nullptr;
    node = &(*node)[key];
  }
  return node;
}

}  // namespace

std::size_t case_list_size(const nlohmann::json& doc, const fs::path& file, const std::string& path, std::size_t most) {
  const nlohmann::json* v = find(doc, path);
  if (v == nullptr) return 0;
  if (!v->is_array() || v->size() > most)
    throw util::UserError(file.string(), 0,
                          fmt::format("{} = {}: not a list of at most {} values", path, v->dump().substr(0, 80), most));
  return v->size();
}

std::optional<double> case_number(const nlohmann::json& doc, const fs::path& file, const std::string& path, double low,
                                  double high) {
  const nlohmann::json* v = find(doc, path);
  if (!v) return std::nullopt;
  if (!v->is_number() || !std::isfinite(v->get<double>()))
    throw util::UserError(file.string(), 0, fmt::format("{} = {}: not a finite number", path, v->dump()));
  const double x = v->get<double>();
  if (x < low || x > high)
    throw util::UserError(file.string(), 0, fmt::format("{} = {}: must lie in [{}, {}]", path, v->dump(), low, high));
  return x;
}

std::optional<double> case_number(const nlohmann::json& doc, const fs::path& file, const std::string& path,
                                  const study::SettingBounds& bounds) {
  const std::optional<double> x =
      case_number(doc, file, path, -std::numeric_limits<double>::max(), std::numeric_limits<double>::max());
  if (x && !bounds.contains(*x))
    throw util::UserError(file.string(), 0, fmt::format("{} = {}: {}", path, study::shortest(*x), bounds.rule()));
  return x;
}

std::optional<long> case_integer(const nlohmann::json& doc, const fs::path& file, const std::string& path, long low,
                                 long high) {
  const nlohmann::json* v = find(doc, path);
  if (!v) return std::nullopt;
  // An integer in JSON is one without fraction or exponent; nlohmann keeps it exact (64-bit).
  if (!v->is_number_integer())
    throw util::UserError(file.string(), 0, fmt::format("{} = {}: not an integer", path, v->dump()));
  const bool in_range = v->is_number_unsigned() ? v->get<std::uint64_t>() <= static_cast<std::uint64_t>(high) &&
                                                      static_cast<long long>(v->get<std::uint64_t>()) >= low
                                                : v->get<std::int64_t>() >= low && v->get<std::int64_t>() <= high;
  if (!in_range)
    throw util::UserError(file.string(), 0, fmt::format("{} = {}: must lie in [{}, {}]", path, v->dump(), low, high));
  return static_cast<long>(v->get<std::int64_t>());
}

std::optional<std::string> case_string(const nlohmann::json& doc, const fs::path& file, const std::string& path) {
  const nlohmann::json* v = find(doc, path);
  if (!v) return std::nullopt;
  if (!v->is_string()) throw util::UserError(file.string(), 0, fmt::format("{} = {}: not a string", path, v->dump()));
  return v->get<std::string>();
}

std::string case_experiment(const nlohmann::json& doc, const fs::path& file) {
  const std::optional<std::string> name = case_string(doc, file, "experiment");
  if (!name) throw util::UserError(file.string(), 0, "names no experiment (\"experiment\")");
  return *name;
}

}  // namespace demsa::experiments
