#pragma once
// Metamodels on the unit cube (paper §5): one interface for polynomial response surfaces
// (sobol/rsm.hpp), radial-basis-function interpolation (sobol/rbf.hpp) and Gaussian-process regression
// (sobol/gp.hpp). Inputs are rows of x on [0,1]^d (scale physical values with sobol/scaling.hpp first).
//
// Typical use:
//   std::unique_ptr<Metamodel> m = make_metamodel("rbf-cubic");
//   m->fit(x, y);                                  // throws InputError / DataError / NumericalError
//   Eigen::VectorXd yhat = m->predict(x_new);       // batched
//   MetamodelSummary s = m->summary();             // R², adjusted R², Q²_LOO, ...
#include "sobol/error.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace demsa::sobol {

enum class MetamodelKind {
  rsm1,       ///< polynomial RSM of total degree 1
  rsm2,       ///< total degree 2
  rsm3,       ///< total degree 3
  rbf_cubic,  ///< RBF interpolation, φ(r) = r³, linear tail
  rbf_tps,    ///< RBF interpolation, φ(r) = r² log r², linear tail
  gp,         ///< Gaussian-process (Kriging) regression
};

/// "rsm1" | "rsm2" | "rsm3" | "rbf-cubic" | "rbf-tps" | "gp"; throws InputError listing the valid names.
MetamodelKind metamodel_kind_from_string(const std::string& name);
std::string to_string(MetamodelKind kind);
/// The canonical names, in enum order.
std::vector<std::string> metamodel_names();

enum class GpKernel {
  squared_exponential,  ///< k(h) = exp(-Σ (h_k/θ_k)² / 2)
  matern52,             ///< k(h) = (1 + √5 r + 5r²/3) exp(-√5 r), r² = Σ (h_k/θ_k)²
};
/// "squared-exponential" (also "se", "gaussian") | "matern52" (also "matern-5/2"); throws listing valid names.
GpKernel gp_kernel_from_string(const std::string& name);
std::string to_string(GpKernel kernel);

enum class GpTrend { constant, linear };
/// "constant" | "linear"; throws listing valid names.
GpTrend gp_trend_from_string(const std::string& name);
std::string to_string(GpTrend trend);

/// Gaussian-process settings (Rasmussen & Williams 2006, ch. 2 and 5; Santner, Williams, Notz 2003, ch. 3).
struct GpOptions {
  GpKernel kernel = GpKernel::squared_exponential;  ///< correlation function
  GpTrend trend = GpTrend::constant;                ///< regression part (universal Kriging for linear)
  bool nugget = false;       ///< estimate a nugget (noise / signal variance ratio) for noisy simulators
  double min_length = 1e-2;  ///< lower bound of every length scale θ_k (unit-cube units), > 0
  double max_length = 1e2;   ///< upper bound of every θ_k, > min_length
  double min_nugget = 1e-8;  ///< lower bound of the nugget ratio when estimated, > 0
  double max_nugget = 1e-1;  ///< upper bound of the nugget ratio, > min_nugget
  /// The simulator's noise variance divided by the output's variance, when measured (replicates: sobol/noise.hpp):
  /// the noise variance in the GP's scaled units. When set (>= 0; needs `nugget`), the nugget is set from it instead
  /// of estimated: τ = noise_share / σ², σ² the process variance of the scaled outputs, by a fixed-point iteration
  /// over the likelihood fit (gp.hpp). NaN: not measured, the nugget is estimated.
  double noise_share = std::numeric_limits<double>::quiet_NaN();
  int starts = 4;              ///< likelihood maximisation starts (first at θ_k = 0.5, others random), >= 1
  int max_evaluations = 400;   ///< likelihood evaluations per start, >= 10
  std::uint64_t seed = 12345;  ///< seed of the random starts
  void validate() const;       ///< throws InputError naming the field, value and rule
};

struct MetamodelOptions {
  GpOptions gp;  ///< used by MetamodelKind::gp only
  void validate() const;
};

