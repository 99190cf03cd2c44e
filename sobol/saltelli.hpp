#pragma once
// Sobol' indices from a Saltelli design, for any model (paper §6):
//   S1 by Saltelli et al. 2010 (Comput. Phys. Commun. 181, eq. (b) of Table 2): V_i = mean(f(B) (f(AB_i) - f(A))),
//   ST by Jansen 1999 (Saltelli 2010, Table 2 (f)): VT_i = mean((f(A) - f(AB_i))^2) / 2,
//   S2 by Saltelli 2002 (Comput. Phys. Commun. 145): V_ij^closed = mean(f(BA_i) f(AB_j) - f(A) f(B)),
//      S2_ij = V_ij^closed / V - S1_i - S1_j,
//   with the BA blocks of a second-order design:
//      S1 from differences on both sides (after Owen 2013, ACM TOMACS 23(2)): V_i = mean((f(B) - f(BA_i)) (f(AB_i)
//      - f(A))) / 2, unbiased because only B, AB_i and A, BA_i share x_i,
//      ST averaged over A and B exchanged: VT_i = mean((f(A) - f(AB_i))^2 + (f(B) - f(BA_i))^2) / 4 (Saltelli 2002,
//      §3), and the mean and variance taken over all 2d + 2 blocks,
// with confidence intervals (SaltelliInterval)
//   - by default from R independently scrambled replicates of the design (randomised quasi-Monte Carlo: Owen 1997,
//     "Monte Carlo variance of scrambled net quadrature", SIAM J. Numer. Anal. 34; L'Ecuyer & Lemieux 2002, "Recent
//     advances in randomized quasi-Monte Carlo methods"): the estimates of the R replicates are independent and
//     identically distributed, so a Student-t interval with R - 1 degrees of freedom on their mean is valid whatever
//     the correlation of the rows inside a replicate; the point estimate is the one of all R N/R rows pooled. A
//     design without replicates gets no interval this way, and the result's note says so;
//   - by name, a percentile bootstrap (resampling the N base rows, every block together; Archer, Saltelli & Sobol'
//     1997), which assumes the base rows are independent random draws. The rows of one scrambled Sobol' sequence
//     are not (their errors cancel), so that interval is conservative, typically several times too wide, and the
//     result says so in its note.
//
// A and B are the two halves of ONE 2d-dimensional scrambled Sobol' sequence. Taking A and B as consecutive blocks
// of a d-dimensional sequence correlates them and biases the indices; saltelli_design() never does that.
#include "sobol/design.hpp"
#include "sobol/stop.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace demsa::sobol {

/// Most inputs of a Saltelli design: A and B are the two halves of one 2d-dimensional Sobol' sequence.
inline constexpr int k_max_saltelli_dimension = k_max_sobol_dimension / 2;
/// The largest base sample size N of a Saltelli design or of metamodel-based indices (the study file's
/// `[analysis] base_samples`, `demsa design saltelli --base`, `demsa sensitivity --base`): N (2d + 2) points are held
/// in memory, about 1 GB at 2^20 for 7 parameters.
inline constexpr int k_max_base_samples = 1 << 20;

struct SaltelliOptions {
  int base = 1024;             ///< N, rows of A and of B, >= 2 (a power of two gives the best balance)
  int dimension = 2;           ///< d, number of inputs, 1..20 (the 2d-dimensional sequence has at most 40)
  bool second_order = false;   ///< also build BA_i, needed for S2
  std::uint64_t seed = 12345;  ///< scrambling seed
  int replicates = 1;          ///< R independently scrambled designs of base N/R each, 1..N/2 dividing N (1: one
                               ///< design, the seed's; R >= 2 gives intervals valid for QMC, see sobol_indices)
  void validate() const;       ///< throws InputError naming the field, value and rule
};

/// The replicates of a Saltelli design written for any simulator (`demsa design saltelli`) unless told otherwise.
/// Ishigami, Sobol' G and a 7-D polynomial at N = 1024 (docs/explanation/benchmarks.md): with 8 replicates the 95%
/// Student-t intervals covered 0.93-0.97 of the true indices at 5.3-6.2 times the mean error, where the bootstrap of
/// one design was 8-30 times the error.
inline constexpr int k_default_saltelli_replicates = 8;
/// The fewest base rows per replicate that default_saltelli_replicates leaves.
inline constexpr int k_min_replicate_base = 16;
/// The default replicates of a design of base N: k_default_saltelli_replicates, halved until every replicate keeps at
/// least k_min_replicate_base rows (1 below 2 k_min_replicate_base: one design, without Student-t intervals).
int default_saltelli_replicates(int base);

