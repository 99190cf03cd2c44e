// demsa as a library, without its command line: a study's analysis, a calibration on its metamodels and a
// prediction at new points, through the libraries' public headers (analysis/*.hpp) alone. Built with demsa, run by
// tests/integration/test_library_example.cpp on a study made without LIGGGHTS.
//
//   demsa_library_example STUDY_DIR ANGLE POINTS.csv
//
// STUDY_DIR is a study folder with done samples of an observable `angle`; ANGLE the angle to calibrate to [°];
// POINTS.csv the points (the study's parameters as columns, physical units) at which to predict it.
#include "orchestrator/analysis/calibration.hpp"
#include "orchestrator/analysis/prediction.hpp"
#include "orchestrator/analysis/study_analysis.hpp"

#include <fmt/core.h>

#include <cstddef>
#include <cstdlib>
#include <exception>
#include <string>

int main(int argc, char** argv) {
  namespace analysis = demsa::analysis;
  if (argc != 4) {
    fmt::print(stderr, "usage: demsa_library_example STUDY_DIR ANGLE POINTS.csv\n");
    return 2;
  }
  try {
    // The analysis: metamodels of every observable and their Sobol' indices, written to STUDY_DIR/analysis/.
    analysis::AnalyzeOptions analyze;
    analyze.dir = argv[1];
    const analysis::AnalysisSummary summary = analysis::analyze_study(analyze);
    for (const analysis::ObservableAnalysis& o : summary.observables)
      fmt::print("analysed {}: {} samples, {} metamodels\n", o.name, o.samples, o.models.size());

    // The calibration: the parameters whose metamodel prediction of `angle` is ANGLE.
    analysis::CalibrateOptions calibrate;
    calibrate.dir = argv[1];
    analysis::MeasuredTarget angle;
    angle.name = "angle";
    char* end = nullptr;
    angle.value = std::strtod(argv[2], &end);
    if (end == argv[2] || *end != '\0') {
      fmt::print(stderr, "demsa_library_example: ANGLE '{}' is not a number\n", argv[2]);
      return 2;
    }
    calibrate.targets = {angle};
    const analysis::CalibrationOutcome calibrated = analysis::calibrate_study(calibrate);
    for (std::size_t k = 0; k < calibrated.parameters.size(); ++k)
      fmt::print("calibrated {} = {:.6g} in [{:.6g}, {:.6g}]\n", calibrated.parameters[k], calibrated.physical[k],
                 calibrated.low[k], calibrated.high[k]);
    for (const analysis::CalibratedTarget& t : calibrated.targets)
      fmt::print("{} at the optimum {:.6g} (target {:.6g}, metamodel {})\n", t.name, t.predicted, t.target, t.model);

    // The prediction of `angle` at the points, by the metamodel of largest Q².
    analysis::PredictOptions predict;
    predict.source = argv[1];
    predict.points = argv[3];
    predict.observable = "angle";
    const analysis::Prediction predicted = analysis::predict(predict);
    fmt::print("{}", analysis::prediction_csv(predicted));
  } catch (const std::exception& e) {
    fmt::print(stderr, "demsa_library_example: {}\n", e.what());
    return 2;
  }
  return 0;
}
