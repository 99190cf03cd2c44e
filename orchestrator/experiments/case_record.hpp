#pragma once
// A case folder's case.json, read back: the one reader of what cases/case_writer.cpp recorded (the experiment, the
// sample, the experiment's schedule and measurement), for the measurement of a finished case, `demsa measure`,
// `demsa postprocess pile CASE`, `demsa compare` and the ParaView files. Values are checked as the study file's rows
// check them: a case.json edited by hand or cut is refused naming the file and the key, never narrowed.
#include "orchestrator/study/settings.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace demsa::experiments {

/// The largest case.json read (one is a few kB).
inline constexpr std::size_t k_max_case_json_bytes = 1 << 20;

/// A dump given directly (`given`), or the final dump `final_name` of the case folder `given` (a measurement of one
/// case outside a study run). Throws util::UserError naming `given` when neither exists.
std::filesystem::path final_dump_path(const std::string& given, std::string_view final_name);

/// CASE/case.json as a JSON object. Throws util::UserError naming the folder when it is not a case folder (no
/// case.json), and naming the file when it cannot be read, is larger than k_max_case_json_bytes, is not valid JSON
/// (a number out of double's range, `1e999`, included) or is not an object.
nlohmann::json read_case_json(const std::filesystem::path& case_dir);

/// A value of case.json at `path` ("pile.pedestal_radius_m"): none when a key on the path is missing. Throws
/// util::UserError "FILE: PATH = VALUE: ..." when it is there but not a finite number, or lies outside [low, high].
std::optional<double> case_number(const nlohmann::json& doc, const std::filesystem::path& file, const std::string& path,
                                  double low, double high);
/// The same against the bounds of the study file's row that wrote the value (the experiment's one range of a
/// setting, shared by its row and this reader): what the study file accepts the measurement reads back.
std::optional<double> case_number(const nlohmann::json& doc, const std::filesystem::path& file, const std::string& path,
                                  const study::SettingBounds& bounds);
/// The same for an integer in [low, high] (a fraction or a number beyond the range is refused, not narrowed).
std::optional<long> case_integer(const nlohmann::json& doc, const std::filesystem::path& file, const std::string& path,
                                 long low, long high);
/// The length of a list at `path` ("pile.history.snapshot_checks"; its elements are PATH.0, PATH.1, ...): 0 when a
/// key on the path is missing. Throws util::UserError when it is there but not a list, or longer than `most`.
std::size_t case_list_size(const nlohmann::json& doc, const std::filesystem::path& file, const std::string& path,
                           std::size_t most);
/// The same for a string.
std::optional<std::string> case_string(const nlohmann::json& doc, const std::filesystem::path& file,
                                       const std::string& path);
/// The experiment a case.json names ("experiment"); throws util::UserError when it names none.
std::string case_experiment(const nlohmann::json& doc, const std::filesystem::path& file);

}  // namespace demsa::experiments
