// `demsa postprocess pile|oedometer` on the real LIGGGHTS pile and on plate files: text, JSON, exit statuses.
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace demsa::test {
namespace {

TEST(CliPostprocess, PileJsonOnRealDump) {
  const std::string dump = data_path("postprocess/liggghts_pile/pile_final.dump").string();
  const CommandResult r = run_demsa({"postprocess", "pile", dump, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["particles_on_pedestal"].get<int>(), 591);
  EXPECT_GT(j["angle_deg"].get<double>(), 20.0);
  EXPECT_LT(j["angle_deg"].get<double>(), 45.0);
  EXPECT_EQ(j["lines"].size(), 180u);
  EXPECT_FALSE(j["boundary"].empty());
  EXPECT_EQ(j["options"]["point"], "centre");
}

TEST(CliPostprocess, PileTextAndCaseFolder) {
  TempDir dir;
  write_file(dir / "pile_final.dump", read_file(data_path("postprocess/liggghts_pile/pile_final.dump")));
  const CommandResult r = run_demsa({"postprocess", "pile", dir.path().string(), "--levels", "8"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("angle of repose"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("591 of 600"), std::string::npos) << r.out;
}

TEST(CliPostprocess, PileErrorsExit2WithFileAndLine) {
  TempDir dir;
  write_file(dir / "bad.dump", "ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\nx\n");
  const CommandResult r = run_demsa({"postprocess", "pile", (dir / "bad.dump").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.dump:4: the value of ITEM: NUMBER OF ATOMS is 'x', not an integer"), std::string::npos)
      << r.err;
  const CommandResult far = run_demsa(
      {"postprocess", "pile", data_path("postprocess/liggghts_pile/pile_final.dump"), "--pedestal-top", "1.0"});
  EXPECT_EQ(far.exit_code, 2);
  EXPECT_NE(far.err.find("no particle of type 1 on the pedestal"), std::string::npos) << far.err;
  EXPECT_EQ(run_demsa({"postprocess", "pile", (dir / "missing.dump").string()}).exit_code, 2);
}

TEST(CliPostprocess, OedometerStatesAndHistory) {
  TempDir dir;
  write_file(dir / "plate_states.txt", "# load_N plate_z_m force_N converged\n100 0.06 100 1\n400 0.059 400 1\n");
  write_file(dir / "plate_history.txt",
             "# step load_N plate_z_m force_N\n1 100 0.061 50\n2 100 0.06 99\n"
             "3 400 0.059 400\n");
  const CommandResult r =
      run_demsa({"postprocess", "oedometer", dir.path().string(), "--measured", "0.0012", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["steps"].size(), 2u);
  EXPECT_NEAR(j["settlements_m"][0].get<double>(), 0.001, 1e-12);
  EXPECT_NEAR(j["settlement_error_m"].get<double>(), 0.0002, 1e-12);
  EXPECT_EQ(j["history"]["step"].size(), 3u);

  const CommandResult text = run_demsa({"postprocess", "oedometer", (dir / "plate_history.txt").string()});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("not every load step converged"), std::string::npos) << text.out;
}

TEST(CliPostprocess, OedometerBadFileExit2) {
  TempDir dir;
  write_file(dir / "plate_states.txt", "100 0.06 abc 1\n");
  const CommandResult r = run_demsa({"postprocess", "oedometer", (dir / "plate_states.txt").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("plate_states.txt:1: column 'force_N': 'abc' is not a number"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace demsa::test
