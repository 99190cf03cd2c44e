#include "postprocess/dump.hpp"

#include "postprocess/text.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <stdexcept>
#include <utility>

namespace demsa::postprocess {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

/// Splits on blanks.
std::vector<std::string_view> split(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_blank(s[i])) ++i;
    const std::size_t start = i;
    while (i < s.size() && !is_blank(s[i])) ++i;
    if (i > start) out.push_back(s.substr(start, i - start));
  }
  return out;
}

std::string join(const std::vector<std::string_view>& parts) {
  std::string out;
  for (std::string_view part : parts) {
    if (!out.empty()) out.push_back(' ');
    out.append(part);
  }
  return out;
}

std::string_view first_token(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size() && !is_blank(s[i])) ++i;
  return s.substr(0, i);
}

/// Parses a whole token as a finite double (std::from_chars: no locale, no allocation).
bool parse_double(std::string_view token, double& value) {
  const char* b = token.data();
  const char* e = b + token.size();
  if (b != e && *b == '+') ++b;
  const auto [ptr, ec] = std::from_chars(b, e, value);
  return ec == std::errc() && ptr == e && b != e && std::isfinite(value);
}

bool parse_long(std::string_view token, long& value) {
  const char* b = token.data();
  const char* e = b + token.size();
  if (b != e && *b == '+') ++b;
  const auto [ptr, ec] = std::from_chars(b, e, value);
  return ec == std::errc() && ptr == e && b != e;
}

bool starts_with_item(std::string_view line, std::string_view item) {
  line = trim(line);
  return line.substr(0, item.size()) == item;
}

}  // namespace

// ------------------------------------------------------------------------------------------------ DumpFrame

int DumpFrame::column_index(std::string_view name) const {
  for (std::size_t c = 0; c < columns.size(); ++c)
    if (columns[c] == name) return static_cast<int>(c);
  return -1;
}

std::span<const double> DumpFrame::column(std::string_view name) const {
  const int c = column_index(name);
  if (c < 0) {
    std::vector<std::string_view> names(columns.begin(), columns.end());
    throw ParseError(file, atoms_line, fmt::format("ITEM: ATOMS has no column '{}' (columns: {})", name, join(names)));
  }
  return values[static_cast<std::size_t>(c)];
}

void DumpReaderOptions::validate() const {
  if (buffer_bytes < 4096)
    throw std::invalid_argument(
        fmt::format("DumpReaderOptions.buffer_bytes = {}: must be at least 4096", buffer_bytes));
  if (max_line_bytes < 256)
    throw std::invalid_argument(
        fmt::format("DumpReaderOptions.max_line_bytes = {}: must be at least 256", max_line_bytes));
}

// ------------------------------------------------------------------------------------------------ DumpReader

struct DumpReader::Impl {
  DumpReaderOptions options;
  std::string name;            // file name in messages
  std::filesystem::path path;  // empty for in-memory text
  std::FILE* file = nullptr;   // null for in-memory text
  std::vector<char> storage;   // read buffer (file mode)
  const char* data = nullptr;  // valid bytes are data[begin, end)
  std::size_t begin = 0;
  std::size_t end = 0;
  bool eof = false;                // no more bytes will come from the source
  std::uint64_t consumed = 0;      // bytes consumed before data[begin]
  std::uint64_t total_bytes = 0;   // size of the source (for plausibility of atom counts)
  std::uint64_t start_offset = 0;  // where reading started in the file
  long line = 0;                   // lines consumed since start_offset
  bool line_base_known = true;     // false when reading started mid-file (read_last_frame)
  long line_base = 0;              // lines before start_offset, once known
  std::size_t frames = 0;
  std::size_t previous_atoms = 0;  // atom rows of the frame read last (for messages about what follows it)

  ~Impl() {
    if (file != nullptr) std::fclose(file);
  }

