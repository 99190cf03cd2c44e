// util/csv: the reader's limits (line, size, cell count; /dev/zero), a UTF-8 byte-order mark, a missing header, a
// constant column, and the agreement of its two ways in (text and stream); the streamed writer and the atomic file
// writer under it.
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"

#include "support/test_support.hpp"

#include <fmt/core.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

namespace demsa::util {
namespace {

std::string parse_error(const std::string& text, const CsvReadOptions& options = {}) {
  return test::message_of<UserError>([&] { parse_csv(text, "d.csv", options); });
}

TEST(CsvErrors, ANulInsideACellIsNotTheEndOfTheNumber) {
  // strtod stopped at the NUL: "5\0 2.23" was read as 5.
  const std::string text("a,b\n1,2\n5\0 2.23,3\n", 18);
  EXPECT_EQ(parse_error(text), "d.csv:3: column 'a': '5\\x00 2.23' is not a number");
  std::istringstream in(text);
  EXPECT_EQ(test::message_of<UserError>([&] { read_csv(in, "d.csv"); }),
            "d.csv:3: column 'a': '5\\x00 2.23' is not a number");
}

// format_shortest writes what fmt's "{}" writes, and the text reads back to the same double: every boundary of the
// fixed/scientific choice, zeros, infinities, NaN, subnormals, the extremes, and a million random bit patterns.
TEST(Csv, ShortestTextIsFmtsAndRoundTrips) {
  const auto check = [](double v) {
    std::array<char, k_shortest_chars> buffer{};
    const std::string ours(buffer.data(), format_shortest(buffer.data(), v));
    ASSERT_EQ(ours, fmt::format("{}", v)) << "bits " << std::bit_cast<std::uint64_t>(v);
    if (!std::isfinite(v)) return;
    double back = 0.0;
    const auto [end, ec] = std::from_chars(ours.data(), ours.data() + ours.size(), back);
    ASSERT_TRUE(ec == std::errc() && end == ours.data() + ours.size()) << ours;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(back), std::bit_cast<std::uint64_t>(v)) << ours;
  };
  using limits = std::numeric_limits<double>;
  for (const double v : {0.0,
                         -0.0,
                         1.0,
                         -1.0,
                         0.1,
                         0.5,
                         3.141592653589793,
                         -2.0,
                         10.0,
                         100.0,
                         1e-4,
                         1e-5,
                         1.5e-5,
                         9.999999999999999e-5,
                         1e15,
                         1e16,
                         1.2345e16,
                         9999999999999998.0,
                         123456789012345680.0,
                         limits::min(),
                         limits::denorm_min(),
                         limits::max(),
                         limits::lowest(),
                         limits::epsilon(),
                         limits::infinity(),
                         -limits::infinity(),
                         limits::quiet_NaN(),
                         2.475e-6,
                         1e100,
                         1e-100})
    check(v);
  for (int e = -30; e <= 30; ++e) {
    check(std::pow(10.0, e));
    check(-1.234567 * std::pow(10.0, e));
  }
  std::mt19937_64 rng(20241201);
  for (int i = 0; i < 1'000'000; ++i) check(std::bit_cast<double>(rng()));
  std::uniform_real_distribution<double> uniform(-3.2, 3.2);
  for (int i = 0; i < 100'000; ++i) check(uniform(rng));
}

TEST(Csv, ByteOrderMarkBeforeTheHeaderIsSkipped) {
  const CsvTable t = parse_csv(
      "\xEF\xBB\xBF"
      "a,b\r\n1,2\r\n",
      "d.csv");
  ASSERT_EQ(t.columns, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(t.column_index("a"), 0);
  EXPECT_DOUBLE_EQ(t.values(0, 1), 2.0);
  test::TempDir dir;
  test::write_file(dir / "d.csv",
                   "\xEF\xBB\xBF"
                   "a,b\n1,2\n");
  EXPECT_EQ(read_csv(dir / "d.csv").column_index("a"), 0);
}

TEST(Csv, InvisibleBytesInNamesAreShown) {
  // A mark inside the header (two files pasted together) stays in the name, but the message shows it.
  const CsvTable t = parse_csv(
      "a,\xEF\xBB\xBF"
      "b,c\t\n1,2,3\n",
      "d.csv");
  EXPECT_EQ(test::message_of<UserError>([&] { t.column_index("b"); }),
            "d.csv:1: no column 'b' (columns: a, <U+FEFF>b, c)");
  const CsvTable tab = parse_csv("a,\"c\x01\"\n1,2\n", "d.csv");
  EXPECT_EQ(test::message_of<UserError>([&] { tab.column_index("c"); }), "d.csv:1: no column 'c' (columns: a, c\\x01)");
}

TEST(Csv, MissingHeaderIsNamed) {
  EXPECT_EQ(parse_error("# outputs\n1.5,2.5\n3,4\n"),
            "d.csv:2: the first row holds numbers (1.5, ...), not column names: the file has no header row; put the "
            "column names on the first line");
  EXPECT_EQ(parse_error("0.25\n"),
            "d.csv:1: the first row holds numbers (0.25), not column names: the file has no header row; put the "
            "column names on the first line");
  // A header with one numeric name among others is a header.
  EXPECT_EQ(parse_csv("y,2\n1,2\n", "d.csv").columns.size(), 2u);
}

TEST(Csv, ConstantColumnRefusedWhenAsked) {
  const std::string text = "block,a,b\n0,0.5,0.1\n1,0.5,0.9\n2,0.5,0.3\n";
  EXPECT_EQ(parse_csv(text, "d.csv").rows(), 3);
  CsvReadOptions options;
  options.require_varying = true;
  EXPECT_EQ(parse_error(text, options),
            "d.csv:1: column 'a' holds 0.5 on every one of its 3 rows: a constant column is not a sampled parameter");
  EXPECT_EQ(parse_csv("a,b\n0.5,1\n", "d.csv", options).rows(), 1);  // one row: nothing to compare
}

TEST(Csv, LineAndSizeLimitsNameFileAndLine) {
  CsvReadOptions options;
  options.max_line_bytes = 256;
  const std::string text = "a,b\n1,2\n" + std::string(300, '7') + "\n";
  EXPECT_EQ(parse_error(text, options), "d.csv:3: line longer than 256 bytes: not a CSV table (binary data?)");
  std::istringstream in(text);
  EXPECT_EQ(test::message_of<UserError>([&] { read_csv(in, "d.csv", options); }),
            "d.csv:3: line longer than 256 bytes: not a CSV table (binary data?)");
  options.max_bytes = 10;
  EXPECT_EQ(parse_error("a,b\n1,2\n3,4\n", options), "d.csv: 12 bytes: larger than the 10 this reader accepts");
  std::istringstream in2(std::string(100000, '\n'));
  EXPECT_EQ(test::message_of<UserError>([&] { read_csv(in2, "d.csv", options); }),
            "d.csv:1: the file goes on past 10 bytes, the most this reader accepts");
  options = {};
  options.max_values = 4;
  EXPECT_EQ(parse_error("a,b\n1,2\n3,4\n5,6\n", options),
            "d.csv:4: more than 4 values: larger than this reader holds in memory");
}

TEST(Csv, DevZeroEndsQuicklyWithTheFileAndLine) {
  // Before: the whole of /dev/zero was read into memory until std::bad_alloc.
  EXPECT_EQ(test::message_of<UserError>([] { read_csv("/dev/zero"); }),
            "/dev/zero:1: line longer than 1048576 bytes: not a CSV table (binary data?)");
  // A FIFO would block the open for ever: refused before it is opened, naming it.
  test::TempDir tmp;
  const std::filesystem::path fifo = tmp / "responses.csv";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(test::message_of<UserError>([&] { read_csv(fifo); }),
            fifo.string() +
                ": a FIFO, not a regular file: demsa reads regular files only (a read from a FIFO or a "
                "device can wait for ever)");
}

TEST(Csv, TextAndStreamAgree) {
  std::string text = "# comment\nname,x,y\n";
  for (int i = 0; i < 20000; ++i) text += fmt::format("p{},{},0.5e-3\n", i, i);
  text += "last,1,2";  // no end of line
  CsvReadOptions options;
  options.numeric_columns = {"x", "y"};
  const CsvTable a = parse_csv(text, "d.csv", options);
  std::istringstream in(text);
  const CsvTable b = read_csv(in, "d.csv", options);
  EXPECT_EQ(a.rows(), 20001);
  EXPECT_EQ(a.lines, b.lines);
  EXPECT_EQ(a.header_line, 2);
  EXPECT_TRUE(a.values.col(1).isApprox(b.values.col(1)));
  EXPECT_DOUBLE_EQ(b.values(20000, 2), 2.0);
  EXPECT_EQ(b.lines.back(), 20003);
}

TEST(Csv, RowsWrittenInPiecesMatchTheWholeText) {
  // More than one 1 MiB piece: 60,000 rows of 3 values.
  Eigen::MatrixXd values(60000, 3);
  for (Eigen::Index r = 0; r < values.rows(); ++r)
    values.row(r) << static_cast<double>(r), 1.0 / (1.0 + static_cast<double>(r)), -0.1 * static_cast<double>(r);
  test::TempDir dir;
  write_csv(dir / "m.csv", {"a", "b", "c"}, values);
  write_csv_rows(dir / "r.csv", {"a", "b", "c"}, values.rows(), [&](Eigen::Index r, std::span<double> cells) {
    for (Eigen::Index k = 0; k < 3; ++k) cells[static_cast<std::size_t>(k)] = values(r, k);
  });
  const std::string whole = format_csv({"a", "b", "c"}, values);
  ASSERT_GT(whole.size(), std::size_t{1} << 20);
  EXPECT_EQ(test::read_file(dir / "m.csv"), whole);
  EXPECT_EQ(test::read_file(dir / "r.csv"), whole);
  EXPECT_FALSE(std::filesystem::exists(dir / "r.csv.tmp"));
}

TEST(AtomicFileWriter, AnExceptionBeforeCommitLeavesTheOldFileAndNoTemporary) {
  test::TempDir dir;
  test::write_file(dir / "d.csv", "old\n");
  EXPECT_THROW(write_csv_rows(dir / "d.csv", {"a"}, 10,
                              [](Eigen::Index r, std::span<double> cells) {
                                if (r == 5) throw std::runtime_error("stop");
                                cells[0] = static_cast<double>(r);
                              }),
               std::runtime_error);
  EXPECT_EQ(test::read_file(dir / "d.csv"), "old\n");
  EXPECT_FALSE(std::filesystem::exists(dir / "d.csv.tmp"));
  {
    AtomicFileWriter w(dir / "d.csv");
    w.append("new");
    EXPECT_EQ(test::read_file(dir / "d.csv"), "old\n");
    w.commit();
  }
  EXPECT_EQ(test::read_file(dir / "d.csv"), "new");
}

TEST(Csv, HeaderCellsAreNeverFormulasAndAreQuotedPerRfc4180) {
  EXPECT_EQ(csv_header_cell("settlement_1"), "settlement_1");
  EXPECT_EQ(csv_header_cell("=cmd|' /C calc'!A0"), "'=cmd|' /C calc'!A0");
  EXPECT_EQ(csv_header_cell("+1"), "'+1");
  EXPECT_EQ(csv_header_cell("-x"), "'-x");
  EXPECT_EQ(csv_header_cell("@sum"), "'@sum");
  EXPECT_EQ(csv_header_cell("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_header_cell("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_header_cell("two\nlines"), "\"two\nlines\"");
  const Eigen::MatrixXd values = Eigen::MatrixXd::Zero(1, 2);
  EXPECT_EQ(format_csv({"=a", "b,c"}, values), "'=a,\"b,c\"\n0,0\n");
}

}  // namespace
}  // namespace demsa::util
