// The bounded line reader under the plate-file and log readers: lines, end of line, BOM, and its two limits.
#include "postprocess/text.hpp"

#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <string>
#include <vector>

namespace demsa::postprocess {
namespace {

std::vector<std::string> lines_of(LineReader& in) {
  std::vector<std::string> out;
  std::string_view line;
  while (in.next(line)) out.emplace_back(line);
  return out;
}

TEST(LineReader, LinesWithoutEndOfLineCarriageReturnOrBom) {
  const std::string text =
      "\xEF\xBB\xBF"
      "a b\r\n\nc\n\xEF\xBB\xBF"
      "d";
  LineReader in = LineReader::of_text(text, "t.txt");
  EXPECT_EQ(lines_of(in), (std::vector<std::string>{"a b", "", "c",
                                                    "\xEF\xBB\xBF"
                                                    "d"}));
  EXPECT_EQ(in.line(), 4);
  EXPECT_EQ(in.bytes(), text.size());
}

TEST(LineReader, FileAndMemoryGiveTheSameLinesAcrossReadBlocks) {
  // Lines that straddle the 64 KiB read blocks of the file mode.
  std::string text;
  for (int i = 0; i < 20000; ++i)
    text += std::to_string(i * 7919) + " " + std::string(static_cast<std::size_t>(i % 13), 'x') + "\n";
  test::TempDir dir;
  test::write_file(dir / "t.txt", text);
  LineReader memory = LineReader::of_text(text, "t.txt");
  LineReader file(dir / "t.txt");
  const std::vector<std::string> a = lines_of(memory);
  EXPECT_EQ(a.size(), 20000u);
  EXPECT_EQ(lines_of(file), a);
}

TEST(LineReader, LineLimitNamesFileAndLine) {
  const std::string text = "ok\n" + std::string(300, 'z') + "\nnever read\n";
  LineReader in = LineReader::of_text(text, "t.txt", {256, 0});
  std::string_view line;
  ASSERT_TRUE(in.next(line));
  EXPECT_EQ(test::message_of<ParseError>([&] { in.next(line); }),
            "t.txt:2: line longer than 256 bytes (it starts 'zzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzz...'): not a text "
            "file of this kind");
  // A line of exactly the limit is accepted.
  const std::string longest(256, 'z');
  LineReader exact = LineReader::of_text(longest, "t.txt", {256, 0});
  EXPECT_EQ(lines_of(exact).front().size(), 256u);
}

TEST(LineReader, SizeLimitOnFilesMemoryAndEndlessStreams) {
  test::TempDir dir;
  std::string text;
  for (int i = 0; i < 1000; ++i) text += "1 2 3\n";
  test::write_file(dir / "t.txt", text);
  EXPECT_EQ(test::message_of<ParseError>([&] {
              LineReader in(dir / "t.txt", {256, 4096});
            }),
            (dir / "t.txt").string() + ": 6000 bytes: larger than the 4096 bytes this reader accepts");
  EXPECT_EQ(test::message_of<ParseError>([&] {
              LineReader::of_text(text, "t.txt", {256, 4096});
            }),
            "t.txt: 6000 bytes: larger than the 4096 bytes this reader accepts");
  // Endless streams (/dev/zero, /dev/urandom) and FIFOs are not regular files: refused before they are opened, as a
  // FIFO without a writer would block the open for ever (issue 45).
  for (const char* device : {"/dev/zero", "/dev/urandom"})
    EXPECT_EQ(test::message_of<ParseError>([&] {
                LineReader in(device, {1 << 16, 1 << 20});
              }),
              std::string(device) +
                  ": a character device, not a regular file: demsa reads regular files only (a read from a FIFO "
                  "or a device can wait for ever)");
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
  EXPECT_EQ(test::message_of<ParseError>([&] {
              LineReader in(dir / "fifo", {1 << 16, 1 << 20});
            }).rfind((dir / "fifo").string() + ": a FIFO, not a regular file", 0),
            0u);
}

TEST(LineReader, DirectoryAndMissingFile) {
  test::TempDir dir;
  EXPECT_EQ(test::message_of<ParseError>([&] { LineReader in(dir.path()); }),
            dir.path().string() + ": is a directory, not a text file");
  EXPECT_THROW(LineReader(dir / "missing.txt"), ParseError);
  EXPECT_THROW(LineReader::of_text("", "t", {100, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace demsa::postprocess
