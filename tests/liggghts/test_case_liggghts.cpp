// Real LIGGGHTS runs of tiny cases written by `demsa case` and run by hand with run.sh: a 300-particle pile and a
// 300-particle oedometer with two loads in both plate modes. Each takes well under two minutes.
#include "postprocess/dump.hpp"
#include "postprocess/oedometer.hpp"
#include "postprocess/pile_angle.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace demsa {
namespace {

namespace fs = std::filesystem;

/// Writes sample 0 of a study in tests/data/cases into `dir` and runs its run.sh from another working directory.
void write_and_run(const std::string& study, const fs::path& dir) {
  const test::CommandResult w =
      test::run_demsa({"case", test::data_path("cases/" + study).string(), "--sample", "0", "-o", dir.string()});
  ASSERT_EQ(w.exit_code, 0) << w.out << w.err;
  const test::CommandResult r = test::run_command({(dir / "run.sh").string()}, dir.parent_path());
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err << test::read_file(dir / "screen.txt");
}

/// The radii a pile case asks for: the column's from pile_particles.data (column 3 of the Atoms section: diameter)
/// and the appended discs' from pile_discs.liggghts (`set region new_atom diameter D`), sorted.
std::vector<double> requested_radii(const fs::path& dir) {
  std::vector<double> radii;
  std::istringstream data(test::read_file(dir / "pile_particles.data"));
  std::string line;
  bool atoms = false;
  while (std::getline(data, line)) {
    if (line.rfind("Atoms", 0) == 0) {
      atoms = true;
      continue;
    }
    std::istringstream words(line);
    long id = 0;
    int type = 0;
    double diameter = 0;
    if (atoms && words >> id >> type >> diameter) radii.push_back(0.5 * diameter);
  }
  std::istringstream discs(test::read_file(dir / "pile_discs.liggghts"));
  const std::string key = "set region new_atom diameter ";
  while (std::getline(discs, line))
    if (line.rfind(key, 0) == 0) radii.push_back(0.5 * std::stod(line.substr(key.size())));
  std::sort(radii.begin(), radii.end());
  return radii;
}

TEST(CaseLiggghts, TinyPileSettlesIntoAPlausibleConeAndRerunsIdentically) {
  test::TempDir tmp;
  const fs::path dir = tmp / "pile case";  // a space in the path must work
  write_and_run("tiny_pile.toml", dir);
  const postprocess::Particles all = postprocess::read_particles(dir / "pile_final.dump", 1);
  // Nothing lost: every particle is in the dump or was removed off the pedestal ([pile] remove_fallen).
  std::istringstream settling(test::read_file(dir / "pile_settling.txt"));
  std::string key;
  double value = 0;
  std::size_t removed = 0;
  while (settling >> key >> value)
    if (key == "removed") removed = static_cast<std::size_t>(value);
  EXPECT_EQ(all.size() + removed, 300u);
  // Every particle has the radius the assembly gave it (appended atoms are found by position, not by id).
  std::vector<double> radii = all.radius;
  std::sort(radii.begin(), radii.end());
  const std::vector<double> requested = requested_radii(dir);
  ASSERT_EQ(radii.size() + removed, requested.size());
  // Every radius in the dump is one that was asked for (removed particles leave gaps in the sorted list).
  for (double r : radii)
    EXPECT_TRUE(std::any_of(requested.begin(), requested.end(), [r](double q) { return std::abs(q - r) < 1e-9; })) << r;
  postprocess::PileAngleOptions options;
  options.levels = 5;
  const postprocess::PileAngleResult angle = postprocess::measure_pile_angle(all, options);
  EXPECT_GT(angle.particles_on_pedestal, 200u);
  EXPECT_GT(angle.pile_height, 0.01);
  EXPECT_GT(angle.angle, 10.0);
  EXPECT_LT(angle.angle, 60.0);

  // The same case again on one rank: a byte-identical final dump.
  fs::copy_file(dir / "pile_final.dump", tmp / "first.dump");
  const test::CommandResult again = test::run_command({(dir / "run.sh").string()});
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(test::read_file(tmp / "first.dump"), test::read_file(dir / "pile_final.dump"));
}

/// A case that LIGGGHTS stops: its run and the LIGGGHTS log.
struct StoppedCase {
  test::CommandResult run;
  std::string log;
  std::string tail() const { return log.substr(log.size() > 3000 ? log.size() - 3000 : 0); }
};

/// tests/data/cases/NAME with the text `from` replaced by `to`, written to TMP/edited.toml; its sample 0 written
/// to TMP/case and run there with its run.sh.
StoppedCase run_edited_case(const test::TempDir& tmp, const std::string& name, const std::string& from,
                            const std::string& to) {
  std::string text = test::read_file(test::data_path("cases/" + name));
  const std::size_t at = text.find(from);
  if (at == std::string::npos)
    ADD_FAILURE() << name << " has no '" << from << "'";
  else
    text.replace(at, from.size(), to);
  test::write_file(tmp / "edited.toml", text);
  const test::CommandResult w =
      test::run_demsa({"case", (tmp / "edited.toml").string(), "--sample", "0", "-o", (tmp / "case").string()});
  EXPECT_EQ(w.exit_code, 0) << w.out << w.err;
  StoppedCase c{test::run_command({(tmp / "case" / "run.sh").string()}), ""};
  c.log = test::read_file(tmp / "case" / "log.liggghts");
  return c;
}

TEST(CaseLiggghts, PileThatReachesTheInsertionHeightStopsWithAClearError) {
  // A fill height of 5 mm above the pedestal: the pile soon reaches the layer where new discs appear. The case must
  // stop there with an error that says so, instead of inserting particles into the pile.
  test::TempDir tmp;
  const StoppedCase c = run_edited_case(tmp, "tiny_pile.toml", "fill_height = 0.06\n", "fill_height = 0.005\n");
  EXPECT_NE(c.run.exit_code, 0);
  EXPECT_NE(c.log.find("the pile has reached the insertion height (raise [pile] fill_height)"), std::string::npos)
      << c.tail();
  EXPECT_NE(c.log.find("ERROR: Unknown command: demsa:_the_pile_has_reached_the_insertion_height"), std::string::npos);
  EXPECT_FALSE(fs::exists(tmp / "case" / "pile_final.dump"));
}

TEST(CaseLiggghts, OedometerPackingAboveTheBoxStopsWithAClearError) {
  // A 5 mm box under 300 particles of 2.5 to 3.5 mm, after a short fill: the plate would start above the box. Both
  // plate modes must stop right after the fill with an error that says so, before any load.
  for (const std::string mode : {"servo", "trial"}) {
    SCOPED_TRACE(mode);
    test::TempDir tmp;
    const StoppedCase c = run_edited_case(tmp, "tiny_oedometer_" + mode + ".toml", "fill_time = 0.25\n",
                                          "fill_time = 0.01\nbox_height = 0.005\n");
    EXPECT_NE(c.run.exit_code, 0);
    EXPECT_NE(c.log.find("plate_gap 0.0005 m lies above box_height = 0.005 m: raise [oedometer] box_height or use "
                         "fewer or smaller particles"),
              std::string::npos)
        << c.tail();
    EXPECT_NE(c.log.find("ERROR: Unknown command: demsa:_the_settled_packing_does_not_fit_under_box_height"),
              std::string::npos);
    EXPECT_FALSE(fs::exists(tmp / "case" / "oedometer_final.dump"));
    // The settled packing is still recorded, and no load state follows it.
    const std::string states = test::read_file(tmp / "case" / "plate_states.txt");
    EXPECT_NE(states.find("# settled packing: particles 300, top_z_m "), std::string::npos) << states;
    EXPECT_TRUE(postprocess::read_plate_states(tmp / "case" / "plate_states.txt").empty());
  }
}

/// Both loads reached within the tolerance, settlement positive.
void check_oedometer(const fs::path& dir, double tolerance) {
  const std::vector<postprocess::PlateState> states = postprocess::read_plate_states(dir / "plate_states.txt");
  ASSERT_EQ(states.size(), 2u);
  EXPECT_DOUBLE_EQ(states[0].load_N, 100.0);
  EXPECT_DOUBLE_EQ(states[1].load_N, 400.0);
  for (const auto& s : states) {
    EXPECT_TRUE(s.converged) << s.load_N;
    EXPECT_LE(std::fabs(s.force_N - s.load_N), tolerance) << s.load_N;
  }
  const double settlement = states[0].plate_z_m - states[1].plate_z_m;
  EXPECT_GT(settlement, 1e-5);
  EXPECT_LT(settlement, 5e-3);
  const postprocess::PlateHistory history = postprocess::read_plate_history(dir / "plate_history.txt");
  EXPECT_GT(history.size(), 5u);
  EXPECT_EQ(postprocess::read_particles(dir / "oedometer_final.dump", 1).size(), 300u);
}

TEST(CaseLiggghts, TinyOedometerServoReachesBothLoads) {
  test::TempDir tmp;
  write_and_run("tiny_oedometer_servo.toml", tmp / "servo");
  check_oedometer(tmp / "servo", 2.0);
}

TEST(CaseLiggghts, TinyOedometerTrialStepReachesBothLoads) {
  test::TempDir tmp;
  write_and_run("tiny_oedometer_trial.toml", tmp / "trial");
  check_oedometer(tmp / "trial", 2.0);
  const postprocess::PlateHistory history = postprocess::read_plate_history(tmp / "trial" / "plate_history.txt");
  ASSERT_EQ(history.accepted.size(), history.size());
  // The paper's loop restores at least once per load on this packing (an overshoot after relaxation).
  EXPECT_GT(std::count(history.accepted.begin(), history.accepted.end(), 0), 0);
}

TEST(CaseLiggghts, AProbeOfATrialStepOedometerBillsItsFirstLoadByTheFillItRead) {
  // `--probe` runs the first case; once its fill is done, plate_states.txt's first comment gives the fill's void ratio,
  // which the trial-step model's first load follows (docs/how-to/cost.md), whether the budget ends the probe or not.
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", test::read_file(test::data_path("cases/tiny_oedometer_trial.toml")));
  const test::CommandResult dry = test::run_demsa(test::run_args(tmp, {"--dry-run", "--json", "--probe", "60"}));
  ASSERT_EQ(dry.exit_code, 0) << dry.out << dry.err;
  const nlohmann::json e = nlohmann::json::parse(dry.out).at("estimate");
  const nlohmann::json& state = e.at("probe").at("state");
  ASSERT_TRUE(state.is_object()) << dry.out;
  EXPECT_EQ(state.at("particles").get<long>(), 300);
  EXPECT_GT(state.at("void_ratio").get<double>(), 0.3);  // a random packing of spheres, loose or dense
  EXPECT_LT(state.at("void_ratio").get<double>(), 3.0);
  EXPECT_NEAR(state.at("plate_gap_m").get<double>(), 0.5e-3, 1e-9);
  const std::string source = e.at("atom_steps_source").get<std::string>();
  EXPECT_NE(source.find("the probe's fill: void ratio"), std::string::npos) << source;
  // The stored probe keeps it: a later dry run bills the same.
  const test::CommandResult again = test::run_demsa(test::run_args(tmp, {"--dry-run", "--json"}));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const nlohmann::json later = nlohmann::json::parse(again.out).at("estimate");
  EXPECT_EQ(later.at("atom_steps_source").get<std::string>(), source);
  EXPECT_DOUBLE_EQ(later.at("atom_steps").get<double>(), e.at("atom_steps").get<double>());
}

TEST(CaseLiggghts, CaseIntoAFolderWithOutputsNeedsOverwrite) {
  // No LIGGGHTS run: the outputs of an earlier ./run.sh are faked.
  test::TempDir tmp;
  const std::string study = test::data_path("cases/tiny_oedometer_servo.toml").string();
  const fs::path dir = tmp / "case";
  ASSERT_EQ(test::run_demsa({"case", study, "--sample", "0", "-o", dir.string()}).exit_code, 0);
  for (const char* f : {"oedometer_final.dump", "log.liggghts", "plate_states.txt"}) test::write_file(dir / f, "old\n");
  const test::CommandResult refused = test::run_demsa({"case", study, "--sample", "1", "-o", dir.string()});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find(dir.string() + ": the case folder is not empty (log.liggghts, oedometer_final.dump, "
                                            "plate_states.txt and "),
            std::string::npos)
      << refused.err;
  EXPECT_NE(test::read_file(dir / "case.json").find("\"sample\": 0"), std::string::npos);
  const test::CommandResult again =
      test::run_demsa({"case", study, "--sample", "1", "-o", dir.string(), "--overwrite", "--json"});
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_FALSE(fs::exists(dir / "oedometer_final.dump"));
  EXPECT_NE(test::read_file(dir / "case.json").find("\"sample\": 1"), std::string::npos);
  const test::CommandResult set =
      test::run_demsa({"case", study, "--set", "E=3e8", "-o", (tmp / "set").string(), "--json"});
  ASSERT_EQ(set.exit_code, 0) << set.err;
  EXPECT_TRUE(nlohmann::json::parse(set.out).at("sample").is_null()) << set.out;
}

TEST(CaseLiggghts, RegeneratedCaseHasIdenticalInputs) {
  test::TempDir tmp;
  for (const char* name : {"a", "b"}) {
    const test::CommandResult w = test::run_demsa({"case", test::data_path("cases/tiny_oedometer_servo.toml").string(),
                                                   "--set", "E=3e8", "-o", (tmp / name).string()});
    ASSERT_EQ(w.exit_code, 0) << w.err;
  }
  for (const auto& entry : fs::directory_iterator(tmp / "a"))
    EXPECT_EQ(test::read_file(entry.path()), test::read_file(tmp / "b" / entry.path().filename())) << entry.path();
}

}  // namespace
}  // namespace demsa
