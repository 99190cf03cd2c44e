#include "orchestrator/util/csv.hpp"

#include "orchestrator/util/atomic_file.hpp"

#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/compile.h>
#include <fmt/core.h>
#include <fmt/format.h>

#include <algorithm>
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
    if (feed_plain_numbers(text, line_number)) return;
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
        // The whole cell: strtod stops at a NUL inside it ("5\0 2.23" read as 5).
        if (end != copy.c_str() + copy.size())
          throw UserError(file, line_number,
                          fmt::format("{}: '{}' is not a number", where(), visible(std::string(cell))));
        if (errno == ERANGE && std::isinf(v))
          throw UserError(file, line_number, fmt::format("{}: '{}' is out of range", where(), cell));
      }
      if (!std::isfinite(v) && !m_options.allow_non_finite)
        throw UserError(file, line_number, fmt::format("{}: '{}' is not a finite number", where(), cell));
      m_values.push_back(v);
    }
    m_table.lines.push_back(line_number);
  }

  /// The common row in one pass: numeric columns only, each cell a number std::from_chars takes whole between
  /// optional blanks, the right count, finite (or non-finite allowed). Returns false, having added nothing, for any
  /// other row, which the general path below then reads and, if wrong, reports.
  bool feed_plain_numbers(std::string_view text, int line_number) {
    const std::size_t columns = m_table.columns.size();
    if (!m_all_numeric || m_values.size() + columns > m_options.max_values) return false;
    const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    const char* p = text.data();
    const char* const end = p + text.size();
    const std::size_t start = m_values.size();
    for (std::size_t k = 0;; ++k) {
      while (p < end && blank(*p)) ++p;
      double v = 0.0;
      const auto [next, ec] = std::from_chars(p, end, v);
      if (ec != std::errc() || next == p || k >= columns || (!std::isfinite(v) && !m_options.allow_non_finite)) {
        m_values.resize(start);
        return false;
      }
      m_values.push_back(v);
      p = next;
      while (p < end && blank(*p)) ++p;
      if (p == end) {
        if (k + 1 == columns) break;
        m_values.resize(start);
        return false;
      }
      if (*p != ',') {
        m_values.resize(start);
        return false;
      }
      ++p;
    }
    m_table.lines.push_back(line_number);
    return true;
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
    m_all_numeric = std::find(m_numeric.begin(), m_numeric.end(), false) == m_numeric.end();
  }

  const CsvReadOptions& m_options;
  CsvTable m_table;
  bool m_have_header = false;
  std::vector<bool> m_numeric;             // per column: parse its cells
  bool m_all_numeric = false;              // every column parsed: rows may take feed_plain_numbers
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
  // A FIFO or a socket would block the open or the read for ever (stat(2) only: nothing is opened); a device such as
  // /dev/zero ends at the reader's limits.
  const std::filesystem::file_type type = std::filesystem::status(file, ec).type();
  if (!ec && (type == std::filesystem::file_type::fifo || type == std::filesystem::file_type::socket))
    throw UserError(name, 0,
                    std::string(type == std::filesystem::file_type::fifo ? "a FIFO" : "a socket") +
                        ", not a regular file: demsa reads regular files only (a read from a FIFO or a device can "
                        "wait for ever)");
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
      if (nl == std::string_view::npos) {
        line.append(piece);
        break;
      }
      if (line.empty()) {  // the whole line is in this block: read it in place
        builder.feed(piece, ++line_number);
      } else {
        line.append(piece);
        builder.feed(line, ++line_number);
        line.clear();
      }
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
  for (std::size_t k = 0; k < header.size(); ++k) {
    if (k) out += ',';
    out += csv_header_cell(header[k]);
  }
  out += '\n';
  return out;
}

/// Appends one row, each cell by format_shortest, into one buffer without a string per value: a row of up to 16
/// cells is laid out on the stack and appended once.
void append_row(std::string& out, std::span<const double> cells) {
  constexpr std::size_t k_cells = 16;
  std::array<char, k_cells*(k_shortest_chars + 1) + 1>
      row;  // NOLINT(cppcoreguidelines-pro-type-member-init): written before read
  if (cells.size() <= k_cells) {
    char* end = row.data();
    for (std::size_t k = 0; k < cells.size(); ++k) {
      if (k) *end++ = ',';
      end = format_shortest(end, cells[k]);
    }
    *end++ = '\n';
    out.append(row.data(), static_cast<std::size_t>(end - row.data()));
    return;
  }
  for (std::size_t k = 0; k < cells.size(); ++k) {
    if (k) out += ',';
    char* end = format_shortest(row.data(), cells[k]);
    out.append(row.data(), static_cast<std::size_t>(end - row.data()));
  }
  out += '\n';
}

