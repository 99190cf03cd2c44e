#include "postprocess/text.hpp"

#include <fmt/core.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace demsa::postprocess {

std::optional<std::string> special_file_kind(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);  // stat(2): follows links, never opens
  switch (status.type()) {
    case fs::file_type::regular:
    case fs::file_type::directory:  // each reader names a folder in its own words
    case fs::file_type::not_found:
    case fs::file_type::none:
      return std::nullopt;
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::socket:
      return "a socket";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::block:
      return "a block device";
    default:
      return ec ? std::nullopt : std::optional<std::string>("not a regular file");
  }
}

std::string special_file_message(const std::string& kind) {
  return fmt::format(
      "{}, not a regular file: demsa reads regular files only (a read from a FIFO or a device can wait "
      "for ever)",
      kind);
}

std::vector<std::string> split_words(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  std::string word;
  while (in >> word) out.push_back(word);
  return out;
}

bool parse_double(const std::string& s, double& value, bool finite_only) {
  const char* b = s.data();
  const char* e = b + s.size();
  if (b != e && *b == '+') ++b;
  const auto [ptr, ec] = std::from_chars(b, e, value);
  return ec == std::errc() && ptr == e && b != e && (!finite_only || std::isfinite(value));
}

std::string shown(std::string_view s) {
  std::string out;
  const std::size_t limit = 40;
  for (std::size_t i = 0; i < s.size() && i < limit; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f)
      out += static_cast<char>(c);
    else
      out += fmt::format("\\x{:02x}", c);
  }
  if (s.size() > limit) out += "...";
  return "'" + out + "'";
}

// ------------------------------------------------------------------------------------------------ LineReader

namespace {

constexpr std::size_t k_block = std::size_t{1} << 16;  // one read from the file
constexpr std::string_view k_bom = "\xEF\xBB\xBF";     // UTF-8 byte-order mark

std::string bytes_text(std::uint64_t n) {
  if (n >= (std::uint64_t{1} << 30) && n % (std::uint64_t{1} << 30) == 0) return fmt::format("{} GiB", n >> 30);
  if (n >= (std::uint64_t{1} << 20) && n % (std::uint64_t{1} << 20) == 0) return fmt::format("{} MiB", n >> 20);
  return fmt::format("{} bytes", n);
}

}  // namespace

void LineLimits::validate() const {
  if (max_line_bytes < 256)
    throw std::invalid_argument(fmt::format("LineLimits.max_line_bytes = {}: must be at least 256", max_line_bytes));
}

LineReader::LineReader(const std::filesystem::path& path, LineLimits limits) : m_name(path.string()), m_limits(limits) {
  m_limits.validate();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw ParseError(m_name, 0, "is a directory, not a text file");
  if (const std::optional<std::string> kind = special_file_kind(path))
    throw ParseError(m_name, 0, special_file_message(*kind));
  m_file = std::fopen(path.c_str(), "rb");
  if (m_file == nullptr) throw ParseError(m_name, 0, fmt::format("cannot open: {}", std::strerror(errno)));
  if (m_limits.max_bytes > 0 && std::filesystem::is_regular_file(path, ec)) {
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec && size > m_limits.max_bytes) {
      std::fclose(m_file);
      m_file = nullptr;
      throw ParseError(
          m_name, 0,
          fmt::format("{} bytes: larger than the {} this reader accepts", size, bytes_text(m_limits.max_bytes)));
    }
  }
  m_storage.resize(k_block + m_limits.max_line_bytes + 1);
  m_data = m_storage.data();
}

LineReader::LineReader(Text, std::string name, LineLimits limits) : m_name(std::move(name)), m_limits(limits) {
  m_limits.validate();
}

LineReader LineReader::of_text(std::string_view text, std::string name, LineLimits limits) {
  LineReader in(Text{}, std::move(name), limits);
  if (limits.max_bytes > 0 && text.size() > limits.max_bytes)
    throw ParseError(
        in.m_name, 0,
        fmt::format("{} bytes: larger than the {} this reader accepts", text.size(), bytes_text(limits.max_bytes)));
  in.m_data = text.data();
  in.m_end = text.size();
  in.m_read = text.size();
  in.m_eof = true;
  return in;
}

LineReader::LineReader(LineReader&& other) noexcept
    : m_name(std::move(other.m_name)),
      m_limits(other.m_limits),
      m_file(std::exchange(other.m_file, nullptr)),
      m_storage(std::move(other.m_storage)),
      m_data(other.m_data),  // a moved vector keeps its buffer
      m_begin(other.m_begin),
      m_end(other.m_end),
      m_eof(other.m_eof),
      m_consumed(other.m_consumed),
      m_read(other.m_read),
      m_line(other.m_line) {}

LineReader::~LineReader() {
  if (m_file != nullptr) std::fclose(m_file);
}

bool LineReader::refill() {
  if (m_file == nullptr || m_eof) return false;
  if (m_begin > 0) {
    std::memmove(m_storage.data(), m_storage.data() + m_begin, m_end - m_begin);
    m_end -= m_begin;
    m_begin = 0;
  }
  const std::size_t room = m_storage.size() - m_end;
  if (room == 0) return false;  // cannot happen: next() reports a long line before the buffer is full
  const std::size_t got = std::fread(m_storage.data() + m_end, 1, std::min(room, k_block), m_file);
  if (got == 0) {
    if (std::ferror(m_file))
      throw ParseError(m_name, m_line + 1, fmt::format("read error after {} bytes", m_consumed + (m_end - m_begin)));
    m_eof = true;
    return false;
  }
  m_read += got;
  if (m_limits.max_bytes > 0 && m_read > m_limits.max_bytes)
    throw ParseError(
        m_name, m_line + 1,
        fmt::format("the file goes on past {}, the most this reader accepts", bytes_text(m_limits.max_bytes)));
  m_end += got;
  m_data = m_storage.data();
  return true;
}

void LineReader::too_long(std::string_view start) const {
  throw ParseError(m_name, m_line + 1,
                   fmt::format("line longer than {} (it starts {}): not a text file of this kind",
                               bytes_text(m_limits.max_line_bytes), shown(start)));
}

bool LineReader::next(std::string_view& out) {
  std::size_t scanned = 0;  // bytes of the pending line already searched for '\n'
  for (;;) {
    const std::size_t pending = m_end - m_begin;
    const void* nl = scanned < pending ? std::memchr(m_data + m_begin + scanned, '\n', pending - scanned) : nullptr;
    const bool found = nl != nullptr;
    std::size_t length = pending;  // a last line without '\n'
    if (found) {
      length = static_cast<std::size_t>(static_cast<const char*>(nl) - (m_data + m_begin));
    } else {
      if (pending > m_limits.max_line_bytes) too_long(std::string_view(m_data + m_begin, 41));
      scanned = pending;
      if (refill()) continue;  // refill() may move the pending bytes to the start of the buffer
      if (pending == 0) return false;
    }
    if (length > m_limits.max_line_bytes) too_long(std::string_view(m_data + m_begin, 41));
    out = std::string_view(m_data + m_begin, length);
    const std::size_t used = length + (found ? 1 : 0);
    m_begin += used;
    m_consumed += used;
    ++m_line;
    if (m_line == 1 && out.substr(0, k_bom.size()) == k_bom) out.remove_prefix(k_bom.size());
    if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
    return true;
  }
}

}  // namespace demsa::postprocess
