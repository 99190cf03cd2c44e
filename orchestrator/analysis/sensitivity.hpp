#pragma once
// Sobol' indices of any simulator from CSV files (`demsa sensitivity`; docs/reference/command-line.md; paper §5–6), two
// ways:
//   saltelli_sensitivity: outputs evaluated outside on a Saltelli design (saltelli_design_file.hpp), intervals from
//                         the design's independently scrambled replicates (or a bootstrap of its rows, or none);
//   data_sensitivity:     samples the user already has: metamodels fitted on the unit cube (scaled by the given
//                         bounds or by the data's range), indices of each, each model optionally saved as a file
//                         (model_file.hpp), and with a CSV of repeated runs each response's noise (the study
//                         analysis's NoiseAnalysis) setting the GP's nugget.
// Every input error is a util::UserError naming the user's file, line, column and value; a mistake in the options
// names the field ("DataSensitivityOptions.bounds"), which a command line writes as its own option
// (cli::name_options). A constant output (up to round-off) is an error on both paths, and no NaN index is returned.
// The long loops poll `should_stop` and throw sobol::Stopped when it returns true, before anything is written.
#include "orchestrator/analysis/analysis_json.hpp"
#include "sobol/metamodel.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/saltelli.hpp"
#include "sobol/scaling.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace demsa::analysis {

/// Where the library's warnings go (a line without "warning:"); empty: util::log::warn.
using WarningSink = std::function<void(const std::string&)>;

/// Gives `message` to `sink`, or to util::log::warn when the sink is empty.
void emit_warning(const WarningSink& sink, const std::string& message);

// ---------------------------------------------------------------- Saltelli design and its responses

struct SaltelliResponseIndices {
  std::string response;        ///< column name
  sobol::SobolResult indices;  ///< finite (checked)
  /// Not empty when an index's whole interval lies outside [0, 1]: the responses most likely do not belong to the
  /// design's rows (also given to the warning sink).
  std::string warning;
};

struct SaltelliSensitivityOptions {
  std::string design;          ///< the Saltelli design's CSV (`demsa design saltelli`), as named in messages
  std::string responses_file;  ///< CSV of responses, one row per design row; "": response columns of `design`
  /// The responses analysed: columns of `responses_file` (empty: all of them), or the response columns appended
  /// to the design (then at least one).
  std::vector<std::string> responses;
  sobol::SobolOptions indices;  ///< estimator, interval, bootstrap, confidence, seed and stop check
  /// Where the result's JSON (saltelli_sensitivity_json) is written, atomically, once every response is done; "":
  /// nowhere.
  std::string json_file;
  WarningSink warn;  ///< empty: util::log::warn
  /// Called with the design's parameter names and each response's indices once computed (the text output follows
  /// the computation).
  std::function<void(const std::vector<std::string>& inputs, const SaltelliResponseIndices&)> on_response;
};

struct SaltelliSensitivity {
  std::string design;                            ///< SaltelliSensitivityOptions::design
  std::string responses_file;                    ///< the file the responses came from (the design when appended)
  std::vector<std::string> inputs;               ///< the design's parameter columns, in file order
  std::vector<SaltelliResponseIndices> outputs;  ///< one per response, in the order asked
};

SaltelliSensitivity saltelli_sensitivity(const SaltelliSensitivityOptions& options);

/// {"design", "responses", "inputs", "outputs": [sobol_json's result + "output" (+ "warning")]}. An index without an
/// interval (one scrambled design, or none asked for) has null "lower" and "upper", as the text shows none.
nlohmann::json saltelli_sensitivity_json(const SaltelliSensitivity& result);

/// The indices of one response as `demsa sensitivity` prints them: S1 and ST of each input (`names`) with their
/// intervals, the residual 1 - sum S1, the S2 pairs, and how the intervals were made.
std::string sobol_indices_text(const sobol::SobolResult& result, const std::vector<std::string>& names);

