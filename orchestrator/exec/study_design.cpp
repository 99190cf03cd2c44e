// The points of a study: the design drawn, its extension when [design] samples grows, and the replicate cases
// (runner.hpp: draw_design, design_extension, replicate_rows).
#include "orchestrator/exec/runner.hpp"

#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/util/errors.hpp"
#include "sobol/augment.hpp"
#include "sobol/design.hpp"
#include "sobol/scaling.hpp"

#include <fmt/core.h>

#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace demsa::exec {

using namespace demsa::study;
using cases::replicate_assembly_seed;
using util::UserError;

std::vector<SampleRow> draw_design(const StudyConfig& config) {
  sobol::DesignOptions options;
  options.kind = sobol::design_kind_from_string(config.design);
  options.samples = config.samples;
  options.dimension = static_cast<int>(config.parameters.size());
  options.seed = config.seed;
  // Reproducibility over speed: the iteration count alone ends the search (a wall-clock budget would make the
  // design depend on the machine's load).
  options.time_limit = std::numeric_limits<double>::infinity();
  const sobol::DesignResult design = sobol::make_design(options);
  std::vector<sobol::Bounds> bounds;
  for (const ParameterRange& p : config.parameters) bounds.push_back(p.bounds);
  const Eigen::MatrixXd physical = sobol::to_physical(design.points, bounds);
  std::vector<SampleRow> rows;
  for (int i = 0; i < design.points.rows(); ++i) {
    SampleRow row;
    row.sample = i;
    for (int j = 0; j < design.points.cols(); ++j) {
      row.unit.push_back(design.points(i, j));
      row.physical.push_back(physical(i, j));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<SampleRow> design_extension(const StudyConfig& config, const std::vector<SampleRow>& existing,
                                        int design_samples, int added) {
  const int d = static_cast<int>(config.parameters.size());
  const sobol::DesignKind kind = sobol::design_kind_from_string(config.design);
  Eigen::MatrixXd unit;
  if (kind == sobol::DesignKind::sobol) {
    unit = sobol::extend_sobol(design_samples, added, d, config.seed);
  } else {
    Eigen::MatrixXd old(static_cast<Eigen::Index>(existing.size()), d);
    for (std::size_t i = 0; i < existing.size(); ++i)
      for (int k = 0; k < d; ++k)
        old(static_cast<Eigen::Index>(i), k) = existing[i].unit.at(static_cast<std::size_t>(k));
    sobol::LhsExtensionOptions options;
    options.centred = kind == sobol::DesignKind::lhs_centred;
    // One seed per extension: the study's, mixed with the count it starts from (splitmix64's constant).
    const std::uint64_t seed = config.seed ^ (0x9E3779B97F4A7C15ULL * static_cast<std::uint64_t>(existing.size() + 1));
    unit = sobol::extend_lhs(old, added, seed, options);
  }
  std::vector<sobol::Bounds> bounds;
  for (const ParameterRange& p : config.parameters) bounds.push_back(p.bounds);
  const Eigen::MatrixXd physical = sobol::to_physical(unit, bounds);
  std::vector<SampleRow> rows;
  for (Eigen::Index i = 0; i < unit.rows(); ++i) {
    SampleRow row;
    row.sample = static_cast<int>(existing.size() + static_cast<std::size_t>(i));
    for (Eigen::Index j = 0; j < unit.cols(); ++j) {
      row.unit.push_back(unit(i, j));
      row.physical.push_back(physical(i, j));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<ReplicateRow> replicate_rows(const StudyConfig& config, const std::vector<SampleRow>& samples) {
  std::vector<ReplicateRow> rows;
  if (!config.replicates.enabled()) return rows;
  if (config.replicates.points > static_cast<int>(samples.size()))
    throw UserError(fmt::format("{}: [design] replicates points = {} exceeds the design's {} samples",
                                config.file.string(), config.replicates.points, samples.size()));
  for (int point = 0; point < config.replicates.points; ++point) {
    const SampleRow& s = samples.at(static_cast<std::size_t>(point));
    for (int repeat = 1; repeat < config.replicates.repeats; ++repeat) {
      ReplicateRow r;
      r.sample = replicate_sample_id(s.sample, repeat);
      r.point = s.sample;
      r.repeat = repeat;
      r.seed = replicate_assembly_seed(config.seed, s.sample, repeat);
      r.unit = s.unit;
      r.physical = s.physical;
      rows.push_back(std::move(r));
    }
  }
  return rows;
}

}  // namespace demsa::exec
