// `demsa predict DIR|MODEL.json --points CSV`: a saved metamodel (analysis/model_file.hpp) evaluated at new points
// given in physical units (analysis/prediction.hpp).
//
// The points file is a CSV table with a header (util/csv.hpp); the model's input columns are found by name, in any
// order; other columns are not read and not copied. The output is a CSV table: the model's inputs (as read), then
// the prediction in a column named after the model's output, then with --std its predictive standard deviation
// (`<output>_sd`, Gaussian process only). A missing input column is an error naming the file and the column; points
// outside the model's bounds are predicted (extrapolation), with a warning that counts them.
//
// For a study folder DIR the model is DIR/analysis/models/<observable>.<metamodel>.json: --observable picks the
// observable (required when the study has several), --model the metamodel (default: the largest leave-one-out Q²
// of DIR/analysis/analysis.json, as the analysis and the calibration choose).
#include "orchestrator/analysis/prediction.hpp"
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/cli/shared.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <memory>
#include <string>

namespace demsa::cli {

using namespace demsa::util;
using namespace demsa::analysis;

namespace {

struct PredictArgs {
  PredictOptions options;
  std::string out;  ///< CSV file ("" or "-": standard output)
};

void run_predict(const PredictArgs& args) {
  const Prediction p =
      with_option_names({{"model", "--model"}, {"observable", "--observable"}, {"standard_deviation", "--std"}},
                        [&] { return predict(args.options); });
  if (args.out.empty() || args.out == "-") {
    fmt::print("{}", prediction_csv(p));
  } else {
    write_file_atomically(args.out, prediction_csv(p));
    fmt::print("{}", prediction_written_text(p, args.out));
  }
}

}  // namespace

void register_predict_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<PredictArgs>();
  CLI::App* sub = app.add_subcommand("predict", "Predict with a saved metamodel at new points in physical units");
  sub->add_option("source", args->options.source, "Study folder (its analysis/models/) or a metamodel file (.json)")
      ->required();
  sub->add_option("--points", args->options.points,
                  "CSV of points: a header naming the model's inputs (other columns are "
                  "ignored), one row per point, physical units")
      ->required();
  sub->add_option("--model", args->options.model,
                  "Metamodel of a study folder (default: the largest leave-one-out Q2); with a file: checked");
  sub->add_option("--observable", args->options.observable,
                  "Observable of a study folder (required when it has several); with a file: checked");
  sub->add_flag("--std", args->options.standard_deviation,
                "Add the predictive standard deviation (<output>_sd; gp only)");
  sub->add_option("-o,--out", args->out, "CSV file to write (default: standard output)");
  sub->callback([args, &state] {
    run_predict(*args);
    state.exit_code = k_exit_ok;
  });
}

}  // namespace demsa::cli