  /// Absolute 1-based line number of relative line `rel` (counts the lines before start_offset on first use).
  long absolute_line(long rel) {
    if (!line_base_known) {
      line_base_known = true;
      line_base = 0;
      if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
        std::vector<char> chunk(std::size_t{1} << 20);
        std::uint64_t left = start_offset;
        while (left > 0) {
          const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(left, chunk.size()));
          const std::size_t got = std::fread(chunk.data(), 1, want, f);
          if (got == 0) break;
          line_base += static_cast<long>(std::count(chunk.data(), chunk.data() + got, '\n'));
          left -= got;
        }
        std::fclose(f);
      }
    }
    return line_base + rel;
  }

  [[noreturn]] void fail(long rel_line, const std::string& message) {
    throw ParseError(name, rel_line > 0 ? absolute_line(rel_line) : 0, message);
  }

  [[noreturn]] void fail_short(long rel_line, const std::string& message, std::size_t rows, std::size_t announced) {
    throw ShortFrameError(name, absolute_line(rel_line), message, rows, announced);
  }

  /// Reads more bytes so that data[begin, end) grows; returns false when nothing more came.
  bool refill() {
    if (file == nullptr || eof) {
      eof = true;
      return false;
    }
    if (begin > 0) {
      std::memmove(storage.data(), storage.data() + begin, end - begin);
      end -= begin;
      begin = 0;
    }
    if (end == storage.size()) return false;  // a line longer than the buffer: the caller reports it
    const std::size_t got = std::fread(storage.data() + end, 1, storage.size() - end, file);
    if (got == 0) {
      if (std::ferror(file)) fail(0, fmt::format("read error after {} bytes", consumed + (end - begin)));
      eof = true;
      return false;
    }
    end += got;
    data = storage.data();
    return true;
  }

  /// Next line without its '\n' (a last line without '\n' counts). False at the end of the input.
  bool next_line(std::string_view& out) {
    std::size_t scanned = begin;
    for (;;) {
      const void* nl = scanned < end ? std::memchr(data + scanned, '\n', end - scanned) : nullptr;
      if (nl != nullptr) {
        const auto* p = static_cast<const char*>(nl);
        out = std::string_view(data + begin, static_cast<std::size_t>(p - (data + begin)));
        if (out.size() > options.max_line_bytes) too_long();
        consumed += out.size() + 1;
        begin = static_cast<std::size_t>(p - data) + 1;
        ++line;
        return true;
      }
      if (end - begin > options.max_line_bytes) too_long();
      const std::size_t pending = end - begin;
      if (!refill()) {
        if (end == begin) return false;
        out = std::string_view(data + begin, end - begin);  // last line, no '\n'
        consumed += out.size();
        begin = end;
        ++line;
        if (options.require_final_newline)
          fail(line, fmt::format("the file ends inside this line ({}, no end of line): cut short?", shown(trim(out))));
        return true;
      }
      scanned = begin + pending;
    }
  }

  [[noreturn]] void too_long() {
    fail(line + 1,
         fmt::format("line longer than {} bytes: not a LIGGGHTS text dump (binary data?)", options.max_line_bytes));
  }

  /// Next non-empty line, or false at the end.
  bool next_nonempty_line(std::string_view& out) {
    while (next_line(out))
      if (!trim(out).empty()) return true;
    return false;
  }

  void expect_line(std::string_view& out, const char* what, long frame_line) {
    if (!next_line(out))
      fail(line + 1, fmt::format("file ends inside the header of the frame starting at line {} (expected {}); "
                                 "truncated?",
                                 absolute_line(frame_line), what));
  }

  long read_long_line(const char* item, long frame_line) {
    std::string_view text;
    expect_line(text, fmt::format("the value of {}", item).c_str(), frame_line);
    long value = 0;
    if (!parse_long(trim(text), value))
      fail(line, fmt::format("the value of {} is {}, not an integer", item, shown(trim(text))));
    return value;
  }

  void expect_item(std::string_view item, long frame_line) {
    std::string_view text;
    expect_line(text, fmt::format("'{}'", item).c_str(), frame_line);
    if (trim(text) != item) fail(line, fmt::format("expected '{}', found {}", item, shown(trim(text))));
  }

  bool read_frame(DumpFrame& frame);
  void read_rows(DumpFrame& frame);
};

