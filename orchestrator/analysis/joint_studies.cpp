#include "orchestrator/analysis/joint_studies.hpp"

#include "orchestrator/analysis/fit.hpp"
#include "orchestrator/analysis/training_data.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace demsa::analysis {

using namespace demsa::util;
using namespace demsa::study;
namespace fs = std::filesystem;

bool JointStudy::measures(const std::string& name) const {
  return std::find(available.begin(), available.end(), name) != available.end();
}

bool QualifiedName::matches(const JointStudy& s, const std::string& observable) const {
  return name == observable && (study.empty() || study == s.config.name);
}

std::vector<JointStudy> load_joint_studies(const std::vector<fs::path>& dirs, const std::string& command) {
  // One folder given twice (or by two spellings of its path) would count its measurements twice and narrow the
  // posterior as if they had been measured twice: refused, compared by canonical path.
  std::vector<fs::path> canonical;
  for (size_t i = 0; i < dirs.size(); ++i) {
    require_study_folder(dirs[i]);
    canonical.push_back(fs::canonical(dirs[i]));
    for (size_t k = 0; k < i; ++k)
      if (canonical[k] == canonical[i])
        throw UserError(
            fmt::format("{}: study folders '{}' and '{}' are the same study ({}); give each study "
                        "once, or its measurements count twice",
                        command, dirs[k].string(), dirs[i].string(), canonical[i].string()));
  }
  std::vector<JointStudy> studies;
  for (const fs::path& dir : dirs) {
    JointStudy s;
    s.dir = dir;
    s.config = experiments::load_study(dir / k_frozen_study);
    const Store store = Store::open_read_only((dir / k_store_file).string());
    s.samples = store.samples();
    s.observables = store.observables();
    s.replicates = store.replicates();
    std::vector<double> cpu;
    for (const RunRow& run : store.runs_in_state(RunState::done))
      if (run.cpu_seconds > 0) cpu.push_back(run.cpu_seconds);
    s.cpu_per_case = cpu.empty() ? std::nan("") : sobol::quantile(cpu, 0.5);
    for (const auto& [sample, values] : s.observables)
      for (const auto& [name, value] : values)
        if (!s.measures(name)) s.available.push_back(name);
    studies.push_back(std::move(s));
  }
  return studies;
}

int JointPrior::column(const std::string& name) const {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

namespace {

/// The joint column a study's parameter `name` maps onto: its partner when any study ties it.
const std::string& joint_name(const JointPrior& prior, const std::string& name) {
  const study::ParameterTie* tie = study::find_tie(prior.ties, name);
  return tie ? tie->partner : name;
}

}  // namespace

int JointPrior::column_of(const std::string& name) const { return column(joint_name(*this, name)); }

JointPrior joint_prior(const std::vector<JointStudy>& studies) {
  JointPrior prior;
  // One tie per parameter over all studies, and no partner tied in another study (a chain across studies).
  std::vector<std::string> tie_owner;
  for (const JointStudy& s : studies)
    for (const study::ParameterTie& t : s.config.ties) {
      if (const study::ParameterTie* seen = study::find_tie(prior.ties, t.name)) {
        if (seen->partner != t.partner)
          throw UserError(fmt::format("parameter {}: {} ties it to {}, {} to {}; the joint prior needs one tie", t.name,
                                      tie_owner[static_cast<size_t>(seen - prior.ties.data())], seen->partner,
                                      s.dir.string(), t.partner));
        continue;
      }
      prior.ties.push_back(t);
      tie_owner.push_back(s.dir.string());
    }
  for (size_t i = 0; i < prior.ties.size(); ++i)
    if (const study::ParameterTie* chain = study::find_tie(prior.ties, prior.ties[i].partner))
      throw UserError(fmt::format(
          "parameter {}: {} ties it to {}, which {} ties to {}; the studies must tie their parameters alike",
          prior.ties[i].name, tie_owner[i], prior.ties[i].partner,
          tie_owner[static_cast<size_t>(chain - prior.ties.data())], chain->partner));
  std::vector<std::string> owner;  // study that set the current bounds (for messages)
  for (const JointStudy& s : studies) {
    for (const ParameterRange& varied : s.config.parameters) {
      // A parameter another study ties to its partner is the partner here too.
      ParameterRange p = varied;
      p.name = joint_name(prior, varied.name);
      const int column = prior.column(p.name);
      if (column < 0) {
        prior.names.push_back(p.name);
        prior.bounds.push_back(p.bounds);
        owner.push_back(s.dir.string());
        continue;
      }
      sobol::Bounds& b = prior.bounds[static_cast<size_t>(column)];
      const std::string& first = owner[static_cast<size_t>(column)];
      if (b.scale != p.bounds.scale)
        throw UserError(fmt::format("parameter {}: {} samples it on a {} scale, {} on a {} scale; the prior needs one",
                                    p.name, first, sobol::to_string(b.scale), s.dir.string(),
                                    sobol::to_string(p.bounds.scale)));
      const double low = std::max(b.low, p.bounds.low), high = std::min(b.high, p.bounds.high);
      if (!(low < high))
        throw UserError(fmt::format("parameter {}: the ranges [{:g}, {:g}] of {} and [{:g}, {:g}] of {} do not overlap",
                                    p.name, b.low, b.high, first, p.bounds.low, p.bounds.high, s.dir.string()));
      b.low = low;
      b.high = high;
    }
  }
  return prior;
}

std::vector<sobol::InputMap> input_maps(const JointStudy& study, const JointPrior& prior) {
  std::vector<sobol::InputMap> maps;
  for (const ParameterRange& p : study.config.parameters) {
    const int column = prior.column_of(p.name);
    assert(column >= 0 && "a study's parameter outside its joint prior");
    const sobol::Bounds& b = prior.bounds[static_cast<size_t>(column)];
    const double at_low = sobol::to_unit(b.low, p.bounds), at_high = sobol::to_unit(b.high, p.bounds);
    maps.push_back({column, at_low, at_high - at_low});
  }
  return maps;
}

FittedObservable fit_observable(const JointStudy& s, const std::string& observable, const std::string& model) {
  const TrainingData data = training_data(s.config, s.samples, s.observables, observable);
  if (data.size() < 2)
    throw UserError(fmt::format("{}: {} done samples measure {}; a metamodel needs at least 2", s.dir.string(),
                                data.size(), observable));
  const std::vector<std::string> candidates =
      model.empty() ? s.config.analysis.metamodels : std::vector<std::string>{model};
  std::vector<FittedMetamodel> fits =
      fit_metamodels(metamodel_kinds(candidates), s.config.analysis.metamodel_options(), data.unit, data.y);
  const std::size_t best = best_measurable(fits, s.dir.string(), observable);
  FittedObservable f;
  f.name = observable;
  f.model_name = fits[best].name();
  f.q2 = fits[best].quality.q2;
  f.model = std::move(fits[best].model);
  f.observed_low = data.y.minCoeff();
  f.observed_high = data.y.maxCoeff();
  f.observed_median = sobol::quantile(std::vector<double>(data.y.data(), data.y.data() + data.y.size()), 0.5);
  f.samples = static_cast<int>(data.size());
  return f;
}

}  // namespace demsa::analysis