/// A named scalar describing a fitted model (a length scale, a regularisation, ...).
struct NamedValue {
  std::string name;
  double value = 0.0;
};

/// Quality of a fitted metamodel; plain data (serialise every field).
struct MetamodelSummary {
  std::string name;                    ///< metamodel name ("rsm2", "gp", ...)
  int samples = 0;                     ///< training points n
  int dimension = 0;                   ///< inputs d
  int terms = 0;                       ///< fitted coefficients (RSM terms, RBF weights + tail, GP trend terms)
  double r2 = 0.0;                     ///< R² = 1 - SSE/SST on the training data (1 for interpolators)
  double adjusted_r2 = 0.0;            ///< 1 - (1 - R²)(n - 1)/(n - terms) for RSM; equal to r2 otherwise
  double q2 = 0.0;                     ///< leave-one-out Q² = 1 - PRESS/SST, closed form (hat matrix, Rippa, GP LOO)
  double rmse_loo = 0.0;               ///< sqrt(PRESS / n)
  double mean = 0.0;                   ///< mean of the training outputs
  double sd = 0.0;                     ///< standard deviation of the training outputs
  std::vector<NamedValue> parameters;  ///< model-specific values (GP: θ_k, σ², nugget, log-likelihood)
};

/// A response surface fitted to (x on [0,1]^d, y). Not thread-safe for fit(); predict() is const.
class Metamodel {
 public:
  virtual ~Metamodel() = default;

  virtual MetamodelKind kind() const = 0;
  std::string name() const { return to_string(kind()); }

  /// Fits to rows of x (n x d, each in [0,1]) and outputs y (n). Throws InputError for NaN/infinite values or
  /// mismatched sizes, DataError for a constant input column or a duplicated point (interpolators), InputError for
  /// too few samples (naming how many are needed), NumericalError for a singular system.
  virtual void fit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) = 0;
  bool fitted() const { return m_fitted; }

  /// Predictions at the rows of x (m x d). Requires fitted().
  virtual Eigen::VectorXd predict(const Eigen::MatrixXd& x) const = 0;

  /// Leave-one-out residuals y_i - ŷ_{-i}(x_i), closed form. Requires fitted().
  virtual Eigen::VectorXd loo_residuals() const = 0;

  /// R², Q², ... Requires fitted().
  virtual MetamodelSummary summary() const = 0;

  /// A new model of the same kind and options fitted to other data. A GP keeps this model's hyperparameters
  /// (no new likelihood search), which is what a design bootstrap wants. Requires fitted().
  virtual std::unique_ptr<Metamodel> refit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) const = 0;

  /// True for models that pass through the data (RBF, GP without nugget): they cannot take duplicated points.
  virtual bool interpolates() const = 0;

  const Eigen::MatrixXd& training_inputs() const { return m_x; }
  const Eigen::VectorXd& training_outputs() const { return m_y; }

 protected:
  /// Checks sizes, finiteness, [0,1] range and non-constant columns; stores the data. `min_samples` is what
  /// the model needs (throws InputError "needs at least K samples for ... (got n)").
  void store_training_data(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, int min_samples);
  /// Summary fields shared by all models, from fitted values and LOO residuals.
  MetamodelSummary base_summary(const Eigen::VectorXd& fitted_values, int terms) const;

  Eigen::MatrixXd m_x;
  Eigen::VectorXd m_y;
  bool m_fitted = false;
};

/// Throws DataError(row, -1, "duplicates the point of sample K") for the first repeated row of x.
void check_no_duplicates(const Eigen::MatrixXd& x);

/// Factory. The string form throws InputError listing the valid names.
std::unique_ptr<Metamodel> make_metamodel(MetamodelKind kind, const MetamodelOptions& options = {});
std::unique_ptr<Metamodel> make_metamodel(const std::string& name, const MetamodelOptions& options = {});

}  // namespace demsa::sobol