bool DumpReader::Impl::read_frame(DumpFrame& frame) {
  std::string_view text;
  if (!next_nonempty_line(text)) {
    if (frames > 0) return false;
    if (consumed == 0) fail(0, "empty file: not a LIGGGHTS dump");
    fail(line, "no frame in the file (no 'ITEM: TIMESTEP' line)");
  }
  if (trim(text) == "ITEM: UNITS") {  // LAMMPS' optional units block precedes the time step
    expect_line(text, "the unit style", line);
    if (!next_nonempty_line(text)) fail(line + 1, "file ends after 'ITEM: UNITS' (expected 'ITEM: TIMESTEP')");
  }
  if (trim(text) != "ITEM: TIMESTEP") {
    if (frames == 0)
      fail(line, fmt::format("expected 'ITEM: TIMESTEP', found {}: not a LIGGGHTS text dump", shown(trim(text))));
    fail(line, fmt::format("expected 'ITEM: TIMESTEP' after the {} atom rows of the previous frame, found {} "
                           "(more rows than NUMBER OF ATOMS?)",
                           previous_atoms, shown(trim(text))));
  }
  const long frame_line = line;
  frame.file = name;
  frame.first_line = line_base_known ? absolute_line(frame_line) : 0;
  frame.timestep = read_long_line("ITEM: TIMESTEP", frame_line);

  expect_line(text, "'ITEM: NUMBER OF ATOMS'", frame_line);
  if (trim(text) == "ITEM: TIME") {  // LAMMPS' optional simulated-time block
    expect_line(text, "the time", frame_line);
    expect_line(text, "'ITEM: NUMBER OF ATOMS'", frame_line);
  }
  if (trim(text) != "ITEM: NUMBER OF ATOMS")
    fail(line, fmt::format("expected 'ITEM: NUMBER OF ATOMS', found {}", shown(trim(text))));
  const long count = read_long_line("ITEM: NUMBER OF ATOMS", frame_line);
  if (count < 0) fail(line, fmt::format("NUMBER OF ATOMS is {}: must not be negative", count));

  expect_line(text, "'ITEM: BOX BOUNDS'", frame_line);
  if (!starts_with_item(text, "ITEM: BOX BOUNDS"))
    fail(line, fmt::format("expected 'ITEM: BOX BOUNDS', found {}", shown(trim(text))));
  {
    std::vector<std::string_view> flags = split(trim(text).substr(std::string_view("ITEM: BOX BOUNDS").size()));
    frame.triclinic = flags.size() >= 3 && flags[0] == "xy" && flags[1] == "xz" && flags[2] == "yz";
    if (frame.triclinic) flags.erase(flags.begin(), flags.begin() + 3);
    frame.boundary = join(flags);
  }
  frame.tilt = {0.0, 0.0, 0.0};
  const std::size_t per_line = frame.triclinic ? 3 : 2;
  for (int d = 0; d < 3; ++d) {
    expect_line(text, "three box bound lines", frame_line);
    const std::vector<std::string_view> tokens = split(text);
    if (tokens.size() != per_line)
      fail(line,
           fmt::format("box bound line has {} values, expected {}: {}", tokens.size(), per_line, shown(trim(text))));
    for (std::size_t k = 0; k < 2; ++k)
      if (!parse_double(tokens[k], frame.box[static_cast<std::size_t>(2 * d) + k]))
        fail(line, fmt::format("box bound {} is not a number", shown(tokens[k])));
    if (frame.triclinic && !parse_double(tokens[2], frame.tilt[static_cast<std::size_t>(d)]))
      fail(line, fmt::format("tilt factor {} is not a number", shown(tokens[2])));
  }

  expect_line(text, "'ITEM: ATOMS'", frame_line);
  if (!starts_with_item(text, "ITEM: ATOMS"))
    fail(line, fmt::format("expected 'ITEM: ATOMS', found {}", shown(trim(text))));
  frame.atoms_line = line_base_known ? absolute_line(line) : 0;
  {
    const std::vector<std::string_view> names = split(trim(text).substr(std::string_view("ITEM: ATOMS").size()));
    if (names.empty()) fail(line, "ITEM: ATOMS names no columns");
    frame.columns.assign(names.begin(), names.end());
    for (std::size_t c = 0; c < names.size(); ++c)
      for (std::size_t k = 0; k < c; ++k)
        if (names[c] == names[k]) fail(line, fmt::format("ITEM: ATOMS names column {} twice", shown(names[c])));
    for (const std::string& required : options.required_columns)
      if (frame.column_index(required) < 0) {
        fail(line, fmt::format("ITEM: ATOMS has no column '{}' (columns: {})", required, join(names)));
      }
  }

  frame.atom_count = static_cast<std::size_t>(count);
  read_rows(frame);
  previous_atoms = frame.atom_count;
  ++frames;
  return true;
}

