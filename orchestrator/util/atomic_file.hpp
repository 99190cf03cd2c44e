#pragma once
// The one durable writer (after ccache's core/atomicfile.hpp): the text goes to a temporary file in the same
// folder, which is fsynced and renamed over the target, and the folder itself is fsynced so that the rename
// survives a power cut. A reader sees the old content or the new one, never a torn file.
#include <filesystem>
#include <string>
#include <string_view>

namespace demsa::util {

/// Writes `text` to `path` atomically and durably. Throws IoError naming the file and the system's reason (a full
/// device: "No space left on device"). A target that exists and is not a regular file (a FIFO, a terminal, a device
/// such as /dev/stdout) is written through instead, never replaced by a regular file; a FIFO that no process reads is
/// an error, not a wait.
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

/// The same, for text written in pieces (a file too large to hold in memory at once): append() writes to the
/// temporary file, commit() makes it durable and renames it over the target. Destroyed without commit(), it removes
/// the temporary file, so an exception (or a stop) leaves the target as it was.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(std::filesystem::path path);
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
  ~AtomicFileWriter();

  void append(std::string_view text);
  void commit();

 private:
  std::filesystem::path path_;
  std::filesystem::path tmp_;
  int fd_ = -1;
  bool through_ = false;  ///< the target is not a regular file (a FIFO, a device): written in place
};

/// The whole content of a file. Throws IoError naming the file when it cannot be read.
std::string read_file(const std::filesystem::path& path);

}  // namespace demsa::util