/// The blocks of a Saltelli design, all N x d on [0,1]^d:
///   A, B                 two independent QMC samples (columns 1..d and d+1..2d of one scrambled sequence),
///   AB[i] (i = 0..d-1)   A with column i taken from B,
///   BA[i]                B with column i taken from A (second order only).
/// Stacked order (for files and batched evaluation): A, B, AB_1..AB_d, then BA_1..BA_d; N(d+2) or N(2d+2) rows.
/// With R replicates every block holds the R replicates one after the other (N/R rows each): replicate r is rows
/// r N/R .. (r + 1) N/R - 1 of every block, and replicate 0 is the design of `seed` at base N/R.
struct SaltelliDesign {
  int base = 0;
  int dimension = 0;
  bool second_order = false;
  std::uint64_t seed = 0;
  int replicates = 1;
  Eigen::MatrixXd a;
  Eigen::MatrixXd b;
  std::vector<Eigen::MatrixXd> ab;
  std::vector<Eigen::MatrixXd> ba;

  /// All blocks stacked in the order above.
  Eigen::MatrixXd stacked() const;
  /// Block code of every stacked row: 0 = A, 1 = B, 1 + i = AB_i, 1 + d + i = BA_i (i = 1..d).
  std::vector<int> block_codes() const;
  /// Number of stacked rows.
  int rows() const;
  /// Replicate (0..R-1) of every stacked row.
  std::vector<int> replicate_codes() const;
};

SaltelliDesign saltelli_design(const SaltelliOptions& options);

/// Block code -> "A", "B", "AB3", "BA2" (1-based input index), for CSV files.
std::string block_name(int code, int dimension);

/// Model outputs on the stacked rows of a Saltelli design, split by block.
struct SaltelliResponses {
  int dimension = 0;
  Eigen::VectorXd a;
  Eigen::VectorXd b;
  std::vector<Eigen::VectorXd> ab;
  std::vector<Eigen::VectorXd> ba;  ///< empty without second order
  std::vector<int> replicate;       ///< replicate (0..R-1) of every base row; empty for a design of one replicate
  int base() const { return static_cast<int>(a.size()); }
  bool second_order() const { return !ba.empty(); }
};

/// Splits stacked outputs (order of SaltelliDesign::stacked). Throws InputError when the length is not N(d+2) or
/// N(2d+2) as `second_order` says, or when a value is not finite (naming the row).
SaltelliResponses split_responses(const Eigen::VectorXd& stacked, int dimension, bool second_order);

/// Groups rows by block code (see SaltelliDesign::block_codes), as read back from a file: every block must have the
/// same number of rows, and rows of a block keep their order. Codes 0..2d+1; throws InputError naming the
/// offending row (0-based index + 1) for an unknown code or an uneven block.
SaltelliResponses group_responses(const Eigen::VectorXd& values, const std::vector<int>& codes, int dimension);

/// Rows of each block, grouped by block code as group_responses does: blocks[c] lists the rows with code c in file
/// order (A, B, AB_1..AB_d, then BA_1..BA_d when present). Throws DataError for an unknown code or an uneven block.
std::vector<std::vector<int>> block_rows(const std::vector<int>& codes, int dimension);

/// Replicate of every base row from the replicate column of a design read back from a file (`replicates[r]` for
/// stacked row r, any integer labels; `codes` as for block_rows): the t-th row of every block must carry the label of
/// the t-th row of block A, and every replicate must have the same number of base rows, at least 2. Returns the
/// replicate (0..R-1, in order of first appearance in block A) of each base row. Throws DataError naming the row.
std::vector<int> base_row_replicates(const std::vector<int>& codes, const std::vector<long long>& replicates,
                                     int dimension);

/// Checks the inputs of a Saltelli design read back from a file (x: rows x d, any scaling; codes as above): every
/// AB_i row is its A row with column i taken from its B row (BA_i likewise), and A and B are independent samples
/// (Spearman's rank correlation of each column within 5/sqrt(N - 1), checked from N = 32). Throws DataError(row,
/// column, detail) naming the first offending cell, or (-1, column) for correlated A and B.
void check_saltelli_inputs(const Eigen::MatrixXd& x, const std::vector<int>& codes, int dimension);

