#pragma once
// A design of experiments for any simulator, written as CSV (`demsa design lhs|sobol|saltelli`; README "Usage"):
// a Latin hypercube or a scrambled Sobol' sequence (write_point_design), or a Saltelli design in independently
// scrambled replicates (write_simulator_saltelli_design; its file format: saltelli_design_file.hpp). Values are on the
// unit cube unless the parameters carry bounds. A mistake in the options is a util::UserError naming the field
// ("PointDesignOptions.samples 1: ..."), which a command line writes as its own option (cli::name_options); the
// warnings go to the options' sink the same way.
#include "orchestrator/analysis/sensitivity.hpp"
#include "sobol/design.hpp"
#include "sobol/saltelli.hpp"
#include "sobol/scaling.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace demsa::analysis {

/// The parameters of a design: their names and, when `named`, the bounds its values are scaled to.
struct DesignParameters {
  std::vector<std::string> names;
  std::vector<sobol::Bounds> bounds;  ///< one per name (the unit interval when not `named`)
  bool named = false;                 ///< given by name with bounds; false: x1..xD on the unit cube
};

/// How a front end names the parameters of a design: by spec, "NAME:LOW:HIGH" or "NAME:LOW:HIGH:log|uniform" (one
/// per parameter), or by a dimension D alone (x1..xD on the unit cube); exactly one of the two.
struct DesignParameterOptions {
  std::vector<std::string> parameters;
  std::optional<int> dimension;
};

/// The parameters the options name, checked (sobol::validate_bounds). A mistake is a util::UserError naming the field
/// and the spec ("DesignParameterOptions.parameters 'a:0:x': high: 'x' is not a number").
DesignParameters parse_design_parameters(const DesignParameterOptions& options);

/// The kind of a Latin hypercube: plain, `centred`, or optimised for `criterion` (sobol::lhs_criterion_from_string;
/// "": none). Not both.
struct LhsKindOptions {
  bool centred = false;
  std::string criterion;
};

/// The kind the options ask for; a util::UserError naming the fields ("LhsKindOptions.criterion: unknown ...").
sobol::DesignKind lhs_kind(const LhsKindOptions& options);

/// A Latin hypercube (plain, centred, optimised) or a scrambled Sobol' sequence.
struct PointDesignOptions {
  sobol::DesignKind kind = sobol::DesignKind::lhs;
  DesignParameters parameters;
  int samples = 0;
  std::uint64_t seed = 12345;
  double time_limit = 60.0;  ///< safety stop of an optimised Latin hypercube [s]; a warning when it ends the search
  int iterations = sobol::DesignOptions{}.iterations;  ///< outer iterations at most
  double phi_p = 50.0;                                 ///< p of the phi_p criterion, >= 1
  std::string output;                                  ///< the CSV file (its folder must exist)
  WarningSink warn;                                    ///< empty: util::log::warn
};

struct PointDesign {
  sobol::DesignResult design;  ///< points on the unit cube, metrics, iterations
  std::vector<std::string> names;
  std::string output;
};

/// Checks the options, draws the design and writes it (header row of names, one row per sample, values scaled to the
/// bounds of named parameters).
PointDesign write_point_design(const PointDesignOptions& options);

/// {"design", "file", "samples", "dimension", "parameters", "seed", "iterations", "stop", "seconds", "metrics"}.
nlohmann::json point_design_json(const PointDesign& written);
/// The design in words: its kind, size, seed and file, the optimisation and the space-filling metrics.
std::string point_design_text(const PointDesign& written);

/// A Saltelli design (blocks A, B, AB_i and BA_i) for `demsa sensitivity --saltelli`.
struct SaltelliDesignFileOptions {
  DesignParameters parameters;
  int base = 0;  ///< N; another value than a power of two is rounded up to the next one, with a warning
  bool second_order = false;
  /// Independently scrambled replicates (column 'replicate' when > 1); 0: sobol::default_saltelli_replicates(N).
  int replicates = 0;
  std::uint64_t seed = 12345;
  std::string output;    ///< the CSV file (its folder must exist)
  bool metrics = false;  ///< the space-filling metrics of block A (O(N^2) time)
  WarningSink warn;      ///< empty: util::log::warn
};

struct SaltelliDesignWritten {
  sobol::SaltelliDesign design;
  std::vector<std::string> names;
  std::string output;
  std::optional<sobol::DesignMetrics> metrics_of_a;  ///< when asked
};

/// Checks the options, draws the design and writes it (saltelli_design_file.hpp).
SaltelliDesignWritten write_simulator_saltelli_design(const SaltelliDesignFileOptions& options);

/// {"design": "saltelli", "file", "base", "dimension", "second_order", "rows", "parameters", "seed", "replicates",
/// "metrics_of_a"}.
nlohmann::json saltelli_design_written_json(const SaltelliDesignWritten& written);
/// The design in words: its size, seed and file, its replicates and what the column 'block' means.
std::string saltelli_design_written_text(const SaltelliDesignWritten& written);

}  // namespace demsa::analysis
