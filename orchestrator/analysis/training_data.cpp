#include "orchestrator/analysis/training_data.hpp"

namespace demsa::analysis {

TrainingData training_data(const study::StudyConfig& config, const std::vector<study::SampleRow>& samples,
                           const SampleObservables& observables, const std::string& observable) {
  std::vector<const study::SampleRow*> rows;
  for (const study::SampleRow& s : samples) {
    const auto it = observables.find(s.sample);
    if (it != observables.end() && it->second.count(observable)) rows.push_back(&s);
  }
  const auto n = static_cast<Eigen::Index>(rows.size());
  const auto d = static_cast<Eigen::Index>(config.parameters.size());
  TrainingData data{observable, {}, Eigen::MatrixXd(n, d), Eigen::MatrixXd(n, d), Eigen::VectorXd(n)};
  for (Eigen::Index i = 0; i < n; ++i) {
    const study::SampleRow& row = *rows[static_cast<std::size_t>(i)];
    data.samples.push_back(row.sample);
    for (Eigen::Index j = 0; j < d; ++j) {
      data.unit(i, j) = row.unit.at(static_cast<std::size_t>(j));
      data.physical(i, j) = row.physical.at(static_cast<std::size_t>(j));
    }
    data.y(i) = observables.at(row.sample).at(observable);
  }
  return data;
}

TrainingData training_data(const study::StudyConfig& config, const study::Store& store, const std::string& observable) {
  return training_data(config, store.samples(), store.observables(), observable);
}

}  // namespace demsa::analysis
