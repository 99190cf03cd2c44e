#pragma once
// Study folders made without running a case: the study file, its design at random points and the store, so that
// analysis, calibration and report can be tested on observables that are known functions of the parameters.
// Linked only by the test modules that link the orchestrator.
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace demsa::test {

struct SyntheticStudy {
  study::StudyConfig config;              ///< the study file as loaded
  std::vector<study::SampleRow> samples;  ///< `config.samples` rows at random points of the unit cube
  study::Store store;                     ///< DIR/study.db, initialised with `samples`; no run recorded yet
};

/// Writes DIR/study.toml (`toml`), draws the design at uniform random points of the unit cube (std::mt19937(seed),
/// one draw per parameter, sample after sample) and initialises DIR/study.db with it.
SyntheticStudy start_synthetic_study(const std::filesystem::path& dir, const std::string& toml, unsigned seed);

/// Records one done run (attempt 1, exit 0) for every sample of `study`, with the observables `measure` gives for it.
void record_every_sample_done(SyntheticStudy& study,
                              const std::function<std::map<std::string, double>(const study::SampleRow&)>& measure);

}  // namespace demsa::test
