#pragma once
// A process-wide advisory lock on a file (fcntl F_SETLK), released when the holder closes it or ends, SIGKILL
// included: a study folder is held by one demsa at a time.
#include <filesystem>

namespace demsa::util {

class FileLock {
 public:
  /// Creates `file` if needed and locks it. Throws UserError naming the folder and the holder's pid when another
  /// process holds it, IoError when the file cannot be opened.
  explicit FileLock(const std::filesystem::path& file);
  ~FileLock();
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;
  /// PID of the process that holds the lock on `file`, or 0 when none does (or the file does not exist).
  static long holder(const std::filesystem::path& file);

 private:
  int m_fd = -1;
};

}  // namespace demsa::util