/// One response of a Saltelli design in words: "NAME: Sobol' indices from a Saltelli design, N = ..., K evaluations"
/// and its indices (sobol_indices_text).
std::string saltelli_response_text(const SaltelliResponseIndices& response, const std::vector<std::string>& inputs);

// ---------------------------------------------------------------- samples and responses: metamodels, then indices

/// The least share of an input's bounds (on its scale) the samples must span unless
/// DataSensitivityOptions::allow_extrapolation: below it the metamodels extrapolate over most of the box, and the
/// indices, integrals over the whole box, describe the extrapolation.
inline constexpr double k_min_coverage = 0.5;

struct DataModelIndices {
  std::string metamodel;            ///< sobol::to_string of its kind
  sobol::MetamodelSummary quality;  ///< R², adjusted R², Q² (leave-one-out), ...
  sobol::SobolResult indices;       ///< finite (checked)
  std::string saved_to;             ///< the model file ("" without DataSensitivityOptions::save_model)
};

struct DataSensitivityOptions {
  std::string data;                             ///< CSV of samples: input and response columns, as named in messages
  std::vector<std::string> inputs;              ///< input columns, at least one, distinct
  std::vector<std::string> responses;           ///< response columns, at least one, none of them an input
  std::map<std::string, sobol::Bounds> bounds;  ///< per input; an input without one: the data's range
  bool allow_extrapolation = false;  ///< proceed (with a warning) when the data cover less than k_min_coverage
  std::vector<sobol::MetamodelKind> metamodels;  ///< at least one
  sobol::MetamodelOptions models;                ///< kernel, trend, nugget and seed of the metamodels
  sobol::MetamodelSobolOptions indices;  ///< base (a power of two, else rounded up with a warning), bootstrap, ...
  /// CSV of repeated runs (column `point` labelling the runs of one input point, and the response columns): each
  /// response's noise variance pooled within points sets the GP's nugget; "": none.
  std::string repeats;
  /// Where each fitted model is written (model_file.hpp): a .json file for one model, else a folder of
  /// <response>.<metamodel>.json; "": nowhere. Written once every model is fitted.
  std::string save_model;
  /// Where the result's JSON (data_sensitivity_json) is written, atomically, once every model is done; "": nowhere.
  std::string json_file;
  WarningSink warn;  ///< empty: util::log::warn
  /// Called with each fitted model and its indices once computed.
  std::function<void(const std::string& response, const DataModelIndices&)> on_model;
  /// Called with each response's noise once its models are fitted (only with `repeats`).
  std::function<void(const NoiseAnalysis&)> on_noise;
};

struct DataResponseIndices {
  std::string response;
  std::vector<DataModelIndices> models;  ///< in the order of DataSensitivityOptions::metamodels
  std::optional<NoiseAnalysis> noise;    ///< with DataSensitivityOptions::repeats
};

struct DataSensitivity {
  std::string data;  ///< DataSensitivityOptions::data
  int samples = 0;   ///< rows of the data
  std::vector<std::string> inputs;
  std::vector<sobol::Bounds> bounds;  ///< per input: given, or the data's range
  std::vector<double> coverage;       ///< per input: the share of its bounds the samples span (on its scale)
  std::vector<DataResponseIndices> outputs;
  std::vector<std::string> model_files;  ///< written, in order
};

DataSensitivity data_sensitivity(const DataSensitivityOptions& options);

/// One fitted model in words: "RESPONSE ~ METAMODEL: R2 ..., adjusted R2 ..., Q2_LOO ... (N samples)" and its indices.
std::string data_model_text(const std::string& response, const DataModelIndices& model,
                            const std::vector<std::string>& inputs);

/// {"data", "samples", "inputs", "bounds": [{"input", "low", "high", "scale", "coverage", "extrapolated"}],
/// "outputs": [{"output", "metamodels": [{"metamodel", "quality", "sobol"}], "noise"?}]}.
nlohmann::json data_sensitivity_json(const DataSensitivity& result);

}  // namespace demsa::analysis
