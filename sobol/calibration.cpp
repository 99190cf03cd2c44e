#include "sobol/calibration.hpp"

#include <fmt/core.h>
#include <nlopt.hpp>
#include "sobol/enum_names.hpp"

#include <cassert>
#include <cmath>
#include <limits>

namespace demsa::sobol {

namespace {

nlopt::algorithm to_nlopt(GlobalAlgorithm a) {
  switch (a) {
    case GlobalAlgorithm::direct_l:
      return nlopt::GN_DIRECT_L;
    case GlobalAlgorithm::crs2:
      return nlopt::GN_CRS2_LM;
    case GlobalAlgorithm::isres:
      return nlopt::GN_ISRES;
    case GlobalAlgorithm::mlsl_lds:
      return nlopt::G_MLSL_LDS;
    case GlobalAlgorithm::none:
      break;
  }
  assert(false && "no NLopt algorithm for GlobalAlgorithm::none");
  return nlopt::GN_DIRECT_L;
}

nlopt::algorithm to_nlopt(LocalAlgorithm a) {
  switch (a) {
    case LocalAlgorithm::bobyqa:
      return nlopt::LN_BOBYQA;
    case LocalAlgorithm::nelder_mead:
      return nlopt::LN_NELDERMEAD;
    case LocalAlgorithm::sbplx:
      return nlopt::LN_SBPLX;
    case LocalAlgorithm::cobyla:
      return nlopt::LN_COBYLA;
    case LocalAlgorithm::none:
      break;
  }
  assert(false && "no NLopt algorithm for LocalAlgorithm::none");
  return nlopt::LN_BOBYQA;
}

/// The misfit with a record of the best point seen (NLopt may stop by an exception after finding it).
struct Objective {
  const std::vector<CalibrationTarget>* targets = nullptr;
  int evaluations = 0;
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> best_x;

