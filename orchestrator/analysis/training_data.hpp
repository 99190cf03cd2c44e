#pragma once
// The training data of one observable of a study (paper §5): the done samples that measured it, as unit-cube points
// x (the metamodels are fitted on [0,1]^d), physical points and values y. The analysis, the calibration and the
// report's leave-one-out plots all fit to exactly these rows.
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"

#include <Eigen/Dense>

#include <map>
#include <string>
#include <vector>

namespace demsa::analysis {

/// Observables per sample, as study::Store::observables() gives them.
using SampleObservables = std::map<int, std::map<std::string, double>>;

/// One observable's training rows, in the order of the store's samples.
struct TrainingData {
  std::string observable;    ///< its name ("angle", "settlement_2", ...)
  std::vector<int> samples;  ///< the sample of each row (for messages)
  Eigen::MatrixXd unit;      ///< n × d, on [0,1]^d, columns in config.parameters order
  Eigen::MatrixXd physical;  ///< n × d, the same points in physical units
  Eigen::VectorXd y;         ///< n values of the observable (as stored: SI units)
  std::size_t size() const { return samples.size(); }
};

/// The rows of `samples` that have a value of `observable` in `observables` (samples without it, failed or not
/// run, are left out). Each sample row holds one coordinate per entry of config.parameters.
TrainingData training_data(const study::StudyConfig& config, const std::vector<study::SampleRow>& samples,
                           const SampleObservables& observables, const std::string& observable);

/// The same, reading the samples and observables from the study's store.
TrainingData training_data(const study::StudyConfig& config, const study::Store& store, const std::string& observable);

}  // namespace demsa::analysis
