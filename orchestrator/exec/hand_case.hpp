#pragma once
// One case folder of a study written to be run by hand (`demsa case`; `cd DIR && ./run.sh`): a case of the study by
// its id (a design sample, one added by `demsa extend` or `demsa refine`, or a replicate case, ids as `demsa status`
// prints them), read from the study folder's store or, before the study has a folder, drawn from the study file as
// `demsa run` draws it; or a case at parameter values given by name. A mistake in the options is a util::UserError
// naming the field ("HandCaseOptions.sample 99: no such case ..."), which a command line writes as its option.
#include "orchestrator/cases/case_writer.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace demsa::exec {

struct HandCaseOptions {
  std::filesystem::path study;                         ///< the study file
  std::optional<int> sample;                           ///< a case id of the study; none: `values`
  std::filesystem::path dir;                           ///< the study folder of `sample` ("": the study file's default)
  std::vector<std::pair<std::string, double>> values;  ///< parameter values; those not named take their range's middle
  std::filesystem::path output;                        ///< the case folder ("": case-<K>, or case-set for `values`)
  bool overwrite = false;                              ///< empty a case folder that holds files first
};

struct HandCase {
  cases::CaseSummary summary;
  std::optional<int> sample;  ///< the case id written, if any
};

/// Parameter values as text, "name=value" items separated by commas (one text or several, as a repeated option gives
/// them; empty items are skipped) -> HandCaseOptions::values in the order given. Each value a finite number, each name
/// once; a mistake is a util::UserError naming HandCaseOptions.values and the item.
std::vector<std::pair<std::string, double>> parse_parameter_values(const std::vector<std::string>& texts);

/// Writes the case. run.sh names the LIGGGHTS found for the study's rolling model; one without it is a warning (the
/// case may run elsewhere).
HandCase write_hand_case(const HandCaseOptions& options);

/// {"dir", "sample", "particles", "dt", "rayleigh_time", "dt_source", "final_dump"}, in that order.
nlohmann::ordered_json hand_case_json(const HandCase& written);

/// "wrote DIR (N particles, dt = ... s = ... T_R); run it with: cd DIR && ./run.sh".
std::string hand_case_text(const HandCase& written);

}  // namespace demsa::exec