  double operator()(const std::vector<double>& x) {
    ++evaluations;
    const Eigen::Map<const Eigen::RowVectorXd> row(x.data(), static_cast<Eigen::Index>(x.size()));
    const Eigen::MatrixXd point = row;
    double j = 0.0;
    for (const CalibrationTarget& t : *targets) {
      const double r = (t.model->predict(point)(0) - t.value) / t.scale;
      j += t.weight * r * r;
    }
    if (j < best) {
      best = j;
      best_x = x;
    }
    return j;
  }
  static double call(unsigned n, const double* x, double*, void* data) {
    return (*static_cast<Objective*>(data))(std::vector<double>(x, x + n));
  }
};

}  // namespace

namespace {

const EnumNames<GlobalAlgorithm>& global_algorithm_names() {
  static const EnumNames<GlobalAlgorithm> names{"global algorithm",
                                                {{GlobalAlgorithm::direct_l, "direct-l"},
                                                 {GlobalAlgorithm::crs2, "crs2"},
                                                 {GlobalAlgorithm::isres, "isres"},
                                                 {GlobalAlgorithm::mlsl_lds, "mlsl-lds"},
                                                 {GlobalAlgorithm::none, "none"}}};
  return names;
}

const EnumNames<LocalAlgorithm>& local_algorithm_names() {
  static const EnumNames<LocalAlgorithm> names{"local algorithm",
                                               {{LocalAlgorithm::bobyqa, "bobyqa"},
                                                {LocalAlgorithm::nelder_mead, "nelder-mead"},
                                                {LocalAlgorithm::sbplx, "sbplx"},
                                                {LocalAlgorithm::cobyla, "cobyla"},
                                                {LocalAlgorithm::none, "none"}}};
  return names;
}

}  // namespace

GlobalAlgorithm global_algorithm_from_string(const std::string& name) {
  return global_algorithm_names().from_string(name);
}
std::string to_string(GlobalAlgorithm algorithm) { return global_algorithm_names().to_string(algorithm); }

LocalAlgorithm local_algorithm_from_string(const std::string& name) {
  return local_algorithm_names().from_string(name);
}
std::string to_string(LocalAlgorithm algorithm) { return local_algorithm_names().to_string(algorithm); }

void CalibrationOptions::validate(int dimension) const {
  for (const auto* v : {&lower, &upper}) {
    const char* field = v == &lower ? "lower" : "upper";
    if (!v->empty() && static_cast<int>(v->size()) != dimension)
      throw InputError(fmt::format("calibration {}: {} values for {} inputs", field, v->size(), dimension));
    for (std::size_t k = 0; k < v->size(); ++k)
      if (!((*v)[k] >= 0.0 && (*v)[k] <= 1.0))
        throw InputError(fmt::format("calibration {}[{}] = {}: must be in [0, 1] (unit cube)", field, k + 1, (*v)[k]));
  }
  for (int k = 0; k < dimension; ++k) {
    const double lo = lower.empty() ? 0.0 : lower[static_cast<std::size_t>(k)];
    const double hi = upper.empty() ? 1.0 : upper[static_cast<std::size_t>(k)];
    if (!(lo < hi))
      throw InputError(
          fmt::format("calibration bounds of input {}: lower ({}) must be less than upper ({})", k + 1, lo, hi));
  }
  if (global == GlobalAlgorithm::none && local == LocalAlgorithm::none)
    throw InputError("calibration: the global and the local algorithm are both 'none'");
  if (global_evaluations < 1)
    throw InputError(fmt::format("calibration global_evaluations = {}: must be at least 1", global_evaluations));
  if (local_evaluations < 1)
    throw InputError(fmt::format("calibration local_evaluations = {}: must be at least 1", local_evaluations));
  if (!(tolerance > 0.0)) throw InputError(fmt::format("calibration tolerance = {}: must be > 0", tolerance));
}

CalibrationResult calibrate(const std::vector<CalibrationTarget>& targets, const CalibrationOptions& options) {
  if (targets.empty()) throw InputError("calibration: no targets");
  int d = -1;
  for (const CalibrationTarget& t : targets) {
    if (t.model == nullptr || !t.model->fitted())
      throw InputError(fmt::format("calibration target '{}': its metamodel is not fitted", t.name));
    const int dt = static_cast<int>(t.model->training_inputs().cols());
    if (d >= 0 && dt != d)
      throw InputError(
          fmt::format("calibration target '{}': its metamodel has {} inputs, the others {}", t.name, dt, d));
    d = dt;
    if (!std::isfinite(t.value))
      throw InputError(fmt::format("calibration target '{}': value {} is not finite", t.name, t.value));
    if (!(t.weight >= 0.0) || !std::isfinite(t.weight))
      throw InputError(fmt::format("calibration target '{}': weight {} must be >= 0", t.name, t.weight));
    if (!(t.scale > 0.0) || !std::isfinite(t.scale))
      throw InputError(fmt::format("calibration target '{}': scale {} must be > 0", t.name, t.scale));
  }
  options.validate(d);
  std::vector<double> lower(static_cast<std::size_t>(d), 0.0), upper(static_cast<std::size_t>(d), 1.0);
  if (!options.lower.empty()) lower = options.lower;
  if (!options.upper.empty()) upper = options.upper;

  Objective objective;
  objective.targets = &targets;
  std::vector<double> x(static_cast<std::size_t>(d));
  for (int k = 0; k < d; ++k)
    x[static_cast<std::size_t>(k)] = 0.5 * (lower[static_cast<std::size_t>(k)] + upper[static_cast<std::size_t>(k)]);
  nlopt::srand(options.seed);  // NLopt's stochastic algorithms (CRS2, ISRES, MLSL) draw from this seed

  auto run = [&](nlopt::algorithm algorithm, int evaluations, bool local) {
    nlopt::opt opt(algorithm, static_cast<unsigned>(d));
    opt.set_lower_bounds(lower);
    opt.set_upper_bounds(upper);
    opt.set_min_objective(&Objective::call, &objective);
    opt.set_maxeval(evaluations);
    if (local) opt.set_xtol_rel(options.tolerance);
    if (algorithm == nlopt::G_MLSL_LDS) {
      nlopt::opt inner(nlopt::LN_BOBYQA, static_cast<unsigned>(d));
      inner.set_xtol_rel(1e-6);
      opt.set_local_optimizer(inner);
    }
    double value = 0.0;
    try {
      opt.optimize(x, value);
    } catch (const nlopt::roundoff_limited&) {
      // The best point seen is kept by the objective.
    } catch (const std::runtime_error& e) {
      throw NumericalError(fmt::format("calibration: NLopt failed: {}", e.what()));
    }
    x = objective.best_x;
  };

  CalibrationResult result;
  if (options.global != GlobalAlgorithm::none) run(to_nlopt(options.global), options.global_evaluations, false);
  if (objective.best_x.empty()) objective(x);
  result.global_misfit = objective.best;
  if (options.local != LocalAlgorithm::none) run(to_nlopt(options.local), options.local_evaluations, true);

  result.x = objective.best_x;
  result.misfit = objective.best;
  result.evaluations = objective.evaluations;
  result.global_algorithm = to_string(options.global);
  result.local_algorithm = to_string(options.local);
  result.seed = options.seed;
  const Eigen::Map<const Eigen::RowVectorXd> row(result.x.data(), d);
  const Eigen::MatrixXd point = row;
  for (const CalibrationTarget& t : targets) {
    result.names.push_back(t.name);
    result.targets.push_back(t.value);
    result.predictions.push_back(t.model->predict(point)(0));
  }
  return result;
}

}  // namespace demsa::sobol
