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
// with percentile-bootstrap confidence intervals (resampling the N base rows, every block together).
//
// A and B are the two halves of ONE 2d-dimensional scrambled Sobol' sequence. Taking A and B as consecutive blocks
// of a d-dimensional sequence correlates them and biases the indices; saltelli_design() never does that.
#include "sobol/design.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace demsa::sobol {

/// Most inputs of a Saltelli design: A and B are the two halves of one 2d-dimensional Sobol' sequence.
inline constexpr int k_max_saltelli_dimension = k_max_sobol_dimension / 2;

struct SaltelliOptions {
  int base = 1024;             ///< N, rows of A and of B, >= 2 (a power of two gives the best balance)
  int dimension = 2;           ///< d, number of inputs, 1..20 (the 2d-dimensional sequence has at most 40)
  bool second_order = false;   ///< also build BA_i, needed for S2
  std::uint64_t seed = 12345;  ///< scrambling seed
  void validate() const;       ///< throws InputError naming the field, value and rule
};

/// The blocks of a Saltelli design, all N x d on [0,1]^d:
///   A, B                 two independent QMC samples (columns 1..d and d+1..2d of one scrambled sequence),
///   AB[i] (i = 0..d-1)   A with column i taken from B,
///   BA[i]                B with column i taken from A (second order only).
/// Stacked order (for files and batched evaluation): A, B, AB_1..AB_d, then BA_1..BA_d; N(d+2) or N(2d+2) rows.
struct SaltelliDesign {
  int base = 0;
  int dimension = 0;
  bool second_order = false;
  std::uint64_t seed = 0;
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

/// Checks the inputs of a Saltelli design read back from a file (x: rows x d, any scaling; codes as above): every
/// AB_i row is its A row with column i taken from its B row (BA_i likewise), and A and B are independent samples
/// (Spearman's rank correlation of each column within 5/sqrt(N - 1), checked from N = 32). Throws DataError(row,
/// column, detail) naming the first offending cell, or (-1, column) for correlated A and B.
void check_saltelli_inputs(const Eigen::MatrixXd& x, const std::vector<int>& codes, int dimension);

struct SobolOptions {
  bool second_order = false;   ///< compute S2 (needs BA blocks)
  int bootstrap = 200;         ///< percentile-bootstrap resamples, >= 0 (0: no interval, bounds = estimate)
  double confidence = 0.95;    ///< interval level, in (0, 1)
  std::uint64_t seed = 12345;  ///< bootstrap seed
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
  double confidence = 0.0;               ///< interval level
  std::uint64_t seed = 0;                ///< seed of the bootstrap (and of the design, where one was drawn)
  std::string note;  ///< why intervals asked for are missing ("" when they are present or were not asked for)
};

/// Indices from outputs on a Saltelli design.
SobolResult sobol_indices(const SaltelliResponses& responses, const SobolOptions& options);

/// A model evaluated in batches: rows of x (on [0,1]^d) -> outputs.
using BatchModel = std::function<Eigen::VectorXd(const Eigen::MatrixXd& x)>;

/// Evaluates `model` on every block of `design` and computes the indices.
SobolResult sobol_indices(const BatchModel& model, const SaltelliDesign& design, const SobolOptions& options);

}  // namespace demsa::sobol
