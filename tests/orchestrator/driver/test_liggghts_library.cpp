// The LIGGGHTS library loaded at run time by `demsa drive-oedometer` (driver/liggghts_library.hpp): found as the
// dynamic loader finds it, with a clear error when it is missing or is not LIGGGHTS.
#include "orchestrator/driver/liggghts_library.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace demsa::driver {
namespace {

TEST(LiggghtsLibrary, MissingLibraryNamesItAndSaysHowToGetOne) {
  const std::string message =
      test::message_of<util::UserError>([] { load_liggghts_library("libdemsa-test-no-such-liggghts.so.3"); });
  EXPECT_NE(message.find("cannot load the LIGGGHTS library libdemsa-test-no-such-liggghts.so.3 ("), std::string::npos)
      << message;
  EXPECT_NE(message.find("libliggghts3"), std::string::npos) << message;
  EXPECT_NE(message.find("LD_LIBRARY_PATH"), std::string::npos) << message;
}

TEST(LiggghtsLibrary, ALibraryWithoutLiggghtsIsRefusedByName) {
  // libm loads, but holds none of library.h's entry points.
  const std::string message = test::message_of<util::UserError>([] { load_liggghts_library("libm.so.6"); });
  EXPECT_NE(message.find("libm.so.6: no lammps_open"), std::string::npos) << message;
  EXPECT_NE(message.find("not LIGGGHTS's library interface"), std::string::npos) << message;
}

TEST(LiggghtsLibrary, LoadsTheSystemsLibraryWithItsMpi) {
  if (!std::filesystem::exists("/usr/lib/x86_64-linux-gnu/libliggghts.so.3") && !std::getenv("LD_LIBRARY_PATH"))
    GTEST_SKIP() << "no libliggghts.so.3 on this machine";
  const LiggghtsLibrary lib = load_liggghts_library();
  EXPECT_NE(lib.path.find("libliggghts.so"), std::string::npos) << lib.path;
  EXPECT_TRUE(std::filesystem::path(lib.path).is_absolute()) << lib.path;  // the file the loader chose
  EXPECT_NE(lib.comm_world, nullptr);
  EXPECT_NE(lib.open, nullptr);
  EXPECT_NE(lib.extract_fix, nullptr);
  EXPECT_NE(lib.mpi_comm_rank, nullptr);
}

}  // namespace
}  // namespace demsa::driver
