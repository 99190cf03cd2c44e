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
//   data.csv:1: the first row holds numbers (0.5, ...), not column names: the file has no header row; ...
//   data.csv:3: line longer than 1048576 bytes: not a CSV table (binary data?)
// A UTF-8 byte-order mark before the header is skipped. The reader streams the file and holds one line and the
// numbers read so far: a file beyond max_bytes or max_values is refused, whatever its size (/dev/zero included).
//
// Writing: a header row, then one row per sample with round-trip precision (%.17g).
#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <istream>
#include <span>
#include <string>
#include <vector>

namespace demsa::util {

struct CsvReadOptions {
  bool allow_non_finite = false;  ///< accept "nan", "inf" cells (otherwise an error naming the cell)
  bool allow_empty = false;       ///< accept a table with a header and no rows
  /// When not empty: only these columns are read as numbers; cells of the others (labels, notes) are not parsed and
  /// read as NaN. Names missing from the header are left for column_index() to report.
  std::vector<std::string> numeric_columns;
  /// Every numeric column must take at least two values when the table has two rows or more (a Saltelli design
  /// samples each of its parameters); a constant column is a UserError naming it and its value.
  bool require_varying = false;
  std::size_t max_line_bytes = std::size_t{1} << 20;  ///< longest line [bytes]; ≥ 256
  std::uint64_t max_bytes = std::uint64_t{1} << 30;   ///< largest file [bytes]; ≥ 1
  std::size_t max_values = std::size_t{1} << 27;      ///< most cells held (8 bytes each: 1 GiB); a data set beyond
                                                      ///< it does not fit the analysis either

  /// Throws std::invalid_argument naming the field, its value and the rule.
  void validate() const;
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
/// Reads a stream (what read_csv(path) does once the file is open); `file` is the name used in messages.
CsvTable read_csv(std::istream& in, const std::string& file, const CsvReadOptions& options = {});
/// Parses CSV text; `file` is the name used in messages.
CsvTable parse_csv(const std::string& text, const std::string& file, const CsvReadOptions& options = {});

/// Writes the shortest decimal text that reads back to exactly `value` (Dragonbox: Jeon 2020, "Dragonbox: A New
/// Floating-Point Binary-to-Decimal Conversion Algorithm"), character for character what fmt::format("{}", value)
/// writes, at `out` (room for k_shortest_chars); returns the end. The digits are laid out here rather than by
/// fmt's general writer, which cost more than the conversion itself.
inline constexpr std::size_t k_shortest_chars = 32;
char* format_shortest(char* out, double value);

/// CSV text: header row, then the rows of `values` (each the shortest text that reads back to the same double).
/// values.cols() == header.size() (asserted).
std::string format_csv(const std::vector<std::string>& header, const Eigen::MatrixXd& values);
/// One header cell as the writers put it: a name beginning with = + - @ (a spreadsheet formula) prefixed with ',
/// and quoted per RFC 4180 when it holds a comma, a double quote or a line break. Plain names are unchanged.
std::string csv_header_cell(const std::string& name);
/// Writes format_csv(...) to `file` durably (util::write_file_atomically); throws IoError on I/O failure.
void write_csv(const std::filesystem::path& file, const std::vector<std::string>& header,
               const Eigen::MatrixXd& values);
/// The same for a table too large to copy (a Saltelli design of millions of rows): `row(r, cells)` fills the
/// header.size() numbers of row r; the text goes to the file in pieces of about 1 MiB, never whole in memory.
void write_csv_rows(const std::filesystem::path& file, const std::vector<std::string>& header, Eigen::Index rows,
                    const std::function<void(Eigen::Index, std::span<double>)>& row);

/// Splits a comma-separated list ("a,b, c") into trimmed, non-empty names.
std::vector<std::string> split_list(const std::string& text);

}  // namespace demsa::util
