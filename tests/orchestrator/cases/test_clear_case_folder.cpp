// cases::clear_case_folder: a case folder is emptied for a new attempt even while a process of the old attempt still
// writes into it (a cancelled SLURM task shutting down), and what it leaves behind is removed by a later call.
#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <iterator>
#include <string>
#include <thread>

namespace demsa::test {
namespace {
namespace fs = std::filesystem;

long entries(const fs::path& dir) { return std::distance(fs::directory_iterator(dir), fs::directory_iterator{}); }

TEST(ClearCaseFolder, AFolderThatIsMissingIsLeftAlone) {
  TempDir dir;
  cases::clear_case_folder(dir / "cases" / "000001");
  EXPECT_FALSE(fs::exists(dir / "cases" / ".stale"));
}

TEST(ClearCaseFolder, TheFolderIsGoneAndNothingIsLeftWhenNobodyWritesThere) {
  TempDir dir;
  const fs::path folder = dir / "cases" / "000003";
  fs::create_directories(folder / "vtk");
  write_file(folder / "log.liggghts", "old attempt\n");
  write_file(folder / "vtk" / "particles.vtp", "<VTKFile/>\n");
  cases::clear_case_folder(folder);
  EXPECT_FALSE(fs::exists(folder));
  EXPECT_EQ(entries(dir / "cases" / ".stale"), 0);
}

TEST(ClearCaseFolder, AWriterThatKeepsCreatingFilesNeitherFailsTheCallNorReachesTheNewAttempt) {
  TempDir dir;
  const fs::path folder = dir / "cases" / "000000";
  fs::create_directories(folder);
  for (int i = 0; i < 200; ++i) write_file(folder / ("dump." + std::to_string(i)), "x\n");
  // The old attempt's process: it holds the folder open (as its working directory) and keeps creating files in it.
  const int dir_fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  ASSERT_GE(dir_fd, 0);
  std::atomic<bool> stop{false};
  std::atomic<int> written{0};
  std::thread writer([&] {
    for (int i = 0; !stop; ++i) {
      const int fd = ::openat(dir_fd, ("late." + std::to_string(i)).c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
      if (fd >= 0) ::close(fd), ++written;
    }
  });
  while (written < 50) std::this_thread::yield();

  EXPECT_NO_THROW(cases::clear_case_folder(folder));
  // The new attempt writes its case into a folder of its own: nothing of the old one appears there.
  fs::create_directories(folder);
  write_file(folder / "in.liggghts", "new attempt\n");
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(entries(folder), 1);

  stop = true;
  writer.join();
  ::close(dir_fd);
  // Once the writer has ended, the next call removes what it left.
  cases::clear_case_folder(folder);
  EXPECT_FALSE(fs::exists(folder));
  EXPECT_EQ(entries(dir / "cases" / ".stale"), 0);
}

TEST(ClearCaseFolder, WhereTheFolderCannotBeMovedAsideTheErrorNamesThePlace) {
  TempDir dir;
  const fs::path cases = dir / "cases";
  fs::create_directories(cases / "000002");
  write_file(cases / ".stale", "a file where the folder of stale attempts belongs\n");
  const std::string message = message_of<util::IoError>([&] { cases::clear_case_folder(cases / "000002"); });
  EXPECT_NE(message.find(".stale"), std::string::npos) << message;
  EXPECT_TRUE(fs::exists(cases / "000002"));  // nothing was removed
}

}  // namespace
}  // namespace demsa::test
