#pragma once
// The CSV file of a Saltelli design (`demsa design saltelli` writes it, `demsa sensitivity --saltelli` reads it back),
// its one writer and its one reader:
//
//   block[,replicate],NAME1,...,NAMEd
//
// 'block' is the row's block code (0 = A, 1 = B, 1+i = AB_i, 1+d+i = BA_i, sobol::SaltelliDesign::block_codes()
// order), 'replicate' (1..R, only when R > 1) the independently scrambled replicate of the row, then one column per
// parameter, unit cube or physical. Response columns may be appended after them (the SALib habit): the reader is
// told their names.
#include "orchestrator/util/csv.hpp"
#include "sobol/saltelli.hpp"

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace demsa::analysis {

/// Writes `design` with the parameter values `values` (design.stacked(), scaled as the user asked) under the
/// parameter names `names`. Rows are written as they are formatted: a design of N = 2^17 in d = 7 is 161 MB of text
/// (bench/design-saltelli.sh).
void write_saltelli_design(const std::string& file, const sobol::SaltelliDesign& design, const Eigen::MatrixXd& values,
                           const std::vector<std::string>& names);

/// The file read as CSV, every column varying (a parameter held constant was not sampled: its indices would be
/// noise). Throws util::UserError naming the file and line.
util::CsvTable read_saltelli_csv(const std::string& file);

/// A Saltelli design read back from its file and checked.
struct SaltelliDesignFile {
  util::CsvTable table;                 ///< the file as read
  std::vector<std::string> parameters;  ///< parameter columns, in file order
  std::vector<int> parameter_columns;   ///< column of parameters[k] in `table`
  int block_column = -1;                ///< column 'block'
  int replicate_column = -1;            ///< column 'replicate', -1 when absent
  std::vector<int> codes;               ///< block code of every row
  std::vector<int> replicate;           ///< replicate (0..R-1) of every base row; empty without 'replicate'

  /// Independently scrambled replicates (1 without the column).
  int replicates() const;
  /// Base rows N of each replicate (the rows of block A over the replicates).
  int base() const;
};

/// Interprets `table` (read_saltelli_csv) as a Saltelli design whose columns other than 'block', 'replicate' and
/// `response_columns` are parameters: block codes in range, AB_i and BA_i rows made of their A and B rows, A and B
/// independent, replicates consistent (sobol::check_saltelli_inputs, sobol::base_row_replicates). Throws
/// util::UserError naming the file, line and column of the first offending cell.
SaltelliDesignFile saltelli_design_of(util::CsvTable table, const std::vector<std::string>& response_columns);

}  // namespace demsa::analysis