void DumpReader::Impl::read_rows(DumpFrame& frame) {
  const std::size_t ncol = frame.columns.size();
  const std::size_t n = frame.atom_count;
  // Every row needs at least two bytes per value: allocate no more rows than the rest of the input can hold, so a
  // count that only the header claims costs nothing; a real frame never grows past this.
  const std::uint64_t left = total_bytes > consumed ? total_bytes - consumed : 0;
  const std::uint64_t room = (left + 1) / (2 * ncol);
  std::size_t capacity = static_cast<std::size_t>(std::min<std::uint64_t>(n, room));
  frame.values.resize(ncol);
  for (std::vector<double>& col : frame.values) col.resize(capacity);
  std::vector<double*> out(ncol);
  for (std::size_t c = 0; c < ncol; ++c) out[c] = frame.values[c].data();
  const long atoms_rel = line;

  std::string_view text;
  for (std::size_t i = 0; i < n; ++i) {
    if (!next_line(text))
      fail_short(line + 1,
                 fmt::format("file ends after {} of the {} atom rows announced for the frame whose ITEM: ATOMS is at "
                             "line {} (truncated?)",
                             i, n, absolute_line(atoms_rel)),
                 i, n);
    if (i == capacity) {  // only when the input grows while it is read
      capacity = std::min(n, 2 * capacity + 1024);
      for (std::size_t c = 0; c < ncol; ++c) {
        frame.values[c].resize(capacity);
        out[c] = frame.values[c].data();
      }
    }
    const char* p = text.data();
    const char* e = p + text.size();
    for (std::size_t c = 0; c < ncol; ++c) {
      while (p != e && is_blank(*p)) ++p;
      if (c == 0 && p != e && *p == 'I' && starts_with_item(text, "ITEM:"))
        fail_short(line, fmt::format("only {} atom rows before {}, but NUMBER OF ATOMS is {}", i, shown(trim(text)), n),
                   i, n);
      if (p == e) {
        fail(line, fmt::format("atom row has {} values, ITEM: ATOMS names {} columns (line cut short?)", c, ncol));
      }
      const char* q = (*p == '+') ? p + 1 : p;
      double value = 0.0;
      const auto [ptr, ec] = std::from_chars(q, e, value);
      if (ec != std::errc() || (ptr != e && !is_blank(*ptr)) || !std::isfinite(value)) {
        const std::string_view token = first_token(std::string_view(p, static_cast<std::size_t>(e - p)));
        fail(line, fmt::format("column '{}': {} is not a finite number", frame.columns[c], shown(token)));
      }
      out[c][i] = value;
      p = ptr;
    }
    while (p != e && is_blank(*p)) ++p;
    if (p != e) fail(line, fmt::format("atom row has more than the {} values ITEM: ATOMS names", ncol));
  }
}

DumpReader::DumpReader(const std::filesystem::path& path, DumpReaderOptions options) : m_impl(new Impl) {
  options.validate();
  Impl& s = *m_impl;
  s.options = std::move(options);
  s.name = path.string();
  s.path = path;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw ParseError(s.name, 0, "is a directory, not a dump file");
  if (const std::optional<std::string> kind = special_file_kind(path))
    throw ParseError(s.name, 0, special_file_message(*kind));
  s.file = std::fopen(path.c_str(), "rb");
  if (s.file == nullptr) throw ParseError(s.name, 0, fmt::format("cannot open: {}", std::strerror(errno)));
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  s.total_bytes = ec ? std::numeric_limits<std::uint64_t>::max() : static_cast<std::uint64_t>(size);
  s.storage.resize(s.options.buffer_bytes + s.options.max_line_bytes + 1);
  s.data = s.storage.data();
}

DumpReader::DumpReader(std::string text, std::string name, DumpReaderOptions options) : m_impl(new Impl) {
  options.validate();
  Impl& s = *m_impl;
  s.options = std::move(options);
  s.name = std::move(name);
  s.storage.assign(text.begin(), text.end());
  s.data = s.storage.data();
  s.begin = 0;
  s.end = s.storage.size();
  s.eof = true;
  s.total_bytes = s.storage.size();
}

