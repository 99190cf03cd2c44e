#pragma once
// The studies of one calibration or plan, read together: several study folders (different experiments) that share
// parameter names. Used by `demsa calibrate --method bayes` (calibration_posterior.hpp) and `demsa plan`
// (experiment_plan.hpp), so that both read the same prior and fit the same metamodels.
//
//   - load_joint_studies: each folder's frozen study, its samples and observables; one folder given twice (or by two
//     spellings of its path) is refused, or its measurements would count twice;
//   - JointPrior: every parameter of any study, uniform on its design scale over the intersection of the ranges of
//     the studies that vary it (an empty intersection, or log in one study and linear in another, is refused);
//   - fit_observable: the candidate metamodel of best leave-one-out Q² for one observable of one study, with the
//     affine map from the prior's coordinates to the study's own unit coordinates.
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/store.hpp"
#include "sobol/metamodel.hpp"
#include "sobol/posterior.hpp"
#include "sobol/scaling.hpp"

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace demsa::analysis {

struct JointStudy {
  std::filesystem::path dir;
  study::StudyConfig config;
  std::vector<study::SampleRow> samples;
  std::map<int, std::map<std::string, double>> observables;  ///< per sample, as the store holds them
  std::vector<std::string> available;                        ///< every observable name stored, first-seen order
  std::vector<study::ReplicateRow> replicates;               ///< its replicate cases ([design] replicates)
  double cpu_per_case = 0.0;                                 ///< median CPU seconds of its done runs (NaN: none)
  bool measures(const std::string& name) const;
};

/// An observable of one study or of any: "STUDY:NAME" or "NAME" (STUDY: a study's `[study] name`).
struct QualifiedName {
  std::string study;  ///< empty: any study that measures `name`
  std::string name;
  /// `name` is `observable` and `study` is empty or the study's name.
  bool matches(const JointStudy& s, const std::string& observable) const;
  std::string label() const { return study.empty() ? name : study + ":" + name; }
};

/// Reads each folder (util::UserError naming `command` and both paths when one study is given twice).
std::vector<JointStudy> load_joint_studies(const std::vector<std::filesystem::path>& dirs, const std::string& command);

struct JointPrior {
  std::vector<std::string> names;     ///< every parameter of any study, first-seen order; none tied in any study
  std::vector<sobol::Bounds> bounds;  ///< on each parameter's design scale, the intersection of the studies' ranges
  /// The ties of every study: a parameter tied in one study is its partner in all (a study that varies it maps it
  /// onto the partner's column, its range intersected into the partner's).
  std::vector<study::ParameterTie> ties;
  int dimension() const { return static_cast<int>(names.size()); }
  int column(const std::string& name) const;  ///< index in names; -1 when absent
  /// The column a study's varied parameter `name` feeds: its own, or its partner's when a study ties it; -1 when
  /// absent.
  int column_of(const std::string& name) const;
};

/// Throws util::UserError naming the parameter and both studies when ranges do not overlap or scales differ.
JointPrior joint_prior(const std::vector<JointStudy>& studies);

/// A study's unit coordinate of its parameter j as an affine function of the prior's coordinate (same scale).
std::vector<sobol::InputMap> input_maps(const JointStudy& study, const JointPrior& prior);

/// One observable of one study with its fitted metamodel.
struct FittedObservable {
  std::string name;                                ///< observable
  std::unique_ptr<sobol::Metamodel> model;         ///< fitted on the study's unit cube
  std::string model_name;                          ///< "gp", "rsm2", ...
  double q2 = 0.0;                                 ///< leave-one-out Q² of the model
  double observed_low = 0.0, observed_high = 0.0;  ///< the observable's range over the done samples
  double observed_median = 0.0;
  int samples = 0;  ///< done samples that measured it
};

/// The candidates (`model`, or the study's [analysis] metamodels when empty) fitted to `observable`; the one of best
/// Q² is kept. Throws util::UserError naming the study when fewer than 2 samples measured it or no fit succeeded.
FittedObservable fit_observable(const JointStudy& study, const std::string& observable, const std::string& model);

}  // namespace demsa::analysis
