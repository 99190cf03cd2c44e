// Real LIGGGHTS runs of tiny cases of the pile on a rough base and of the draw-down (written by `demsa case`, run by
// hand with run.sh, measured by `demsa measure`): the frozen layers stay where they were written, the measurement
// leaves them out, and the observables are those of the physics. Each takes well under a minute.
#include "postprocess/dump.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>

namespace demsa {
namespace {

namespace fs = std::filesystem;

void write_and_run(const fs::path& study, const std::string& set, const fs::path& dir) {
  const test::CommandResult w = test::run_demsa({"case", study.string(), "--set", set, "-o", dir.string()});
  ASSERT_EQ(w.exit_code, 0) << w.out << w.err;
  const test::CommandResult r = test::run_command({(dir / "run.sh").string()}, dir.parent_path());
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err << test::read_file(dir / "screen.txt");
}

/// Atom id -> (x, y, z) of the first `count` atoms of a LIGGGHTS data file's Atoms section.
std::map<long, std::array<double, 3>> written_atoms(const fs::path& data, long count) {
  std::map<long, std::array<double, 3>> atoms;
  std::istringstream in(test::read_file(data));
  std::string line;
  bool section = false;
  while (std::getline(in, line)) {
    if (line.rfind("Atoms", 0) == 0) section = true;
    if (!section || line.empty() || line[0] == 'A') continue;
    std::istringstream words(line);
    long id = 0;
    int type = 0;
    double d = 0, rho = 0, x = 0, y = 0, z = 0;
    if (words >> id >> type >> d >> rho >> x >> y >> z && id <= count) atoms[id] = {x, y, z};
  }
  return atoms;
}

/// Every atom 1..count of the final dump is where the data file put it.
void expect_layer_unmoved(const fs::path& dir, const std::string& data, const std::string& dump, long count) {
  const auto written = written_atoms(dir / data, count);
  ASSERT_EQ(static_cast<long>(written.size()), count);
  const postprocess::Particles final_state = postprocess::read_particles(dir / dump);
  long seen = 0;
  for (std::size_t i = 0; i < final_state.size(); ++i) {
    const auto it = written.find(final_state.id[i]);
    if (it == written.end()) continue;
    ++seen;
    EXPECT_NEAR(final_state.x[i], it->second[0], 1e-9) << final_state.id[i];
    EXPECT_NEAR(final_state.y[i], it->second[1], 1e-9) << final_state.id[i];
    EXPECT_NEAR(final_state.z[i], it->second[2], 1e-9) << final_state.id[i];
  }
  EXPECT_EQ(seen, count);
}

TEST(ExperimentsReal, APileOnARoughBaseStandsOnItsFrozenLayer) {
  test::TempDir tmp;
  std::string text = test::read_file(test::data_path("cases/tiny_pile.toml"));
  text.replace(text.find("[pile]\n"), 7, "[pile]\nbase = \"particles\"\npedestal_radius = 0.025\n");
  test::write_file(tmp / "rough.toml", text);
  const fs::path dir = tmp / "case";
  write_and_run(tmp / "rough.toml", "E=1e8,mu_r_pp=0.3", dir);
  const nlohmann::json doc = nlohmann::json::parse(test::read_file(dir / "case.json"));
  const long layer = doc["pile"]["base"]["particles"].get<long>();
  ASSERT_GT(layer, 100);
  expect_layer_unmoved(dir, "pile_particles.data", "pile_final.dump", layer);
  const test::CommandResult m = test::run_demsa({"measure", dir.string(), "--json"});
  ASSERT_EQ(m.exit_code, 0) << m.out << m.err;
  const nlohmann::json values = nlohmann::json::parse(m.out)["observables"];
  // A pile stands on the layer: particles on the pedestal besides the layer, an angle of a pile.
  EXPECT_GT(values["particles_on_pedestal"].get<double>(), 50) << m.out;
  EXPECT_GT(values["angle"].get<double>(), 10) << m.out;
  EXPECT_LT(values["angle"].get<double>(), 50) << m.out;
  const test::CommandResult vtk = test::run_demsa({"export-vtk", dir.string()});
  EXPECT_EQ(vtk.exit_code, 0) << vtk.err;
}

TEST(ExperimentsReal, ADrawdownEmptiesThroughItsSlotAndLeavesSlopes) {
  test::TempDir tmp;
  const fs::path dir = tmp / "case";
  write_and_run(test::data_path("cases/tiny_drawdown.toml"), "mu_pp=1.0,mu_r_pp=0.2", dir);
  const nlohmann::json doc = nlohmann::json::parse(test::read_file(dir / "case.json"));
  const long layer = doc["drawdown"]["floor_particles"].get<long>();
  ASSERT_GT(layer, 20);
  expect_layer_unmoved(dir, "drawdown_particles.data", "drawdown_final.dump", layer);
  const test::CommandResult m = test::run_demsa({"measure", dir.string(), "--json"});
  ASSERT_EQ(m.exit_code, 0) << m.out << m.err;
  const nlohmann::json values = nlohmann::json::parse(m.out)["observables"];
  EXPECT_GT(values["discharged_mass"].get<double>(), 0.0) << m.out;
  EXPECT_GT(values["discharge_rate"].get<double>(), 0.0) << m.out;
  EXPECT_GT(values["retained_fraction"].get<double>(), 0.02) << m.out;
  EXPECT_LT(values["retained_fraction"].get<double>(), 0.9) << m.out;
  EXPECT_GT(values["slope_angle"].get<double>(), 10) << m.out;
  EXPECT_LT(values["slope_angle"].get<double>(), 60) << m.out;
}

}  // namespace
}  // namespace demsa
