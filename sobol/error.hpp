#pragma once
// Errors a caller's input can cause in demsa::sobol (bad data, bad options). The message names the source
// (file, row, column, value) when there is one; programming errors are assertions instead.
#include <stdexcept>
#include <string>

namespace demsa::sobol {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

/// A problem with one sample or one input column of a data set (a constant column, a duplicated point, a NaN).
/// The library knows only row and column indices; a caller that read the data from a file rewrites the message
/// with the file name, its line number and the column name (see orchestrator/csv.hpp).
class DataError : public InputError {
 public:
  /// `row`: 0-based sample index, or -1; `column`: 0-based input column, or -1; `detail`: what is wrong, without
  /// position (e.g. "duplicates the point of sample 3").
  /// `other_row`: a second sample the problem involves (the first copy of a duplicated point), or -1.
  DataError(int row, int column, const std::string& detail, int other_row = -1)
      : InputError(describe(row, column, detail)),
        m_row(row),
        m_column(column),
        m_other_row(other_row),
        m_detail(detail) {}
  int row() const { return m_row; }
  int column() const { return m_column; }
  int other_row() const { return m_other_row; }
  const std::string& detail() const { return m_detail; }

 private:
  static std::string describe(int row, int column, const std::string& detail) {
    std::string where;
    if (row >= 0) where += "sample " + std::to_string(row + 1);
    if (column >= 0) where += (where.empty() ? "" : ", ") + std::string("input ") + std::to_string(column + 1);
    return where.empty() ? detail : where + ": " + detail;
  }
  int m_row;
  int m_column;
  int m_other_row;
  std::string m_detail;
};

/// A numerical failure that the input caused (singular system, no convergence): the caller decides.
class NumericalError : public std::runtime_error {
 public:
  explicit NumericalError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace demsa::sobol
