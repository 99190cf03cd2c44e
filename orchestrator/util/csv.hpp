#pragma once
// Numeric CSV tables with a header row (design.csv, observables.csv, user data for `demsa sensitivity`).
//
// Reading: the first non-empty, non-comment line is the header (column names, unique, non-empty); every following
// non-empty line is one row of numbers. Lines starting with '#' are comments. Fields are separated by a comma
// (surrounding blanks ignored, optional double quotes around a name). Every error is a UserError that names the
// file, the line and, for a cell, the column and the value:
//   data.csv:7: column 'nu': 'abc' is not a number
//   data.csv:7: column 'nu': empty cell
//   data.csv:7: column 'nu': 'nan' is not a finite number
//   data.csv:9: 5 values for 6 columns
//   data.csv:1: duplicate column name 'E'
//   data.csv: no data rows
//
// Writing: a header row, then one row per sample with round-trip precision (%.17g).
#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace demsa::util {

struct CsvReadOptions {
  bool allow_non_finite = false;  ///< accept "nan", "inf" cells (otherwise an error naming the cell)
  bool allow_empty = false;       ///< accept a table with a header and no rows
  /// When not empty: only these columns are read as numbers; cells of the others (labels, notes) are not parsed and
  /// read as NaN. Names missing from the header are left for column_index() to report.
  std::vector<std::string> numeric_columns;
};

/// A numeric table read from a file. `values` is rows x columns; `lines[r]` is the 1-based line number of row r in
/// the file, for messages about a row found later (a duplicate point, a constant column).
struct CsvTable {
  std::string file;                  ///< name used in messages (the path as given)
  std::vector<std::string> columns;  ///< header, in file order
  Eigen::MatrixXd values;            ///< rows x columns
  std::vector<int> lines;            ///< file line of each row
  int header_line = 1;               ///< file line of the header

  int rows() const { return static_cast<int>(values.rows()); }
  bool has_column(const std::string& name) const;
  /// Index of a column; throws UserError "file: no column 'x' (columns: a, b, c)".
  int column_index(const std::string& name) const;
  /// One column by name.
  Eigen::VectorXd column(const std::string& name) const;
  /// Several columns by name, in the order given (throws for a missing one).
  Eigen::MatrixXd select(const std::vector<std::string>& names) const;
  /// "file:LINE" of row r (0-based), for messages.
  std::string where(int row) const;
  /// Throws UserError "file:LINE: column 'c': message" for row r and column index c (-1: no column).
  [[noreturn]] void fail(int row, int column, const std::string& message) const;
};

/// Reads a file; throws UserError when it cannot be opened or is malformed (see above).
CsvTable read_csv(const std::filesystem::path& file, const CsvReadOptions& options = {});
/// Parses CSV text; `file` is the name used in messages.
CsvTable parse_csv(const std::string& text, const std::string& file, const CsvReadOptions& options = {});

/// CSV text: header row, then the rows of `values` (each the shortest text that reads back to the same double).
/// values.cols() == header.size() (asserted).
std::string format_csv(const std::vector<std::string>& header, const Eigen::MatrixXd& values);
/// Writes format_csv(...) to `file` durably (util::write_file_atomically); throws IoError on I/O failure.
void write_csv(const std::filesystem::path& file, const std::vector<std::string>& header,
               const Eigen::MatrixXd& values);

/// Splits a comma-separated list ("a,b, c") into trimmed, non-empty names.
std::vector<std::string> split_list(const std::string& text);

}  // namespace demsa::util
