// `demsa compare A B`: exit 0 within tolerance, 1 beyond it, 2 on an error; dumps and case folders.
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

namespace demsa::test {
namespace {

std::string dump_text(double x_of_id2, int count = 2) {
  std::string text = "ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n" + std::to_string(count) +
                     "\nITEM: BOX BOUNDS ff ff ff\n-1 1\n-1 1\n-1 1\nITEM: ATOMS id type x y z radius\n";
  text += "1 1 0 0 0.01 0.001\n";
  text += "2 1 " + std::to_string(x_of_id2) + " 0 0.01 0.001\n";
  if (count == 3) text += "3 1 0.5 0 0.01 0.001\n";
  return text;
}

TEST(CliCompare, IdenticalDumpsExit0) {
  TempDir dir;
  write_file(dir / "a.dump", dump_text(0.1));
  write_file(dir / "b.dump", dump_text(0.1));
  const CommandResult r = run_demsa({"compare", (dir / "a.dump").string(), (dir / "b.dump").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["within_tolerance"].get<bool>());
  EXPECT_EQ(j["comparisons"][0]["common"].get<int>(), 2);
  EXPECT_DOUBLE_EQ(j["comparisons"][0]["max_displacement_m"].get<double>(), 0.0);
}

TEST(CliCompare, DisplacementBeyondToleranceExit1) {
  TempDir dir;
  write_file(dir / "a.dump", dump_text(0.1));
  write_file(dir / "b.dump", dump_text(0.1003, 3));
  const CommandResult r = run_demsa({"compare", (dir / "a.dump").string(), (dir / "b.dump").string(), "--json"});
  ASSERT_EQ(r.exit_code, 1) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out)["comparisons"][0];
  EXPECT_NEAR(j["max_displacement_m"].get<double>(), 3e-4, 1e-12);
  EXPECT_EQ(j["max_displacement_id"].get<int>(), 2);
  EXPECT_NEAR(j["rms_displacement_m"].get<double>(), 3e-4 / std::sqrt(2.0), 1e-12);
  EXPECT_EQ(j["extra"].get<int>(), 1);
  EXPECT_EQ(j["extra_ids"][0].get<int>(), 3);
  // Within a looser tolerance only the extra id remains a violation.
  const CommandResult loose =
      run_demsa({"compare", (dir / "a.dump").string(), (dir / "b.dump").string(), "--tol-pos", "1e-3"});
  EXPECT_EQ(loose.exit_code, 1);
  EXPECT_NE(loose.out.find("1 ids of"), std::string::npos) << loose.out;
}

TEST(CliCompare, CaseFoldersWithPileCompareAngles) {
  TempDir dir;
  std::filesystem::create_directories(dir / "a");
  std::filesystem::create_directories(dir / "b");
  const std::string pile = read_file(data_path("postprocess/liggghts_pile/pile_final.dump"));
  write_file(dir / "a" / "pile_final.dump", pile);
  write_file(dir / "b" / "pile_final.dump", pile);
  const CommandResult r = run_demsa({"compare", (dir / "a").string(), (dir / "b").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out)["comparisons"][0];
  EXPECT_DOUBLE_EQ(j["pile"]["angle_difference_deg"].get<double>(), 0.0);
  EXPECT_GT(j["pile"]["angle_a_deg"].get<double>(), 20.0);
}

TEST(CliCompare, ErrorsExit2) {
  TempDir dir;
  write_file(dir / "a.dump", dump_text(0.1));
  write_file(dir / "bad.dump", "garbage\n");
  EXPECT_EQ(run_demsa({"compare", (dir / "a.dump").string(), (dir / "missing.dump").string()}).exit_code, 2);
  const CommandResult bad = run_demsa({"compare", (dir / "a.dump").string(), (dir / "bad.dump").string()});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("bad.dump:1: expected 'ITEM: TIMESTEP'"), std::string::npos) << bad.err;
  EXPECT_EQ(run_demsa({"compare", (dir / "a.dump").string(), dir.path().string()}).exit_code, 2);
}

}  // namespace
}  // namespace demsa::test