DumpReader::~DumpReader() = default;
DumpReader::DumpReader(DumpReader&&) noexcept = default;
DumpReader& DumpReader::operator=(DumpReader&&) noexcept = default;

bool DumpReader::next(DumpFrame& frame) { return m_impl->read_frame(frame); }
std::size_t DumpReader::frames_read() const { return m_impl->frames; }
std::uint64_t DumpReader::bytes_read() const { return m_impl->consumed; }

// ------------------------------------------------------------------------------------------------ whole-file helpers

namespace {

/// Offset of the last line that starts with "ITEM: TIMESTEP", searching backwards in blocks; -1 when there is none.
long long find_last_frame(std::FILE* f, std::uint64_t size) {
  static constexpr std::string_view k_marker = "ITEM: TIMESTEP";
  const std::uint64_t block = std::uint64_t{1} << 20;
  std::vector<char> buf(static_cast<std::size_t>(block) + k_marker.size());
  std::uint64_t hi = size;  // candidates start in [lo, hi); the read extends past hi so a marker there is whole
  while (hi > 0) {
    const std::uint64_t lo = hi > block ? hi - block : 0;
    const std::uint64_t read_end = std::min<std::uint64_t>(size, hi + k_marker.size());
    if (std::fseek(f, static_cast<long>(lo), SEEK_SET) != 0) return -1;
    const std::size_t got = std::fread(buf.data(), 1, static_cast<std::size_t>(read_end - lo), f);
    const std::string_view view(buf.data(), got);
    std::size_t pos = static_cast<std::size_t>(hi - lo) - 1;
    for (;;) {
      const std::size_t at = view.rfind(k_marker, pos);
      if (at == std::string_view::npos) break;
      if (lo + at == 0) return 0;
      if (at == 0) break;  // the byte before lies in the next block down, which re-examines this position
      if (view[at - 1] == '\n') return static_cast<long long>(lo + at);
      pos = at - 1;
    }
    if (lo == 0) break;
    hi = lo + 1;
  }
  return -1;
}

}  // namespace

DumpFrame read_last_frame(const std::filesystem::path& path, const DumpReaderOptions& options) {
  options.validate();
  if (const std::optional<std::string> kind = special_file_kind(path))
    throw ParseError(path.string(), 0, special_file_message(*kind));
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  long long offset = -1;
  if (!ec && size > 0) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f != nullptr) {
      offset = find_last_frame(f, static_cast<std::uint64_t>(size));
      std::fclose(f);
    }
  }
  DumpReader reader(path, options);
  DumpFrame frame;
  if (offset > 0) {
    DumpReader::Impl& s = *reader.m_impl;
    if (std::fseek(s.file, static_cast<long>(offset), SEEK_SET) != 0)
      throw ParseError(path.string(), 0, "cannot seek to the last frame");
    s.start_offset = static_cast<std::uint64_t>(offset);
    s.consumed = static_cast<std::uint64_t>(offset);
    s.line_base_known = false;
  }
  reader.next(frame);  // throws on an empty file or a file without a frame
  DumpFrame after;
  while (reader.next(after)) std::swap(frame, after);  // also checks that nothing but whole rows follow
  return frame;
}

DumpFrame read_first_frame(const std::filesystem::path& path, const DumpReaderOptions& options) {
  DumpReader reader(path, options);
  DumpFrame frame;
  reader.next(frame);
  return frame;
}

// ------------------------------------------------------------------------------------------------ particles

