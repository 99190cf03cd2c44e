#pragma once
// Fitting the candidate metamodels to one observable (paper §5.2: RSM, RBF, GP) and ranking them by their
// leave-one-out Q², the one fitting loop of the analysis, the calibration, the report and `demsa sensitivity`.
#include "sobol/metamodel.hpp"

#include <Eigen/Dense>

#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace demsa::analysis {

/// One metamodel kind fitted to one (x, y): the model and its quality, or why it could not be fitted.
struct FittedMetamodel {
  sobol::MetamodelKind kind = sobol::MetamodelKind::rsm2;
  std::unique_ptr<sobol::Metamodel> model;  ///< null when the fit failed
  sobol::MetamodelSummary quality;          ///< R², adjusted R², Q² (leave-one-out), ... (when fitted)
  std::string error;                        ///< why the fit failed ("" when fitted)
  std::exception_ptr exception;             ///< the exception behind `error`, for callers that report it their way
  bool ok() const { return model != nullptr; }
  std::string name() const { return sobol::to_string(kind); }
};

/// Fits one kind to x (n × d, on [0,1]^d) and y (n). A model that cannot be fitted to the data (too few samples for
/// an RSM of degree 3, a constant observable, a singular system) is returned with the reason, never thrown.
FittedMetamodel fit_metamodel(sobol::MetamodelKind kind, const sobol::MetamodelOptions& options,
                              const Eigen::MatrixXd& x, const Eigen::VectorXd& y);

/// fit_metamodel for each kind, in order.
std::vector<FittedMetamodel> fit_metamodels(const std::vector<sobol::MetamodelKind>& kinds,
                                            const sobol::MetamodelOptions& options, const Eigen::MatrixXd& x,
                                            const Eigen::VectorXd& y);

/// The kinds of the names (sobol::metamodel_kind_from_string; throws sobol::InputError for an unknown name).
std::vector<sobol::MetamodelKind> metamodel_kinds(const std::vector<std::string>& names);

/// Index of the fitted model with the largest Q²; a Q² that is not finite (as many terms as samples: no
/// leave-one-out) ranks below every finite one, and the first of equals wins. nullopt when none was fitted.
std::optional<std::size_t> best_by_q2(const std::vector<FittedMetamodel>& fits);

/// Why the leave-one-out error of a fitted model cannot be measured ("" when its Q² and RMSE_LOO are finite): a model
/// with as many terms as samples passes through every sample, and each leave-one-out residual e_i / (1 − h_ii) (the
/// PRESS residual, Allen 1974, Technometrics 16(1)) is 0/0, its leverage h_ii being 1; a sample of leverage 1 does the
/// same among more samples. Such a model cannot be judged, ranked or weighed against another.
std::string unmeasurable_error(const sobol::MetamodelSummary& quality);

/// The fit a calibration or a plan weighs its targets with: the best by Q² among those whose leave-one-out error
/// can be measured (finite Q²). A model fitted on as many samples as it has terms passes through every sample and
/// leaves none out (each leave-one-out residual is 0/0): its error, the variance the likelihood adds for it, would be
/// taken as 0. Throws util::UserError naming the study folder `where`, the observable and each candidate's reason
/// when no fit is left.
std::size_t best_measurable(const std::vector<FittedMetamodel>& fits, const std::string& where,
                            const std::string& observable);

}  // namespace demsa::analysis
