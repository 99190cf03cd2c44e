// Case folders: the files, their determinism, run.sh, case.json, the refusal of settings LIGGGHTS cannot run,
// and the paper-size presets (written, not run).
#include "orchestrator/case_writer.hpp"
#include "orchestrator/errors.hpp"
#include "orchestrator/study_config.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <sstream>

namespace demsa {
namespace {

namespace fs = std::filesystem;
using test::read_file;
using test::TempDir;

StudyConfig study(const std::string& extra, const std::string& experiment = "pile") {
  return parse_study("[study]\nname = \"t\"\nexperiment = \"" + experiment +
                         "\"\nseed = 11\n[parameters]\nE = { low = 1e8, high = 1e9, scale = \"log\" }\n"
                         "mu_r_pp = { low = 0.05, high = 0.5 }\n" +
                         extra,
                     "study.toml");
}

int count_lines_starting(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) ++n;
  return n;
}

/// Atoms in a read_data file: the "N atoms" header line.
int data_atoms(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line))
    if (line.find(" atoms") != std::string::npos) return std::stoi(line);
  return -1;
}

TEST(CaseWriter, PileCaseHasEveryFile) {
  const StudyConfig c = study("[pile]\nparticles = 300\n");
  TempDir tmp;
  const fs::path dir = tmp / "case with space";
  CaseRequest r = request_from_unit_point(c, 3, {0.5, 0.25});
  r.demsa_executable = "/usr/bin/demsa";
  const CaseSummary s = write_case(c, r, dir);
  for (const char* f : {"in.liggghts", "params.liggghts", "run.sh", "case.json", "pile_particles.data",
                        "pile_discs.liggghts", "pedestal.stl", "system.liggghts", "contact.liggghts"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  EXPECT_EQ(s.particles, 300);
  EXPECT_EQ(s.final_dump, "pile_final.dump");
  const std::string params = read_file(dir / "params.liggghts");
  // E at u = 0.5 on a log scale: sqrt(1e8 * 1e9).
  EXPECT_NE(params.find("variable E                    equal 316227766.01683"), std::string::npos) << params;
  EXPECT_NE(params.find("variable dt "), std::string::npos);
  // 300 particles = initial column + appended.
  const int column = data_atoms(read_file(dir / "pile_particles.data"));
  const int appended = count_lines_starting(read_file(dir / "pile_discs.liggghts"), "create_atoms");
  EXPECT_EQ(column + appended, 300);
  EXPECT_GT(column, 0);

  const nlohmann::json j = nlohmann::json::parse(read_file(dir / "case.json"));
  EXPECT_EQ(j["sample"], 3);
  EXPECT_EQ(j["seed"], 11);
  EXPECT_DOUBLE_EQ(j["unit_point"][1].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(j["parameters"]["mu_r_pp"].get<double>(), 0.05 + 0.25 * 0.45);
  EXPECT_DOUBLE_EQ(j["dt"].get<double>(), s.dt);
  EXPECT_NEAR(j["dt_fraction_of_rayleigh"].get<double>(), 0.15, 1e-12);
  EXPECT_EQ(j["dt_source"], "rayleigh");

  const fs::perms p = fs::status(dir / "run.sh").permissions();
  EXPECT_NE(p & fs::perms::owner_exec, fs::perms::none);
  const std::string run = read_file(dir / "run.sh");
  EXPECT_NE(run.find("set -u"), std::string::npos);
  EXPECT_NE(run.find("cd \"$(dirname \"$0\")\""), std::string::npos);
  EXPECT_NE(run.find("stdbuf -oL -eL 'mpirun'"), std::string::npos);
  EXPECT_NE(run.find("-np 1 'liggghts' -in in.liggghts -log log.liggghts -screen screen.txt"), std::string::npos);
  EXPECT_EQ(run.find("-screen none"), std::string::npos);
}

TEST(CaseWriter, RegeneratingGivesIdenticalFiles) {
  const StudyConfig c = study("[pile]\nparticles = 200\n");
  TempDir tmp;
  const CaseRequest r = request_from_unit_point(c, 0, {0.1, 0.9});
  write_case(c, r, tmp / "a");
  write_case(c, r, tmp / "b");
  for (const auto& entry : fs::directory_iterator(tmp / "a"))
    EXPECT_EQ(read_file(entry.path()), read_file(tmp / "b" / entry.path().filename())) << entry.path();
  // Another sample: same particles and geometry, other parameters.
  write_case(c, request_from_unit_point(c, 1, {0.7, 0.3}), tmp / "c");
  EXPECT_EQ(read_file(tmp / "a" / "pile_particles.data"), read_file(tmp / "c" / "pile_particles.data"));
  EXPECT_EQ(read_file(tmp / "a" / "pedestal.stl"), read_file(tmp / "c" / "pedestal.stl"));
  EXPECT_NE(read_file(tmp / "a" / "params.liggghts"), read_file(tmp / "c" / "params.liggghts"));
}

TEST(CaseWriter, TooLargeFixedTimestepIsRefused) {
  const StudyConfig c = study("[pile]\nparticles = 100\n[timestep]\nmode = \"fixed\"\nvalue = 2e-5\n");
  TempDir tmp;
  try {
    write_case(c, request_from_unit_point(c, 4, {1.0, 0.5}), tmp / "x");
    FAIL() << "no error";
  } catch (const UserError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("study.toml: sample 4 cannot run in LIGGGHTS: time step 2e-05 s is"), std::string::npos) << m;
    EXPECT_NE(m.find("Rayleigh times"), std::string::npos) << m;
  }
  EXPECT_FALSE(fs::exists(tmp / "x"));
}

TEST(CaseWriter, ServoSpeedLimitIsRefused) {
  const StudyConfig c = study("[oedometer]\nparticles = 50\nservo_vel_max = 100.0\n", "oedometer");
  TempDir tmp;
  try {
    write_case(c, request_from_unit_point(c, 0, {0.5, 0.5}), tmp / "x");
    FAIL() << "no error";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("servo_vel_max = 100 m/s reaches skin/(2 dt)"), std::string::npos) << e.what();
  }
}

TEST(CaseWriter, SetValuesAreCheckedAndExact) {
  const StudyConfig c = study("");
  const CaseRequest r = request_from_values(c, {{"E", 2e8}});
  EXPECT_EQ(r.sample, -1);
  EXPECT_DOUBLE_EQ(r.physical[0], 2e8);
  EXPECT_DOUBLE_EQ(r.unit_point[1], 0.5);
  EXPECT_THROW(request_from_values(c, {{"E", 2e9}}), UserError);
  EXPECT_THROW(request_from_values(c, {{"young", 2e8}}), UserError);
  EXPECT_THROW(request_from_values(c, {{"nu", 0.3}}), UserError);  // not varied
}

TEST(CaseWriter, TrialStepOedometerRunsTheDriver) {
  const StudyConfig c = study("[oedometer]\nparticles = 60\nplate_mode = \"trial-step\"\n", "oedometer");
  TempDir tmp;
  CaseRequest r = request_from_unit_point(c, 0, {0.5, 0.5});
  r.demsa_executable = "/opt/my tools/demsa";
  write_case(c, r, tmp / "t");
  const std::string run = read_file(tmp / "t" / "run.sh");
  EXPECT_NE(run.find("'/opt/my tools/demsa' drive-oedometer ."), std::string::npos) << run;
  for (const char* f : {"oedometer_restore.liggghts", "oedometer_plate.liggghts", "plate.stl"})
    EXPECT_TRUE(fs::exists(tmp / "t" / f)) << f;
  const nlohmann::json j = nlohmann::json::parse(read_file(tmp / "t" / "case.json"));
  EXPECT_EQ(j["oedometer"]["trial_step"]["trial_steps"], 15000);
  EXPECT_EQ(j["oedometer"]["trial_step"]["relax_steps"], 80000);
  EXPECT_DOUBLE_EQ(j["oedometer"]["trial_step"]["trial_step0_m"].get<double>(), 0.0075e-3);
}

TEST(CaseWriter, PaperPresetsWriteFullCases) {
  TempDir tmp;
  for (const std::string preset : {"set1", "set2"}) {
    const StudyConfig c = study("[pile]\npreset = \"" + preset + "\"\n");
    const CaseSummary s = write_case(c, request_from_unit_point(c, 0, {1.0, 1.0}), tmp / preset);
    const int expected = preset == "set1" ? 6000 : 8000;
    EXPECT_EQ(s.particles, expected);
    const int column = data_atoms(read_file(tmp / preset / "pile_particles.data"));
    const int appended = count_lines_starting(read_file(tmp / preset / "pile_discs.liggghts"), "create_atoms");
    EXPECT_EQ(column + appended, expected) << preset;
    // Every appended atom gets its radius through a region around its centre, never through a predicted id.
    const std::string discs = read_file(tmp / preset / "pile_discs.liggghts");
    EXPECT_EQ(count_lines_starting(discs, "set region new_atom diameter "), appended) << preset;
    EXPECT_EQ(count_lines_starting(discs, "set atom"), 0) << preset;
    EXPECT_EQ(count_lines_starting(discs, "if \"${in_insertion_zone} > 0\""),
              count_lines_starting(discs, "run ${append_steps}"))
        << preset << ": the insertion height is checked before every appended disc";
  }
  const StudyConfig o = study("[oedometer]\npreset = \"paper\"\n", "oedometer");
  const CaseSummary s = write_case(o, request_from_unit_point(o, 0, {1.0, 1.0}), tmp / "oed");
  EXPECT_EQ(s.particles, 4642);
  EXPECT_EQ(data_atoms(read_file(tmp / "oed" / "oedometer_particles.data")), 4642);
  EXPECT_EQ(count_lines_starting(read_file(tmp / "oed" / "oedometer_particles.data"), "4642 1 "), 1);
}

}  // namespace
}  // namespace demsa