void check_unique_ids(const DumpFrame& frame) {
  // An id names one atom (LAMMPS atom_modify id yes): two rows with one id are a corrupt dump, and every observable
  // matched or counted by id would silently take one of them.
  const std::span<const double> id = frame.column("id");
  const std::size_t n = id.size();
  std::vector<std::pair<double, std::size_t>> by_id(n);
  for (std::size_t i = 0; i < n; ++i) by_id[i] = {id[i], i};
  std::sort(by_id.begin(), by_id.end());
  for (std::size_t k = 1; k < n; ++k)
    if (by_id[k].first == by_id[k - 1].first) {
      const std::size_t first = by_id[k - 1].second, second = by_id[k].second;
      const long line = frame.atoms_line > 0 ? frame.atoms_line + static_cast<long>(second) + 1 : 0;
      const std::string where =
          frame.atoms_line > 0 ? fmt::format("lines {} and {}", frame.atoms_line + static_cast<long>(first) + 1, line)
                               : fmt::format("atom rows {} and {}", first + 1, second + 1);
      throw ParseError(frame.file, line,
                       fmt::format("atom id {} appears twice in the frame of time step {} ({})",
                                   static_cast<std::int64_t>(by_id[k].first), frame.timestep, where));
    }
}

Particles particles_from_frame(const DumpFrame& frame, int only_type) {
  auto fail_row = [&frame](std::size_t row, const std::string& message) -> ParseError {
    if (frame.atoms_line > 0) return ParseError(frame.file, frame.atoms_line + static_cast<long>(row) + 1, message);
    return ParseError(frame.file, 0,
                      fmt::format("frame of time step {}, atom row {}: {}", frame.timestep, row + 1, message));
  };

  const std::span<const double> id = frame.column("id");
  const std::span<const double> type = frame.column("type");
  const std::span<const double> radius = frame.column("radius");
  std::span<const double> pos[3];
  const char* axes[3][3] = {{"x", "xu", "xs"}, {"y", "yu", "ys"}, {"z", "zu", "zs"}};
  bool scaled[3] = {false, false, false};
  for (int d = 0; d < 3; ++d) {
    if (frame.has_column(axes[d][0])) {
      pos[d] = frame.column(axes[d][0]);
    } else if (frame.has_column(axes[d][1])) {
      pos[d] = frame.column(axes[d][1]);
    } else if (frame.has_column(axes[d][2])) {
      if (frame.triclinic)
        throw ParseError(
            frame.file, frame.atoms_line,
            fmt::format("scaled coordinate '{}' in a triclinic box is not supported; dump x y z", axes[d][2]));
      pos[d] = frame.column(axes[d][2]);
      scaled[d] = true;
    } else {
      pos[d] = frame.column(axes[d][0]);  // throws, naming the columns there are
    }
  }

  Particles p;
  const std::size_t n = frame.atom_count;
  p.id.reserve(n);
  p.type.reserve(n);
  p.x.reserve(n);
  p.y.reserve(n);
  p.z.reserve(n);
  p.radius.reserve(n);
  constexpr double k_max_exact = 9007199254740992.0;  // 2^53
  for (std::size_t i = 0; i < n; ++i) {
    if (id[i] != std::floor(id[i]) || std::fabs(id[i]) > k_max_exact)
      throw fail_row(i, fmt::format("id {} is not an integer", id[i]));
    if (type[i] != std::floor(type[i]) || std::fabs(type[i]) > 1e9)
      throw fail_row(i, fmt::format("type {} is not an integer", type[i]));
    if (radius[i] < 0.0) throw fail_row(i, fmt::format("radius {} is negative", radius[i]));
    const int t = static_cast<int>(type[i]);
    if (only_type > 0 && t != only_type) continue;
    p.id.push_back(static_cast<std::int64_t>(id[i]));
    p.type.push_back(t);
    double c[3];
    for (int d = 0; d < 3; ++d) {
      const double lo = frame.box[static_cast<std::size_t>(2 * d)];
      const double hi = frame.box[static_cast<std::size_t>(2 * d + 1)];
      c[d] = scaled[d] ? lo + pos[d][i] * (hi - lo) : pos[d][i];
    }
    p.x.push_back(c[0]);
    p.y.push_back(c[1]);
    p.z.push_back(c[2]);
    p.radius.push_back(radius[i]);
  }
  check_unique_ids(frame);
  return p;
}

Particles read_particles(const std::filesystem::path& path, int only_type, DumpReaderOptions options) {
  for (const char* name : {"id", "type", "radius"})
    if (std::find(options.required_columns.begin(), options.required_columns.end(), name) ==
        options.required_columns.end())
      options.required_columns.emplace_back(name);
  return particles_from_frame(read_last_frame(path, options), only_type);
}

}  // namespace demsa::postprocess
