#include "support/synthetic_study.hpp"

#include "support/test_support.hpp"

#include "orchestrator/experiments/registry.hpp"

#include <random>

using namespace demsa::study;

namespace demsa::test {

SyntheticStudy start_synthetic_study(const std::filesystem::path& dir, const std::string& toml, unsigned seed) {
  std::filesystem::create_directories(dir);
  write_file(dir / "study.toml", toml);
  StudyConfig config = experiments::load_study(dir / "study.toml");
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<SampleRow> samples;
  for (int i = 0; i < config.samples; ++i) {
    SampleRow row;
    row.sample = i;
    for (const ParameterRange& p : config.parameters) {
      row.unit.push_back(u(rng));
      row.physical.push_back(sobol::to_physical(row.unit.back(), p.bounds));
    }
    samples.push_back(row);
  }
  Store store((dir / "study.db").string());
  store.initialize(design_hash(config), config.name, samples);
  return {std::move(config), std::move(samples), std::move(store)};
}

void record_every_sample_done(SyntheticStudy& study,
                              const std::function<std::map<std::string, double>(const SampleRow&)>& measure) {
  for (const SampleRow& row : study.samples) {
    RunOutcome done;
    done.exit_code = 0;
    study.store.record_done(study.store.add_run(row.sample, 1), done, measure(row));
  }
}

}  // namespace demsa::test
