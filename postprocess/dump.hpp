#pragma once
// Reading LIGGGHTS text dumps: `dump custom` files (one or many frames) and `write_dump ... custom` snapshots.
//
// A frame is the block
//   ITEM: TIMESTEP / <step> / ITEM: NUMBER OF ATOMS / <n> / ITEM: BOX BOUNDS [xy xz yz] [ff ff ff] / 3 lines /
//   ITEM: ATOMS <col> <col> ... / n rows
// (LAMMPS' optional `ITEM: UNITS` and `ITEM: TIME` blocks before `ITEM: NUMBER OF ATOMS` are accepted and skipped).
// Columns may come in any order; they are found by the names on the `ITEM: ATOMS` line. Rows may be unsorted.
//
// The reader streams: it holds one frame and one read buffer, never the whole file. Numbers are parsed by hand over
// large `fread` blocks (std::from_chars), not with iostreams. Every malformed input (empty file, truncated frame,
// wrong atom count, missing column, non-numeric field, binary data) is a ParseError naming the file and line.
#include "postprocess/error.hpp"

#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::postprocess {

/// One dump frame, stored column by column (values[c][row]).
struct DumpFrame {
  long timestep = 0;                        ///< value after `ITEM: TIMESTEP`
  std::size_t atom_count = 0;               ///< value after `ITEM: NUMBER OF ATOMS` (= rows in every column)
  std::array<double, 6> box{};              ///< xlo xhi ylo yhi zlo zhi [length unit of the dump, m for demsa]
  std::array<double, 3> tilt{};             ///< xy xz yz for triclinic boxes, else 0
  bool triclinic = false;                   ///< the BOX BOUNDS line named `xy xz yz`
  std::string boundary;                     ///< boundary flags as written (`ff ff ff`), empty when the line has none
  std::vector<std::string> columns;         ///< names on the `ITEM: ATOMS` line, in file order
  std::vector<std::vector<double>> values;  ///< values[c][i]: column c of row i (ids and types as exact doubles)
  std::string file;                         ///< the file the frame came from (for error messages)
  long first_line = 0;                      ///< 1-based line of this frame's `ITEM: TIMESTEP`
  long atoms_line = 0;                      ///< 1-based line of this frame's `ITEM: ATOMS`

  /// Index of column `name` in `columns`, or -1.
  int column_index(std::string_view name) const;
  bool has_column(std::string_view name) const { return column_index(name) >= 0; }
  /// Values of column `name`; throws ParseError (file, `ITEM: ATOMS` line, the columns there are) when absent.
  std::span<const double> column(std::string_view name) const;
};

struct DumpReaderOptions {
  /// Columns every frame must have (ParseError at the `ITEM: ATOMS` line otherwise). Empty = no requirement.
  std::vector<std::string> required_columns;
  /// Size of one read from the file [bytes]; at least 4096. Larger reads are faster on big dumps.
  std::size_t buffer_bytes = std::size_t{1} << 22;
  /// Longest line accepted [bytes]; a longer line is reported as not being a text dump (binary data).
  std::size_t max_line_bytes = std::size_t{1} << 20;
  /// The file must end with an end of line. LIGGGHTS ends every line of a dump with one, so a last line without it
  /// was cut by a writer that stopped (killed, disk full); when the cut falls inside the last value of the last row,
  /// that row still parses, with a wrong value. On by default for every reader (postprocess, compare, export-vtk, a
  /// study's measurement); off: a last line without end of line counts as a line.
  bool require_final_newline = true;

  /// Throws std::invalid_argument naming the field, its value and the rule.
  void validate() const;
};

/// A frame with fewer atom rows than its NUMBER OF ATOMS: the file ends, or the next `ITEM:` line comes, after
/// rows() of the announced() rows (a dump cut short). The message is that of any ParseError.
class ShortFrameError : public ParseError {
 public:
  ShortFrameError(const std::string& file, long line, const std::string& message, std::size_t rows,
                  std::size_t announced)
      : ParseError(file, line, message), m_rows(rows), m_announced(announced) {}
  std::size_t rows() const { return m_rows; }
  std::size_t announced() const { return m_announced; }

 private:
  std::size_t m_rows;
  std::size_t m_announced;
};

DumpFrame read_last_frame(const std::filesystem::path& path, const DumpReaderOptions& options);

/// Streams the frames of one dump file in order.
///
///   DumpReader reader("pile.dump");
///   DumpFrame frame;
///   while (reader.next(frame)) { ... }
///
/// Memory: one frame (`frame`'s vectors are reused between calls) plus one read buffer.
class DumpReader {
 public:
  /// Opens `path`; throws ParseError when it cannot be opened.
  explicit DumpReader(const std::filesystem::path& path, DumpReaderOptions options = {});
  /// Reads a dump held in memory (the reader keeps its own copy); `name` stands for the file in error messages.
  DumpReader(std::string text, std::string name, DumpReaderOptions options = {});
  ~DumpReader();
  DumpReader(const DumpReader&) = delete;
  DumpReader& operator=(const DumpReader&) = delete;
  DumpReader(DumpReader&&) noexcept;
  DumpReader& operator=(DumpReader&&) noexcept;

  /// Reads the next frame into `frame`. Returns false at the end of the file (after at least one frame); an empty
  /// file, a file without any frame, and any malformed frame throw ParseError.
  bool next(DumpFrame& frame);

  /// Number of frames returned so far.
  std::size_t frames_read() const;
  /// Bytes consumed from the file so far.
  std::uint64_t bytes_read() const;

 private:
  friend DumpFrame read_last_frame(const std::filesystem::path& path, const DumpReaderOptions& options);
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

/// The last frame of a dump, found by searching backwards from the end of the file for the last `ITEM: TIMESTEP`,
/// so its cost does not grow with the number of earlier frames. The frame must be complete; the line numbers in
/// its errors are counted from the start of the file.
DumpFrame read_last_frame(const std::filesystem::path& path, const DumpReaderOptions& options = {});

/// The first frame of a dump.
DumpFrame read_first_frame(const std::filesystem::path& path, const DumpReaderOptions& options = {});

/// Spheres of one frame in the units of the dump (demsa's cases: m).
struct Particles {
  std::vector<std::int64_t> id;
  std::vector<int> type;
  std::vector<double> x, y, z, radius;
  std::size_t size() const { return id.size(); }
};

/// Throws ParseError (the file, the line of the second row, both lines) when two rows of the frame's `id` column
/// hold one id: a corrupt dump, whose observables matched or counted by id would take one of the two at random.
void check_unique_ids(const DumpFrame& frame);

/// Particles from a frame that has `id type radius` and either `x y z`, unwrapped `xu yu zu`, or scaled `xs ys zs`
/// (scaled coordinates are unscaled with the box; orthogonal boxes only). Rows whose id or type is not an integer,
/// and an id on two rows (file, line, time step and id in the message), throw ParseError. `only_type` > 0 keeps only
/// atoms of that type (demsa: type 1 = particles, 2 = walls).
Particles particles_from_frame(const DumpFrame& frame, int only_type = 0);

/// particles_from_frame(read_last_frame(path, options), only_type) with `id type radius` added to the required
/// columns: what the observables use from a final dump.
Particles read_particles(const std::filesystem::path& path, int only_type = 0, DumpReaderOptions options = {});

}  // namespace demsa::postprocess
