// The project's LIGGGHTS build (scripts/build-liggghts.sh) against Debian's on the same tiny cases written by
// `demsa case`: the final states are identical to the last digit (positions, velocities and angular velocities
// written with %.17g). The build changes code paths only (compiled kernels, the mesh contact history's cheaper
// clearing, the mesh wall's exact skip, the profile-guided and link-time optimisation of RECIPE 6), never the
// arithmetic; a build change that did would fail here (docs/explanation/benchmarks.md, "LIGGGHTS builds" and
// "Profile-guided and link-time optimisation").
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <ostream>
#include <string>
#include <utility>

namespace demsa {
namespace {

namespace fs = std::filesystem;

/// Debian's LIGGGHTS: `liggghts` on PATH (scripts/install-deps.sh); "" when there is none.
std::string stock_liggghts() {
  const test::CommandResult w = test::run_command({"bash", "-c", "command -v liggghts"});
  std::string path = w.out;
  while (!path.empty() && (path.back() == '\n' || path.back() == ' ')) path.pop_back();
  return w.exit_code == 0 ? path : "";
}

/// The full state at the end of a case, sorted by id, every number to the last digit.
const char* const k_final_state =
    "\nwrite_dump all custom final_state.dump id type x y z vx vy vz omegax omegay omegaz radius modify sort id "
    "format \"%d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\"\n";

/// The incline deletes its probes as they leave the plate, so it ends empty: its probes' frames, taken every
/// record_steps until then, are compared instead, written to the last digit.
const char* const k_probe_frames = "dump_modify     probes sort id first yes";

struct TinyCase {
  const char* study;     ///< tests/data/cases/STUDY
  const char* compared;  ///< the file compared, written by the case's input with %.17g
};

/// How gtest names a case in its output: its study file.
void PrintTo(const TinyCase& c, std::ostream* os) { *os << c.study; }

/// Writes sample 0 of the case's study into TMP/case, runs a copy of it with each executable on one rank (the
/// input ends with a dump of the full state; the incline's probe frames are written to the last digit) and returns
/// the two files compared.
std::pair<std::string, std::string> final_states(const test::TempDir& tmp, const TinyCase& c, const std::string& a,
                                                 const std::string& b) {
  const fs::path dir = tmp / "case";
  const test::CommandResult w = test::run_demsa(
      {"case", test::data_path(std::string("cases/") + c.study).string(), "--sample", "0", "-o", dir.string()});
  EXPECT_EQ(w.exit_code, 0) << w.out << w.err;
  std::string input = test::read_file(dir / "in.liggghts") + k_final_state;
  if (const std::size_t at = input.find(k_probe_frames); at != std::string::npos)
    input.insert(at + std::string(k_probe_frames).size(),
                 "\ndump_modify     probes format \"%d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g\"");
  test::write_file(dir / "in.liggghts", input);
  std::string compared[2];
  const std::string exes[2] = {a, b};
  for (int k = 0; k < 2; ++k) {
    const fs::path run = tmp / ("run-" + std::to_string(k));
    fs::copy(dir, run, fs::copy_options::recursive);
    const test::CommandResult r =
        test::run_command({exes[k], "-in", "in.liggghts", "-log", "log.liggghts", "-screen", "screen.txt"}, run);
    EXPECT_EQ(r.exit_code, 0) << exes[k] << ": " << r.err << test::read_file(run / "log.liggghts");
    compared[k] = test::read_file(run / c.compared);
  }
  return {compared[0], compared[1]};
}

class SameTrajectory : public ::testing::TestWithParam<TinyCase> {};

TEST_P(SameTrajectory, ProjectBuildEndsInDebiansStateToTheLastDigit) {
  std::string why;
  const std::string project = test::project_liggghts(why);
  ASSERT_FALSE(project.empty()) << why;
  const std::string stock = stock_liggghts();
  ASSERT_FALSE(stock.empty()) << "no liggghts on PATH (Debian's LIGGGHTS: scripts/install-deps.sh)";
  test::TempDir tmp;
  const TinyCase c = GetParam();
  const auto [debian, ours] = final_states(tmp, c, stock, project);
  ASSERT_GT(debian.size(), 1000u) << c.study << ": no " << c.compared << " written";
  EXPECT_TRUE(debian == ours) << c.study << ": " << c.compared << " differs (" << stock << " against " << project
                              << ")";
}

// The pile on its mesh pedestal (pair and mesh-wall kernels, the mesh contact history), the incline (primitive
// walls), and the oedometer's servo plate (a moving mesh).
INSTANTIATE_TEST_SUITE_P(TinyCases, SameTrajectory,
                         ::testing::Values(TinyCase{"tiny_pile.toml", "final_state.dump"},
                                           TinyCase{"tiny_incline.toml", "incline_probes.dump"},
                                           TinyCase{"tiny_oedometer_servo.toml", "final_state.dump"}),
                         [](const ::testing::TestParamInfo<TinyCase>& param) {
                           const std::string name = param.param.study;  // tiny_NAME.toml
                           return name.substr(5, name.find('.') - 5);
                         });

}  // namespace
}  // namespace demsa
