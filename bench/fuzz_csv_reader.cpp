// libFuzzer target for the CSV reader (orchestrator/util/csv.cpp): any input must either parse or raise UserError,
// never crash, hang or hold more than the reader's limits; and the two ways in, parse_csv (text in memory) and
// read_csv (a stream read in blocks), must agree: the same table or the same message. Built and run by
// bench/fuzz-csv-reader.sh (needs clang++), not by CMake and not in CI.
#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>

namespace {

using demsa::util::CsvReadOptions;
using demsa::util::CsvTable;
using demsa::util::UserError;

void require(bool ok) {
  if (!ok) std::abort();  // the two readers disagree, or a broken promise: libFuzzer saves the input
}

struct Outcome {
  std::optional<CsvTable> table;
  std::string error;
};

template <class F>
Outcome attempt(F&& read) {
  Outcome out;
  try {
    out.table = read();
  } catch (const UserError& e) {
    out.error = e.what();
  }
  return out;
}

bool same_values(const CsvTable& a, const CsvTable& b) {
  if (a.values.rows() != b.values.rows() || a.values.cols() != b.values.cols()) return false;
  for (Eigen::Index r = 0; r < a.values.rows(); ++r)
    for (Eigen::Index c = 0; c < a.values.cols(); ++c) {
      const double x = a.values(r, c), y = b.values(r, c);
      if (!(x == y || (std::isnan(x) && std::isnan(y)))) return false;
    }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  CsvReadOptions options;
  options.max_line_bytes = 256;  // small limits, so that the fuzzer reaches them
  options.max_values = 4096;
  // The first byte picks the options, so both settings of each are explored; the rest is the file.
  const unsigned pick = data[0];
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  options.allow_non_finite = (pick & 1u) != 0;
  options.allow_empty = (pick & 2u) != 0;
  options.require_varying = (pick & 4u) != 0;
  if ((pick & 8u) != 0) options.numeric_columns = {"a", "y"};

  const Outcome parsed = attempt([&] { return demsa::util::parse_csv(text, "fuzz.csv", options); });
  const Outcome streamed = attempt([&] {
    std::istringstream in(text);
    return demsa::util::read_csv(in, "fuzz.csv", options);
  });
  require(parsed.error == streamed.error);
  require(parsed.table.has_value() == streamed.table.has_value());
  if (parsed.table) {
    const CsvTable& a = *parsed.table;
    const CsvTable& b = *streamed.table;
    require(a.columns == b.columns && a.lines == b.lines && a.header_line == b.header_line);
    require(same_values(a, b));
    require(static_cast<std::size_t>(a.values.size()) <= options.max_values);
    require(static_cast<std::size_t>(a.rows()) == a.lines.size());
    for (const std::string& c : a.columns) require(!c.empty());
  }
  // A byte-order mark at the start of the file changes nothing.
  const std::string bom = "\xEF\xBB\xBF";
  if (text.rfind(bom, 0) != 0) {
    const Outcome marked = attempt([&] { return demsa::util::parse_csv(bom + text, "fuzz.csv", options); });
    require(marked.error == parsed.error);
    require(marked.table.has_value() == parsed.table.has_value());
    if (parsed.table)
      require(marked.table->columns == parsed.table->columns && same_values(*marked.table, *parsed.table));
  }
  return 0;
}
