#include "orchestrator/util/csv.hpp"

#include "orchestrator/util/atomic_file.hpp"

#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/compile.h>
#include <fmt/core.h>

#include <array>
#include <cassert>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

namespace demsa::util {

namespace {

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(trim(field));
  if (!line.empty() && line.back() == ',') fields.emplace_back();  // a trailing empty cell
  return fields;
}

std::string unquote(const std::string& s) {
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return s.substr(1, s.size() - 2);
  return s;
}

bool blank_or_comment(const std::string& line) {
  const std::string t = trim(line);
  return t.empty() || t.front() == '#';
}

}  // namespace

bool CsvTable::has_column(const std::string& name) const {
  for (const std::string& c : columns)
    if (c == name) return true;
  return false;
}

int CsvTable::column_index(const std::string& name) const {
  for (std::size_t k = 0; k < columns.size(); ++k)
    if (columns[k] == name) return static_cast<int>(k);
  std::string list;
  for (const std::string& c : columns) list += (list.empty() ? "" : ", ") + c;
  throw UserError(file, header_line, fmt::format("no column '{}' (columns: {})", name, list));
}

Eigen::VectorXd CsvTable::column(const std::string& name) const { return values.col(column_index(name)); }

Eigen::MatrixXd CsvTable::select(const std::vector<std::string>& names) const {
  Eigen::MatrixXd out(values.rows(), static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) out.col(static_cast<Eigen::Index>(k)) = column(names[k]);
  return out;
}

std::string CsvTable::where(int row) const {
  assert(row >= 0 && row < rows());
  return fmt::format("{}:{}", file, lines[static_cast<std::size_t>(row)]);
}

void CsvTable::fail(int row, int column_index_, const std::string& message) const {
  const int line = row >= 0 && row < rows() ? lines[static_cast<std::size_t>(row)] : 0;
  const std::string text =
      column_index_ >= 0 && column_index_ < static_cast<int>(columns.size())
          ? fmt::format("column '{}': {}", columns[static_cast<std::size_t>(column_index_)], message)
          : message;
  throw UserError(file, line, text);
}

CsvTable parse_csv(const std::string& text, const std::string& file, const CsvReadOptions& options) {
  CsvTable table;
  table.file = file;
  std::istringstream in(text);
  std::string line;
  int line_number = 0;
  bool have_header = false;
  std::vector<std::vector<double>> rows;
  std::vector<bool> numeric;  // per column: parse its cells
  while (std::getline(in, line)) {
    ++line_number;
    if (blank_or_comment(line)) continue;
    std::vector<std::string> fields = split_fields(line);
    if (!have_header) {
      std::set<std::string> seen;
      for (std::size_t k = 0; k < fields.size(); ++k) {
        const std::string name = unquote(fields[k]);
        if (name.empty()) throw UserError(file, line_number, fmt::format("header: column {} has no name", k + 1));
        if (!seen.insert(name).second)
          throw UserError(file, line_number, fmt::format("duplicate column name '{}'", name));
        table.columns.push_back(name);
      }
      table.header_line = line_number;
      have_header = true;
      numeric.assign(table.columns.size(), options.numeric_columns.empty());
      for (const std::string& name : options.numeric_columns)
        for (std::size_t k = 0; k < table.columns.size(); ++k)
          if (table.columns[k] == name) numeric[k] = true;
      continue;
    }
    if (fields.size() != table.columns.size())
      throw UserError(file, line_number,
                      fmt::format("{} values for {} columns ({})", fields.size(), table.columns.size(),
                                  fields.size() < table.columns.size() ? "missing values" : "too many values"));
    std::vector<double> row(fields.size(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t k = 0; k < fields.size(); ++k) {
      if (!numeric[k]) continue;
      const std::string& cell = fields[k];
      const std::string where = fmt::format("column '{}'", table.columns[k]);
      if (cell.empty()) throw UserError(file, line_number, where + ": empty cell");
      errno = 0;
      char* end = nullptr;
      const double v = std::strtod(cell.c_str(), &end);
      if (end == cell.c_str() || *end != '\0')
        throw UserError(file, line_number, fmt::format("{}: '{}' is not a number", where, cell));
      if (errno == ERANGE && std::isinf(v))
        throw UserError(file, line_number, fmt::format("{}: '{}' is out of range", where, cell));
      if (!std::isfinite(v) && !options.allow_non_finite)
        throw UserError(file, line_number, fmt::format("{}: '{}' is not a finite number", where, cell));
      row[k] = v;
    }
    rows.push_back(std::move(row));
    table.lines.push_back(line_number);
  }
  if (!have_header) throw UserError(file, 0, "empty file (expected a header row of column names)");
  if (rows.empty() && !options.allow_empty) throw UserError(file, 0, "no data rows after the header");
  table.values.resize(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(table.columns.size()));
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t k = 0; k < rows[r].size(); ++k)
      table.values(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k)) = rows[r][k];
  return table;
}

CsvTable read_csv(const std::filesystem::path& file, const CsvReadOptions& options) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw UserError(file.string(), 0, "cannot open the file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_csv(text.str(), file.string(), options);
}

std::string format_csv(const std::vector<std::string>& header, const Eigen::MatrixXd& values) {
  assert(static_cast<std::size_t>(values.cols()) == header.size());
  std::string out;
  for (std::size_t k = 0; k < header.size(); ++k) out += (k ? "," : "") + header[k];
  out += '\n';
  // The shortest text that reads back to the same double (fmt's Dragonbox), formatted into one buffer without a
  // string per value: 2.5x faster than fmt::format("{:.17g}") on a 9.4-million-value Saltelli design.
  out.reserve(out.size() + static_cast<std::size_t>(values.size()) * 20);
  std::array<char, 64> cell{};
  for (Eigen::Index r = 0; r < values.rows(); ++r) {
    for (Eigen::Index k = 0; k < values.cols(); ++k) {
      if (k) out += ',';
      char* end = fmt::format_to(cell.data(), FMT_COMPILE("{}"), values(r, k));
      out.append(cell.data(), static_cast<std::size_t>(end - cell.data()));
    }
    out += '\n';
  }
  return out;
}

void write_csv(const std::filesystem::path& file, const std::vector<std::string>& header,
               const Eigen::MatrixXd& values) {
  write_file_atomically(file, format_csv(header, values));
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  for (const std::string& f : split_fields(text))
    if (!f.empty()) out.push_back(f);
  return out;
}

}  // namespace demsa::util
