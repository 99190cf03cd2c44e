#include "orchestrator/util/file_lock.hpp"

#include "orchestrator/util/errors.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <fmt/core.h>

#include <cerrno>
#include <cstring>

namespace demsa::util {

namespace fs = std::filesystem;

FileLock::FileLock(const fs::path& file) {
  m_fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (m_fd < 0) throw IoError(fmt::format("{}: cannot open: {}", file.string(), std::strerror(errno)));
  struct flock lock {};
  lock.l_type = F_WRLCK;
  lock.l_whence = SEEK_SET;
  if (::fcntl(m_fd, F_SETLK, &lock) != 0) {
    ::close(m_fd);
    m_fd = -1;
    const long pid = holder(file);
    throw UserError(fmt::format("{}: another demsa (pid {}) is running this study; wait for it or stop it",
                                file.parent_path().string(), pid));
  }
}

FileLock::~FileLock() {
  if (m_fd >= 0) ::close(m_fd);
}

long FileLock::holder(const fs::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  struct flock lock {};
  lock.l_type = F_WRLCK;
  lock.l_whence = SEEK_SET;
  long pid = 0;
  if (::fcntl(fd, F_GETLK, &lock) == 0 && lock.l_type != F_UNLCK) pid = lock.l_pid;
  ::close(fd);
  return pid;
}

}  // namespace demsa::util
