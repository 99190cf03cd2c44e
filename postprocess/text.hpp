#pragma once
// Small text helpers shared by the readers of LIGGGHTS's text files (log, plate files): a bounded line reader and
// word and number parsing.
#include "postprocess/error.hpp"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::postprocess {

/// What `path` is when it exists and is neither a regular file nor a folder ("a FIFO", "a socket", "a character
/// device", "a block device"), by stat(2), which does not block; none for a regular file (or a link to one), a folder
/// (each reader names it in its own words) and a path that does not exist. demsa's readers refuse such a path before
/// they open it: opening a FIFO for reading waits for a writer for ever, a terminal for its user.
std::optional<std::string> special_file_kind(const std::filesystem::path& path);
/// "a FIFO, not a regular file: ..." for a special_file_kind `kind` (the caller's error names the file).
std::string special_file_message(const std::string& kind);

/// The whitespace-separated words of a line.
std::vector<std::string> split_words(const std::string& line);

/// Parses the whole of `s` as a double (a leading '+' allowed). False when `s` is empty, has trailing characters,
/// or (with `finite_only`) is infinite or NaN.
bool parse_double(const std::string& s, double& value, bool finite_only = false);

/// A value from the user's file, fit to print in a message: quoted, at most 40 characters, non-printable bytes as
/// \xNN.
std::string shown(std::string_view s);

/// What a LineReader accepts. A line or a file beyond a limit is a ParseError naming the file and the line: the
/// reader never holds more than one line (plus one read block) whatever the input, /dev/zero included.
struct LineLimits {
  std::size_t max_line_bytes = std::size_t{1} << 20;  ///< longest line [bytes]; ≥ 256
  std::uint64_t max_bytes = 0;                        ///< largest file [bytes]; 0 = no limit (streaming readers)

  /// Throws std::invalid_argument naming the field, its value and the rule.
  void validate() const;
};

/// Reads a text file (or text in memory) line by line with LineLimits:
///
///   LineReader in(path, {.max_line_bytes = 1 << 20, .max_bytes = 256 << 20});  // or LineReader::of_text(...)
///   std::string_view line;
///   while (in.next(line)) { ... in.line() ... }
///
/// A line is returned without its '\n' and a '\r' before it; a last line without '\n' counts; a UTF-8 byte-order
/// mark at the start of the file is skipped (editors on Windows write one). The view stays valid until the next call.
class LineReader {
 public:
  /// Opens `path`; throws ParseError when it is a directory or cannot be opened.
  explicit LineReader(const std::filesystem::path& path, LineLimits limits = {});
  /// Reads `text` (not copied: it must outlive the reader); `name` stands for the file in messages.
  static LineReader of_text(std::string_view text, std::string name, LineLimits limits = {});
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;
  LineReader(LineReader&& other) noexcept;
  LineReader& operator=(LineReader&&) = delete;

  /// The next line; false at the end of the input. Throws ParseError on a line or a file beyond the limits, or a
  /// read error.
  bool next(std::string_view& line);
  /// 1-based number of the line last returned (0 before the first).
  long line() const { return m_line; }
  /// Bytes consumed so far.
  std::uint64_t bytes() const { return m_consumed; }
  /// The file name used in messages.
  const std::string& name() const { return m_name; }

 private:
  struct Text {};  // the constructor of of_text
  LineReader(Text, std::string name, LineLimits limits);
  bool refill();
  [[noreturn]] void too_long(std::string_view start) const;

  std::string m_name;
  LineLimits m_limits;
  std::FILE* m_file = nullptr;   // null for text in memory
  std::vector<char> m_storage;   // read buffer (file mode)
  const char* m_data = nullptr;  // valid bytes: m_data[m_begin, m_end)
  std::size_t m_begin = 0;
  std::size_t m_end = 0;
  bool m_eof = false;
  std::uint64_t m_consumed = 0;  // bytes before m_data[m_begin]
  std::uint64_t m_read = 0;      // bytes read from the source
  long m_line = 0;
};

}  // namespace demsa::postprocess
