// demsa links neither LIGGGHTS nor MPI (nor the VTK libraries Debian's libliggghts brings): `demsa drive-oedometer`
// loads libliggghts.so.3 at run time, as the dynamic loader finds it (LD_LIBRARY_PATH first, as run.sh of a viscous
// case sets it), and says clearly when it cannot.
#include "orchestrator/experiments/oedometer/oedometer.hpp"
#include "orchestrator/study/folder.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace demsa {
namespace {

namespace fs = std::filesystem;

TEST(DriverLoading, DemsaLinksNoLiggghtsMpiOrVtk) {
  const test::CommandResult ldd = test::run_command({"ldd", DEMSA_BINARY});
  ASSERT_EQ(ldd.exit_code, 0) << ldd.err;
  for (const char* library : {"liggghts", "libmpi", "vtk", "libopen-pal"})
    EXPECT_EQ(ldd.out.find(library), std::string::npos) << library << " in\n" << ldd.out;
}

TEST(DriverLoading, DriverLoadsLibliggghtsFromLdLibraryPathAndNamesItWhenItCannot) {
  test::TempDir tmp;
  const test::CommandResult written =
      test::run_demsa({"case", test::data_path("cases/tiny_oedometer_trial.toml").string(), "--set", "E=1e8", "-o",
                       (tmp / "trial").string()});
  ASSERT_EQ(written.exit_code, 0) << written.err;
  // A "libliggghts.so.3" first on LD_LIBRARY_PATH that is not a library at all: the driver tries that one, as it
  // loads the build of scripts/build-liggghts.sh that run.sh of a viscous case puts there, and names it.
  test::write_file(tmp / "lib" / "libliggghts.so.3", "not a shared library\n");
  const test::CommandResult r = test::run_command(
      {"env", "LD_LIBRARY_PATH=" + (tmp / "lib").string(), DEMSA_BINARY, "drive-oedometer", (tmp / "trial").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("demsa: error: cannot load the LIGGGHTS library libliggghts.so.3 (" +
                       (tmp / "lib" / "libliggghts.so.3").string()),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(tmp / "trial" / experiments::oedometer::k_plate_history));
}

}  // namespace
}  // namespace demsa
