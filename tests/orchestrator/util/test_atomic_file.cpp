// The durable writer and targets that are not regular files: a FIFO and a device are written through, never replaced
// by a regular file; a full device is reported with its reason; a FIFO without a reader is an error, not a hang.
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"

#include "support/test_support.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <thread>

namespace demsa::util {
namespace {

namespace fs = std::filesystem;

TEST(AtomicFile, AFifoIsWrittenThroughAndStaysAFifo) {
  test::TempDir dir;
  const fs::path fifo = dir / "out.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] {
    const int fd = ::open(fifo.c_str(), O_RDONLY);
    char buffer[256];
    for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) > 0;) received.append(buffer, static_cast<std::size_t>(n));
    ::close(fd);
  });
  // The writer's non-blocking open fails until the reader has opened its end.
  for (int i = 0; i < 200; ++i) {
    try {
      write_file_atomically(fifo, "{\"a\": 1}\n");
      break;
    } catch (const IoError&) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  reader.join();
  EXPECT_EQ(received, "{\"a\": 1}\n");
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_FALSE(fs::exists(dir / "out.fifo.tmp"));
}

TEST(AtomicFile, AFifoWithoutAReaderIsAnErrorNotAWait) {
  test::TempDir dir;
  const fs::path fifo = dir / "out.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(test::message_of<IoError>([&] { write_file_atomically(fifo, "x"); }),
            fifo.string() + ": cannot write: a FIFO that no process reads");
  EXPECT_TRUE(fs::is_fifo(fifo));
}

TEST(AtomicFile, AFullDeviceIsReportedWithItsReasonAndKept) {
  test::TempDir dir;
  const fs::path full = dir / "full";
  // A node of /dev/full's device (1, 7) in our own folder: the real one is left alone.
  if (::mknod(full.c_str(), S_IFCHR | 0600, makedev(1, 7)) != 0) GTEST_SKIP() << "mknod needs root";
  EXPECT_EQ(test::message_of<IoError>([&] { write_file_atomically(full, "x"); }),
            full.string() + ": write failed: No space left on device");
  EXPECT_TRUE(fs::is_character_file(full));
}

}  // namespace
}  // namespace demsa::util