/// How sobol_indices() puts intervals on the indices (see the top of this file).
enum class SaltelliInterval {
  /// Student-t over the responses' independently scrambled replicates, valid for QMC; without replicates the
  /// estimates stand without an interval and the note says why.
  replicates,
  /// Percentile bootstrap over the base rows: conservative for QMC (often several times too wide), said in the note.
  bootstrap,
  /// Point estimates only.
  none,
};
/// "replicates" | "bootstrap" | "none"; throws InputError listing the valid names.
SaltelliInterval saltelli_interval_from_string(const std::string& name);
std::string to_string(SaltelliInterval interval);
/// The canonical names, in enum order.
std::vector<std::string> saltelli_interval_names();

struct SobolOptions {
  bool second_order = false;  ///< compute S2 (needs BA blocks)
  /// The replicates' interval by default; the bootstrap, whose intervals a QMC design makes too wide, only by name.
  SaltelliInterval interval = SaltelliInterval::replicates;
  int bootstrap = 200;         ///< resamples of the bootstrap interval, >= 0 (0: no interval, bounds = estimate)
  double confidence = 0.95;    ///< interval level, in (0, 1)
  std::uint64_t seed = 12345;  ///< bootstrap seed
  StopCheck stop;              ///< polled between bootstrap resamples and evaluated blocks (empty: never stops)
  void validate() const;       ///< throws InputError naming the field, value and rule
};

/// One index with its confidence interval (lower = upper = value when not bootstrapped or exact).
struct IndexEstimate {
  double value = 0.0;
  double lower = 0.0;
  double upper = 0.0;
};

struct SecondOrderIndex {
  int i = 0;  ///< 0-based input index, i < j
  int j = 0;
  IndexEstimate s;
};

/// Sobol' indices of one output; plain data (serialise every field).
struct SobolResult {
  std::string method;  ///< "saltelli-qmc", "rsm-exact", "metamodel-qmc"
  int dimension = 0;
  int base = 0;                          ///< N of the Saltelli design (0 for exact indices)
  int evaluations = 0;                   ///< model evaluations used (N(d+2) or N(2d+2); 0 for exact)
  double mean = 0.0;                     ///< E[f]
  double variance = 0.0;                 ///< V[f]
  std::vector<IndexEstimate> first;      ///< S1_i
  std::vector<IndexEstimate> total;      ///< ST_i
  std::vector<SecondOrderIndex> second;  ///< S2_ij, i < j, row-major; empty unless second order
  IndexEstimate residual;                ///< 1 - Σ S1_i (the paper's "Res" column, Tables 4-7)
  int bootstrap = 0;                     ///< resamples behind the intervals (0: none)
  int replicates = 0;                    ///< independent scramblings behind Student-t intervals (0: none)
  double confidence = 0.0;               ///< interval level
  std::uint64_t seed = 0;                ///< seed of the bootstrap (and of the design, where one was drawn)
  std::string note;  ///< what the intervals assume, or why intervals asked for are missing ("" when nothing to say)
};

/// Whether an output of this mean and variance is constant up to round-off: standard deviation <= 1e-12 |mean|
/// (about 5000 units in the last place; zero for an exactly constant output). Sobol' indices are then undefined.
bool negligible_variance(double mean, double variance);

/// Outputs beyond this magnitude are divided by their largest magnitude before any moment is taken (sobol_indices),
/// or refused where a metamodel would be fitted to them: their squares and sums leave double's range.
inline constexpr double k_large_output = 1e100;

/// Indices from outputs on a Saltelli design. Intervals (options.interval): `replicates`, with responses.replicate
/// (R >= 2 replicates), the pooled estimate +- t_{R-1} s / sqrt(R), s the standard deviation of the R replicate
/// estimates, and without replicates none, with a note saying why; `bootstrap`, the percentile bootstrap of
/// options.bootstrap resamples, with a note saying what it assumes. Throws NumericalError when the
/// output is constant up to round-off (negligible_variance), Stopped when options.stop says so. Outputs beyond
/// k_large_output in magnitude are scaled first (the indices do not change).
SobolResult sobol_indices(const SaltelliResponses& responses, const SobolOptions& options);

/// A model evaluated in batches: rows of x (on [0,1]^d) -> outputs.
using BatchModel = std::function<Eigen::VectorXd(const Eigen::MatrixXd& x)>;

/// Evaluates `model` on every block of `design` (polling options.stop between blocks) and computes the indices.
SobolResult sobol_indices(const BatchModel& model, const SaltelliDesign& design, const SobolOptions& options);

}  // namespace demsa::sobol
