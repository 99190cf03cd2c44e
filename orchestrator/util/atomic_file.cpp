#include "orchestrator/util/atomic_file.hpp"

#include "orchestrator/util/errors.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/core.h>

#include <cassert>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <utility>

namespace demsa::util {

namespace fs = std::filesystem;

AtomicFileWriter::AtomicFileWriter(fs::path path)
    : path_(std::move(path)), tmp_(path_.parent_path() / (path_.filename().string() + ".tmp")) {
  struct stat st {};
  if (::stat(path_.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)) {
    // A FIFO, a terminal or a device (`--json /dev/stdout`): written through, since a rename would replace the node
    // by a regular file. Opened without blocking, so that a FIFO without a reader is an error, not a hang.
    through_ = true;
    tmp_ = path_;
    fd_ = ::open(path_.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) {
      const int error = errno;
      throw IoError(fmt::format("{}: cannot write: {}", path_.string(),
                                error == ENXIO ? std::string("a FIFO that no process reads") : std::strerror(error)));
    }
    const int flags = ::fcntl(fd_, F_GETFL);
    if (flags >= 0) ::fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK);
    return;
  }
  fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw IoError(fmt::format("{}: cannot write: {}", tmp_.string(), std::strerror(errno)));
}

AtomicFileWriter::~AtomicFileWriter() {
  if (fd_ >= 0) {
    ::close(fd_);
    if (!through_) ::unlink(tmp_.c_str());
  }
}

void AtomicFileWriter::append(std::string_view text) {
  assert(fd_ >= 0);
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd_, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw IoError(fmt::format("{}: write failed: {}", tmp_.string(), std::strerror(errno)));
    written += static_cast<std::size_t>(n);
  }
}

void AtomicFileWriter::commit() {
  assert(fd_ >= 0);
  if (through_) {
    if (::close(std::exchange(fd_, -1)) != 0)
      throw IoError(fmt::format("{}: close failed: {}", path_.string(), std::strerror(errno)));
    return;
  }
  if (::fsync(fd_) != 0) throw IoError(fmt::format("{}: fsync failed: {}", tmp_.string(), std::strerror(errno)));
  const int fd = std::exchange(fd_, -1);
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlink(tmp_.c_str());
    throw IoError(fmt::format("{}: close failed: {}", tmp_.string(), std::strerror(error)));
  }
  if (::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const int error = errno;
    ::unlink(tmp_.c_str());
    throw IoError(fmt::format("{}: rename failed: {}", path_.string(), std::strerror(error)));
  }
  // The rename itself is durable only once the folder is synced.
  const fs::path parent = path_.parent_path().empty() ? fs::path(".") : path_.parent_path();
  const int dir_fd = ::open(parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
}

void write_file_atomically(const fs::path& path, const std::string& text) {
  AtomicFileWriter writer(path);
  writer.append(text);
  writer.commit();
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(fmt::format("{}: cannot read: {}", path.string(), std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace demsa::util
