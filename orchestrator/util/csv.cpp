#include "orchestrator/util/csv.hpp"

#include "orchestrator/util/atomic_file.hpp"

#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/compile.h>
#include <fmt/core.h>

#include <array>
#include <cassert>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace demsa::util {

namespace {

std::vector<std::string> split_fields(const std::string& line) {
  // Split in place (no stream per line: reading was most of `demsa sensitivity --saltelli` at N = 2^14).
  std::vector<std::string> fields;
  const std::string_view text(line);
  std::size_t start = 0;
  for (std::size_t comma = text.find(','); comma != std::string_view::npos; comma = text.find(',', start)) {
    fields.push_back(trim(text.substr(start, comma - start)));
    start = comma + 1;
  }
  if (start < text.size()) fields.push_back(trim(text.substr(start)));
  if (!line.empty() && line.back() == ',') fields.emplace_back();  // a trailing empty cell
  return fields;
}

/// The same as views into `line`, into `fields` (kept between rows, so a data row allocates nothing).
void split_field_views(std::string_view line, std::vector<std::string_view>& fields) {
  const auto trimmed = [](std::string_view cell) {
    const std::size_t begin = cell.find_first_not_of(" \t\r\n");  // the blanks of util::trim
    if (begin == std::string_view::npos) return std::string_view();
    return cell.substr(begin, cell.find_last_not_of(" \t\r\n") - begin + 1);
  };
  fields.clear();
  std::size_t start = 0;
  for (std::size_t comma = line.find(','); comma != std::string_view::npos; comma = line.find(',', start)) {
    fields.push_back(trimmed(line.substr(start, comma - start)));
    start = comma + 1;
  }
  if (start < line.size()) fields.push_back(trimmed(line.substr(start)));
  if (!line.empty() && line.back() == ',') fields.emplace_back();  // a trailing empty cell
}

std::string unquote(const std::string& s) {
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return s.substr(1, s.size() - 2);
  return s;
}

bool blank_or_comment(std::string_view line) {
  const std::size_t first = line.find_first_not_of(" \t\r\n");  // the blanks of util::trim
  return first == std::string_view::npos || line[first] == '#';
}

constexpr std::string_view k_bom = "\xEF\xBB\xBF";  // UTF-8 byte-order mark (editors on Windows write one)

/// A name as it can be read in a message: control bytes as \xNN and a byte-order mark (invisible in a terminal) as
/// <U+FEFF>, so that "no column 'a'" never lists an 'a' that differs from it invisibly.
std::string visible(const std::string& name) {
  std::string out;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    if (name.compare(i, k_bom.size(), k_bom) == 0) {
      out += "<U+FEFF>";
      i += k_bom.size() - 1;
    } else if (c < 0x20 || c == 0x7f) {
      out += fmt::format("\\x{:02x}", c);
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
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
  for (const std::string& c : columns) list += (list.empty() ? "" : ", ") + visible(c);
  throw UserError(file, header_line, fmt::format("no column '{}' (columns: {})", visible(name), list));
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

namespace {

/// Builds a CsvTable from lines fed one at a time (the rules of csv.hpp), holding the numbers in one flat array.
class CsvBuilder {
 public:
  CsvBuilder(const std::string& file, const CsvReadOptions& options) : m_options(options) { m_table.file = file; }

  void feed(std::string_view text, int line_number) {
    if (blank_or_comment(text)) return;
    if (!m_have_header) {
      header(split_fields(std::string(text)), line_number);
      return;
    }
    std::vector<std::string_view>& fields = m_fields;
    split_field_views(text, fields);
    const std::string& file = m_table.file;
    const std::vector<std::string>& columns = m_table.columns;
    if (fields.size() != columns.size())
      throw UserError(file, line_number,
                      fmt::format("{} values for {} columns ({})", fields.size(), columns.size(),
                                  fields.size() < columns.size() ? "missing values" : "too many values"));
    if (m_values.size() + fields.size() > m_options.max_values)
      throw UserError(
          file, line_number,
          fmt::format("more than {} values: larger than this reader holds in memory", m_options.max_values));
    for (std::size_t k = 0; k < fields.size(); ++k) {
      if (!m_numeric[k]) {
        m_values.push_back(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      const std::string_view cell = fields[k];
      const auto where = [&] { return fmt::format("column '{}'", columns[k]); };  // only for a message
      if (cell.empty()) throw UserError(file, line_number, where() + ": empty cell");
      // std::from_chars (fast_float in libstdc++ 12: Lemire 2021, "Number parsing at a gigabyte per second") reads
      // the plain decimal numbers of a design 3-5 times faster than strtod; anything else it does not take whole (a
      // leading '+', hexadecimal, an overflow) goes to strtod, whose rules the messages below follow.
      double v = 0.0;
      const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
      if (ec != std::errc() || ptr != cell.data() + cell.size()) {
        const std::string copy(cell);  // strtod reads up to a NUL
        errno = 0;
        char* end = nullptr;
        v = std::strtod(copy.c_str(), &end);
        if (end == copy.c_str() || *end != '\0')
          throw UserError(file, line_number, fmt::format("{}: '{}' is not a number", where(), cell));
        if (errno == ERANGE && std::isinf(v))
          throw UserError(file, line_number, fmt::format("{}: '{}' is out of range", where(), cell));
      }
      if (!std::isfinite(v) && !m_options.allow_non_finite)
        throw UserError(file, line_number, fmt::format("{}: '{}' is not a finite number", where(), cell));
      m_values.push_back(v);
    }
    m_table.lines.push_back(line_number);
  }

  CsvTable finish() {
    const std::string& file = m_table.file;
    if (!m_have_header) throw UserError(file, 0, "empty file (expected a header row of column names)");
    const std::size_t rows = m_table.lines.size();
    if (rows == 0 && !m_options.allow_empty) throw UserError(file, 0, "no data rows after the header");
    const auto ncol = static_cast<Eigen::Index>(m_table.columns.size());
    m_table.values = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        m_values.data(), static_cast<Eigen::Index>(rows), ncol);
    m_values = {};
    if (m_options.require_varying && rows >= 2)
      for (Eigen::Index k = 0; k < ncol; ++k) {
        if (!m_numeric[static_cast<std::size_t>(k)]) continue;
        const double first = m_table.values(0, k);
        if ((m_table.values.col(k).array() == first).all())
          throw UserError(file, m_table.header_line,
                          fmt::format("column '{}' holds {} on every one of its {} rows: a constant column is not "
                                      "a sampled parameter",
                                      m_table.columns[static_cast<std::size_t>(k)], first, rows));
      }
    return std::move(m_table);
  }

 private:
  void header(const std::vector<std::string>& fields, int line_number) {
    const std::string& file = m_table.file;
    std::set<std::string> seen;
    bool all_numbers = true;
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const std::string name = unquote(fields[k]);
      if (name.empty()) throw UserError(file, line_number, fmt::format("header: column {} has no name", k + 1));
      if (!seen.insert(name).second)
        throw UserError(file, line_number, fmt::format("duplicate column name '{}'", name));
      all_numbers = all_numbers && parse_number(name).has_value();
      m_table.columns.push_back(name);
    }
    // A file whose first row is numbers has no header: reading that row as names would lose it and then report
    // a row count or a missing column that does not say why.
    if (all_numbers)
      throw UserError(file, line_number,
                      fmt::format("the first row holds numbers ({}{}), not column names: the file has no header "
                                  "row; put the column names on the first line",
                                  fields.front(), fields.size() > 1 ? ", ..." : ""));
    m_table.header_line = line_number;
    m_have_header = true;
    m_numeric.assign(m_table.columns.size(), m_options.numeric_columns.empty());
    for (const std::string& name : m_options.numeric_columns)
      for (std::size_t k = 0; k < m_table.columns.size(); ++k)
        if (m_table.columns[k] == name) m_numeric[k] = true;
  }

  const CsvReadOptions& m_options;
  CsvTable m_table;
  bool m_have_header = false;
  std::vector<bool> m_numeric;             // per column: parse its cells
  std::vector<double> m_values;            // row-major
  std::vector<std::string_view> m_fields;  // the cells of the row being read
};

[[noreturn]] void line_too_long(const std::string& file, int line_number, std::size_t limit) {
  throw UserError(file, line_number, fmt::format("line longer than {} bytes: not a CSV table (binary data?)", limit));
}

}  // namespace

void CsvReadOptions::validate() const {
  if (max_line_bytes < 256)
    throw std::invalid_argument(
        fmt::format("CsvReadOptions.max_line_bytes = {}: must be at least 256", max_line_bytes));
  if (max_bytes < 1) throw std::invalid_argument("CsvReadOptions.max_bytes = 0: must be at least 1");
}

CsvTable parse_csv(const std::string& text, const std::string& file, const CsvReadOptions& options) {
  options.validate();
  if (text.size() > options.max_bytes)
    throw UserError(file, 0,
                    fmt::format("{} bytes: larger than the {} this reader accepts", text.size(), options.max_bytes));
  CsvBuilder builder(file, options);
  std::string_view rest(text);
  if (rest.substr(0, k_bom.size()) == k_bom) rest.remove_prefix(k_bom.size());
  int line_number = 0;
  while (!rest.empty()) {
    const std::size_t nl = rest.find('\n');
    const std::string_view line = rest.substr(0, nl);
    ++line_number;
    if (line.size() > options.max_line_bytes) line_too_long(file, line_number, options.max_line_bytes);
    builder.feed(line, line_number);
    rest.remove_prefix(nl == std::string_view::npos ? rest.size() : nl + 1);
  }
  return builder.finish();
}

CsvTable read_csv(const std::filesystem::path& file, const CsvReadOptions& options) {
  const std::string name = file.string();
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw UserError(name, 0, "is a folder, not a CSV file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw UserError(name, 0, fmt::format("cannot open the file: {}", std::strerror(errno)));
  return read_csv(in, name, options);
}

CsvTable read_csv(std::istream& in, const std::string& name, const CsvReadOptions& options) {
  options.validate();
  // Streamed in blocks, one line at a time: memory stays bounded by the limits whatever the file (/dev/zero too).
  CsvBuilder builder(name, options);
  std::vector<char> block(std::size_t{1} << 16);
  std::string line;
  std::uint64_t total = 0;
  int line_number = 0;
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    if (got == 0) break;
    total += got;
    if (total > options.max_bytes)
      throw UserError(name, line_number + 1,
                      fmt::format("the file goes on past {} bytes, the most this reader accepts", options.max_bytes));
    std::string_view chunk(block.data(), got);
    if (total == got && chunk.substr(0, k_bom.size()) == k_bom) chunk.remove_prefix(k_bom.size());  // first block
    while (!chunk.empty()) {
      const std::size_t nl = chunk.find('\n');
      const std::string_view piece = chunk.substr(0, nl);
      if (line.size() + piece.size() > options.max_line_bytes)
        line_too_long(name, line_number + 1, options.max_line_bytes);
      line.append(piece);
      if (nl == std::string_view::npos) break;
      builder.feed(line, ++line_number);
      line.clear();
      chunk.remove_prefix(nl + 1);
    }
  }
  if (in.bad()) throw UserError(name, line_number + 1, "read error");
  if (!line.empty()) builder.feed(line, ++line_number);
  return builder.finish();
}

namespace {

std::string header_line(const std::vector<std::string>& header) {
  std::string out;
  for (std::size_t k = 0; k < header.size(); ++k) out += (k ? "," : "") + header[k];
  out += '\n';
  return out;
}

/// Appends one row: the shortest text that reads back to the same double (fmt's Dragonbox), formatted into one
/// buffer without a string per value (2.5x faster than fmt::format("{:.17g}") on a 9.4-million-value design).
void append_row(std::string& out, std::span<const double> cells) {
  std::array<char, 64> cell{};
  for (std::size_t k = 0; k < cells.size(); ++k) {
    if (k) out += ',';
    char* end = fmt::format_to(cell.data(), FMT_COMPILE("{}"), cells[k]);
    out.append(cell.data(), static_cast<std::size_t>(end - cell.data()));
  }
  out += '\n';
}

}  // namespace

std::string format_csv(const std::vector<std::string>& header, const Eigen::MatrixXd& values) {
  assert(static_cast<std::size_t>(values.cols()) == header.size());
  std::string out = header_line(header);
  out.reserve(out.size() + static_cast<std::size_t>(values.size()) * 20);
  std::vector<double> cells(header.size());
  for (Eigen::Index r = 0; r < values.rows(); ++r) {
    for (Eigen::Index k = 0; k < values.cols(); ++k) cells[static_cast<std::size_t>(k)] = values(r, k);
    append_row(out, cells);
  }
  return out;
}

void write_csv(const std::filesystem::path& file, const std::vector<std::string>& header,
               const Eigen::MatrixXd& values) {
  assert(static_cast<std::size_t>(values.cols()) == header.size());
  write_csv_rows(file, header, values.rows(), [&](Eigen::Index r, std::span<double> cells) {
    for (Eigen::Index k = 0; k < values.cols(); ++k) cells[static_cast<std::size_t>(k)] = values(r, k);
  });
}

void write_csv_rows(const std::filesystem::path& file, const std::vector<std::string>& header, Eigen::Index rows,
                    const std::function<void(Eigen::Index, std::span<double>)>& row) {
  // Pieces of ~1 MiB stay in the cache: building the whole text first cost a page fault per 4 KiB of it and half the
  // time of a 161 MB design (bench/design-saltelli.sh).
  constexpr std::size_t k_piece = std::size_t{1} << 20;
  AtomicFileWriter writer(file);
  std::string out = header_line(header);
  out.reserve(k_piece + 4096);
  std::vector<double> cells(header.size());
  for (Eigen::Index r = 0; r < rows; ++r) {
    row(r, cells);
    append_row(out, cells);
    if (out.size() >= k_piece) {
      writer.append(out);
      out.clear();
    }
  }
  writer.append(out);
  writer.commit();
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  for (const std::string& f : split_fields(text))
    if (!f.empty()) out.push_back(f);
  return out;
}

}  // namespace demsa::util
