#pragma once
// `demsa predict` (docs/reference/command-line.md): a saved metamodel (model_file.hpp) evaluated at new points given in
// physical units.
//
// The points file is a CSV table with a header (util/csv.hpp); the model's input columns are found by name, in any
// order; other columns are not read. For a study folder the model is DIR/analysis/models/<observable>.<metamodel>.json:
// PredictOptions::observable picks the observable (required when the study has several), ::model the metamodel
// (default: the largest leave-one-out Q² of DIR/analysis/analysis.json, as the analysis and the calibration choose).
// Points outside the model's bounds are predicted (extrapolation), with a warning that counts them. Every input error
// is a util::UserError naming the file, line and column; a mistake in the options names the field
// ("PredictOptions.model"), which a command line writes as its own option (cli::name_options).
#include <Eigen/Dense>

#include <filesystem>
#include <string>
#include <vector>

namespace demsa::analysis {

struct PredictOptions {
  std::string source;      ///< a study folder (its analysis's saved models) or a model file, as named in messages
  std::string points;      ///< CSV of points in physical units
  std::string model;       ///< metamodel kind: of a study folder, which one ("": the largest Q²); of a file, checked
  std::string observable;  ///< of a study folder, which one ("": its only one); of a file, checked
  bool standard_deviation = false;  ///< also the predictive standard deviation (a gp metamodel only)
};

struct Prediction {
  std::filesystem::path model_file;  ///< the model file used
  std::string metamodel;             ///< its kind
  std::vector<std::string> inputs;   ///< the model's inputs, in its order
  std::string output;                ///< the modelled output
  Eigen::MatrixXd physical;          ///< the points (rows) as read, in the model's input order
  Eigen::VectorXd mean;              ///< the prediction at each point
  Eigen::VectorXd sd;                ///< its predictive standard deviation (empty unless asked)
  long outside = 0;                  ///< points outside the model's bounds (extrapolated)
};

Prediction predict(const PredictOptions& options);

/// The output CSV: the inputs, the prediction in a column named after the output, and `<output>_sd` when asked.
std::string prediction_csv(const Prediction& prediction);

/// "N predictions of 'OUTPUT' by METAMODEL (MODEL FILE) written to FILE": the CSV written to `file`.
std::string prediction_written_text(const Prediction& prediction, const std::string& file);

}  // namespace demsa::analysis