constexpr char k_digit_pairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

/// Writes the two digits of `n` < 100 ending at `end`; returns where they start.
char* write_pair(char* end, std::uint32_t n) {
  end -= 2;
  std::memcpy(end, k_digit_pairs + 2 * n, 2);
  return end;
}

/// Writes exactly eight digits of `n` < 10^8 (leading zeros kept) ending at `end`, in 32-bit arithmetic.
char* write_eight(char* end, std::uint32_t n) {
  const std::uint32_t high = n / 10000, low = n % 10000;
  end = write_pair(end, low % 100);
  end = write_pair(end, low / 100);
  end = write_pair(end, high % 100);
  return write_pair(end, high / 100);
}

/// The decimal digits of `n` (n > 0) ending at `end`; returns where they start. A double's shortest significand has
/// at most 17 digits: eight at a time, then the rest two at a time.
char* write_digits_backward(char* end, std::uint64_t n) {
  while (n >= 100000000) {
    end = write_eight(end, static_cast<std::uint32_t>(n % 100000000));
    n /= 100000000;
  }
  auto m = static_cast<std::uint32_t>(n);
  while (m >= 100) {
    end = write_pair(end, m % 100);
    m /= 100;
  }
  if (m >= 10) return write_pair(end, m);
  *--end = static_cast<char>('0' + m);
  return end;
}

}  // namespace

char* format_shortest(char* out, double value) {
  // Zero, infinities and NaN keep fmt's own spelling.
  if (value == 0.0 || !std::isfinite(value)) return fmt::format_to(out, FMT_COMPILE("{}"), value);
  if (std::signbit(value)) {
    *out++ = '-';
    value = -value;
  }
  const auto decimal = fmt::detail::dragonbox::to_decimal(value);  // value = significand * 10^exponent
  std::array<char, 24> digits{};
  char* const digits_end = digits.data() + digits.size();
  char* const first = write_digits_backward(digits_end, decimal.significand);
  const auto size = static_cast<int>(digits_end - first);
  // fmt's choice for the shortest form: scientific when the decimal exponent of the first digit is below -4 or at
  // least 16, fixed otherwise; no trailing ".0".
  const int scientific_exponent = decimal.exponent + size - 1;
  if (scientific_exponent < -4 || scientific_exponent >= 16) {
    *out++ = first[0];
    if (size > 1) {
      *out++ = '.';
      out = std::copy(first + 1, digits_end, out);
    }
    *out++ = 'e';
    *out++ = scientific_exponent < 0 ? '-' : '+';
    const int magnitude = std::abs(scientific_exponent);
    if (magnitude < 10) *out++ = '0';
    std::array<char, 4> exponent{};
    char* const e = write_digits_backward(exponent.data() + exponent.size(), static_cast<unsigned>(magnitude));
    return std::copy(e, exponent.data() + exponent.size(), out);
  }
  if (decimal.exponent >= 0) {  // an integer: the digits, then zeros
    out = std::copy(first, digits_end, out);
    return std::fill_n(out, decimal.exponent, '0');
  }
  const int point = size + decimal.exponent;  // digits before the decimal point
  if (point > 0) {
    out = std::copy(first, first + point, out);
    *out++ = '.';
    return std::copy(first + point, digits_end, out);
  }
  *out++ = '0';
  *out++ = '.';
  out = std::fill_n(out, -point, '0');
  return std::copy(first, digits_end, out);
}

std::string csv_header_cell(const std::string& name) {
  // A name that a spreadsheet would run as a formula (= + - @ first, or a tab or carriage return: OWASP, "CSV
  // Injection") is prefixed with a quote character; one with a comma, a double quote or a line break is quoted as
  // RFC 4180 §2 (6, 7) says, inner quotes doubled.
  const bool formula = !name.empty() && std::string_view("=+-@\t\r").find(name.front()) != std::string_view::npos;
  const bool quote = name.find_first_of(",\"\r\n") != std::string::npos;
  std::string cell;
  cell.reserve(name.size() + 4);
  if (quote) cell.push_back('"');
  if (formula) cell.push_back('\'');
  for (const char c : name) {
    cell.push_back(c);
    if (c == '"') cell.push_back('"');
  }
  if (quote) cell.push_back('"');
  return cell;
}

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
