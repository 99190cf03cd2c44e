// Case folders: the files, their determinism, run.sh, case.json, the refusal of settings LIGGGHTS cannot run,
// and the paper-size presets (written, not run).
#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/experiments/embedded_templates.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <sstream>

namespace demsa {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::experiments;
using namespace demsa::cases;
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
  EXPECT_NE(run.find("--bind-to none -np 1 'liggghts' -in in.liggghts -log log.liggghts -screen screen.txt"),
            std::string::npos);
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

TEST(CaseWriter, FolderWithFilesIsRefusedEmptiedOrRewrittenAsAsked) {
  const StudyConfig c = study("[pile]\nparticles = 100\n");
  TempDir tmp;
  const fs::path dir = tmp / "case";
  const CaseRequest r = request_from_unit_point(c, 2, {0.5, 0.5});
  write_case(c, r, dir, ExistingCaseFiles::refuse);  // a new folder
  // The outputs of an earlier ./run.sh.
  for (const char* f : {"pile_final.dump", "log.liggghts", "screen.txt"}) test::write_file(dir / f, "old\n");
  const std::string m = test::message_of<UserError>([&] { write_case(c, r, dir, ExistingCaseFiles::refuse); });
  EXPECT_NE(m.find(dir.string() + ": the case folder is not empty (log.liggghts, pile_final.dump, screen.txt and "),
            std::string::npos)
      << m;
  EXPECT_NE(m.find("--overwrite"), std::string::npos) << m;
  EXPECT_TRUE(fs::exists(dir / "pile_final.dump"));

  // Only the old outputs: they are named.
  const fs::path outputs = tmp / "outputs";
  fs::create_directories(outputs / "post");
  for (const char* f : {"pile_final.dump", "log.liggghts", "screen.txt"}) test::write_file(outputs / f, "old\n");
  const std::string m2 = test::message_of<UserError>([&] { write_case(c, r, outputs, ExistingCaseFiles::refuse); });
  EXPECT_NE(m2.find("(log.liggghts, pile_final.dump, screen.txt and 1 more)"), std::string::npos) << m2;
  EXPECT_FALSE(fs::exists(outputs / "case.json"));

  // demsa run's path (the default): the case's files are written, other files are left to the caller.
  write_case(c, r, dir);
  EXPECT_TRUE(fs::exists(dir / "pile_final.dump"));

  // --overwrite: the folder is emptied first.
  const std::string before = read_file(dir / "params.liggghts");
  write_case(c, r, dir, ExistingCaseFiles::remove);
  for (const char* f : {"pile_final.dump", "log.liggghts", "screen.txt"}) EXPECT_FALSE(fs::exists(dir / f)) << f;
  EXPECT_EQ(read_file(dir / "params.liggghts"), before);
  EXPECT_TRUE(fs::exists(dir / "run.sh"));

  // A folder that holds no case.json is not a case folder: --overwrite leaves it alone.
  const std::string m3 = test::message_of<UserError>([&] { write_case(c, r, outputs, ExistingCaseFiles::remove); });
  EXPECT_NE(m3.find("but no case.json: it is not a case folder"), std::string::npos) << m3;
  EXPECT_TRUE(fs::exists(outputs / "pile_final.dump"));

  // A file is not a folder.
  test::write_file(tmp / "plain", "x\n");
  EXPECT_NE(test::message_of<UserError>([&] {
              write_case(c, r, tmp / "plain", ExistingCaseFiles::remove);
            }).find("it is a file, not a folder"),
            std::string::npos);
}

TEST(CaseWriter, OverwriteNeverEmptiesTheFolderOfTheStudyFile) {
  TempDir tmp;
  const std::string text =
      "[study]\nname = \"t\"\nexperiment = \"pile\"\n[parameters]\n"
      "mu_pp = { low = 0.5, high = 1.0 }\n[pile]\nparticles = 100\n";
  test::write_file(tmp / "study.toml", text);
  const StudyConfig c = load_study(tmp / "study.toml");
  const CaseRequest r = request_from_unit_point(c, 0, {0.5});
  test::write_file(tmp / "case.json", "{}\n");  // a case written next to the study file earlier
  const std::string m = test::message_of<UserError>([&] { write_case(c, r, tmp.path(), ExistingCaseFiles::remove); });
  EXPECT_NE(m.find("will not empty the folder that holds the study file"), std::string::npos) << m;
  EXPECT_EQ(read_file(tmp / "study.toml"), text);
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
  const StudyConfig c = study("[oedometer]\nparticles = 50\nservo_vel_max = 1000.0\n", "oedometer");
  TempDir tmp;
  try {
    write_case(c, request_from_unit_point(c, 0, {0.5, 0.5}), tmp / "x");
    FAIL() << "no error";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("servo_vel_max = 1000 m/s reaches skin/(2 dt)"), std::string::npos)
        << e.what();
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
  // case.json: no design row, so no sample number.
  TempDir tmp;
  write_case(c, r, tmp / "set");
  const nlohmann::json j = nlohmann::json::parse(read_file(tmp / "set" / "case.json"));
  ASSERT_TRUE(j.contains("sample"));
  EXPECT_TRUE(j["sample"].is_null()) << j["sample"];
  EXPECT_DOUBLE_EQ(j["parameters"]["E"].get<double>(), 2e8);
}

TEST(CaseWriter, TrialStepOedometerRunsTheDriver) {
  const StudyConfig c = study("[oedometer]\nparticles = 60\nplate_mode = \"trial-step\"\n", "oedometer");
  TempDir tmp;
  CaseRequest r = request_from_unit_point(c, 0, {0.5, 0.5});
  r.demsa_executable = "/opt/my tools/demsa";
  write_case(c, r, tmp / "t");
  const std::string run = read_file(tmp / "t" / "run.sh");
  EXPECT_NE(run.find("demsa_built='/opt/my tools/demsa'\ndemsa=\"${DEMSA:-$demsa_built}\"\n"), std::string::npos)
      << run;
  EXPECT_NE(run.find("-np 1 \"$demsa\" drive-oedometer ."), std::string::npos) << run;
  for (const char* f : {"oedometer_restore.liggghts", "oedometer_plate.liggghts", "plate.stl"})
    EXPECT_TRUE(fs::exists(tmp / "t" / f)) << f;
  const nlohmann::json j = nlohmann::json::parse(read_file(tmp / "t" / "case.json"));
  EXPECT_EQ(j["oedometer"]["trial_step"]["trial_steps"], 15000);
  EXPECT_EQ(j["oedometer"]["trial_step"]["relax_steps"], 80000);
  EXPECT_DOUBLE_EQ(j["oedometer"]["trial_step"]["trial_step0_m"].get<double>(), 0.0075e-3);
}

TEST(CaseWriter, TrialStepRunScriptFindsDemsaWhenTheFolderMoves) {
  TempDir tmp;
  // A fake mpirun that records the program it was asked to start, and a `demsa` on PATH.
  fs::create_directories(tmp / "bin");
  test::write_file(tmp / "bin" / "mpirun",
                   "#!/bin/sh\nfor a; do last3=\"$last2\"; last2=\"$last1\"; last1=\"$a\"; done\n"
                   "echo \"$last3\" > started.txt\n");
  test::write_file(tmp / "bin" / "demsa", "#!/bin/sh\nexit 0\n");
  test::write_file(tmp / "other-demsa", "#!/bin/sh\nexit 0\n");
  for (const char* f : {"bin/mpirun", "bin/demsa", "other-demsa"})
    fs::permissions(tmp / f, fs::perms::owner_all, fs::perm_options::replace);
  const StudyConfig c = study("[oedometer]\nparticles = 60\nplate_mode = \"trial-step\"\n[run]\nmpirun = \"" +
                                  (tmp / "bin" / "mpirun").string() + "\"\n",
                              "oedometer");
  CaseRequest r = request_from_unit_point(c, 0, {0.5, 0.5});
  r.demsa_executable = tmp / "build-that-moved" / "demsa";
  write_case(c, r, tmp / "a");
  write_case(c, r, tmp / "b");
  for (const auto& entry : fs::directory_iterator(tmp / "a"))
    EXPECT_EQ(read_file(entry.path()), read_file(tmp / "b" / entry.path().filename())) << entry.path();

  const std::string path = "PATH=" + (tmp / "bin").string() + ":/usr/bin:/bin";
  const auto started = [&](const std::vector<std::string>& env) {
    std::vector<std::string> argv{"env", "-u", "DEMSA", path};
    argv.insert(argv.end(), env.begin(), env.end());
    argv.push_back((tmp / "a" / "run.sh").string());
    const test::CommandResult result = test::run_command(argv);
    EXPECT_EQ(result.exit_code, 0) << result.err;
    const std::string text = read_file(tmp / "a" / "started.txt");
    return text.substr(0, text.find('\n'));
  };
  EXPECT_EQ(started({}), "demsa");  // the writing build is gone: demsa from PATH
  EXPECT_EQ(started({"DEMSA=" + (tmp / "other-demsa").string()}), (tmp / "other-demsa").string());
  EXPECT_EQ(started({"DEMSA=" + (tmp / "a" / "case.json").string()}), "demsa");  // not an executable
  // The writing build is still there: it is used.
  fs::create_directories(tmp / "build-that-moved");
  fs::copy_file(tmp / "other-demsa", tmp / "build-that-moved" / "demsa");
  EXPECT_EQ(started({}), (tmp / "build-that-moved" / "demsa").string());
  // No demsa anywhere: a clear error.
  fs::remove(tmp / "bin" / "demsa");
  fs::remove(tmp / "build-that-moved" / "demsa");
  const test::CommandResult none = test::run_command({"env", "-u", "DEMSA", path, (tmp / "a" / "run.sh").string()});
  EXPECT_EQ(none.exit_code, 127);
  EXPECT_NE(none.err.find("set DEMSA=/path/to/demsa"), std::string::npos) << none.err;
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

namespace demsa {
namespace {

/// Every *.liggghts file of a case folder, concatenated.
std::string all_inputs(const std::filesystem::path& dir) {
  std::string text;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".liggghts") text += test::read_file(e.path());
  return text;
}

/// The value of `variable NAME equal VALUE` in params.liggghts; "" when absent.
std::string param(const std::string& params, const std::string& name) {
  std::istringstream in(params);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string variable, key, style, value;
    if (words >> variable >> key >> style >> value && variable == "variable" && key == name) return value;
  }
  return "";
}

int count_of(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(CaseWriterRolling, TheDefaultWritesTheCdtTemplatesAsTheyAre) {
  const study::StudyConfig c = experiments::parse_study(
      "[study]\nname = \"t\"\nexperiment = \"pile\"\n[parameters]\nE = { low = 1e8, high = 1e9 }\n"
      "[pile]\nparticles = 300\n",
      "study.toml");
  test::TempDir tmp;
  cases::CaseRequest r = cases::request_from_unit_point(c, 0, {0.5});
  cases::write_case(c, r, tmp / "case");
  for (const char* name : {"contact.liggghts", "pile.liggghts"}) {
    const std::string written =
        test::read_file(tmp / "case" / (std::string(name) == "pile.liggghts" ? "in.liggghts" : name));
    EXPECT_EQ(written, experiments::embedded_templates().at(name)) << name;
  }
  EXPECT_EQ(test::read_file(tmp / "case" / "params.liggghts").find("rolling_damping"), std::string::npos);
}

TEST(CaseWriterRolling, ViscousIsWrittenIntoEveryPairAndWallFixInSI) {
  for (const std::string oedometer : {"", "servo", "trial-step"}) {
    SCOPED_TRACE(oedometer.empty() ? "pile" : oedometer);
    const std::string experiment = oedometer.empty() ? "pile" : "oedometer";
    const std::string table = oedometer.empty() ? "[pile]\nparticles = 300\n"
                                                : "[oedometer]\nparticles = 300\nplate_mode = \"" + oedometer + "\"\n";
    const study::StudyConfig c = experiments::parse_study(
        "[study]\nname = \"t\"\nexperiment = \"" + experiment +
            "\"\n[parameters]\nmu_r_pp = { low = 0.45, high = 4.5 }\n[contact]\nrolling_model = \"viscous\"\n"
            "viscous_unit = \"mm*ms\"\n[material]\nmu_r_pw = 5\n" +
            table,
        "study.toml");
    test::TempDir tmp;
    cases::CaseRequest r = cases::request_from_values(c, {{"mu_r_pp", 2.0}});
    r.demsa_executable = "/usr/bin/demsa";
    cases::write_case(c, r, tmp / "case");
    const std::string inputs = all_inputs(tmp / "case");
    EXPECT_EQ(count_of(inputs, "rolling_friction cdt"), 0);
    // pair_style and every wall/gran fix
    EXPECT_EQ(count_of(inputs, "model hertz tangential history rolling_friction viscous"),
              count_of(inputs, "model hertz tangential history"));
    EXPECT_GE(count_of(inputs, "model hertz tangential history rolling_friction viscous"), 2);
    EXPECT_EQ(count_of(inputs, "coefficientRollingFriction"), 0);
    EXPECT_EQ(count_of(inputs, "property/global coefficientRollingViscosity peratomtypepair 2 ${mu_r_pp} ${mu_r_pw}"),
              1);
    // mm·ms to s·m
    const std::string params = test::read_file(tmp / "case" / "params.liggghts");
    EXPECT_EQ(param(params, "mu_r_pp"), "2e-06") << params;
    EXPECT_EQ(param(params, "mu_r_pw"), "5e-06") << params;
  }
}

TEST(CaseWriterRolling, EpsdModelsWriteTheirDampingAndStiffness) {
  const study::StudyConfig c = experiments::parse_study(
      "[study]\nname = \"t\"\nexperiment = \"pile\"\n[parameters]\nmu_r_pp = { low = 0.05, high = 0.5 }\n"
      "[contact]\nrolling_model = \"epsd3\"\nrolling_damping = 0.25\nrolling_stiffness = 3\n[pile]\nparticles = 300\n",
      "study.toml");
  test::TempDir tmp;
  cases::write_case(c, cases::request_from_values(c, {{"mu_r_pp", 0.2}}), tmp / "case");
  const std::string inputs = all_inputs(tmp / "case");
  EXPECT_EQ(count_of(inputs, "rolling_friction cdt"), 0);
  EXPECT_EQ(count_of(inputs, "model hertz tangential history rolling_friction epsd3"),
            count_of(inputs, "model hertz tangential history"));
  EXPECT_EQ(count_of(inputs, "coefficientRollingViscousDamping peratomtypepair 2 ${rolling_damping}"), 1);
  EXPECT_EQ(count_of(inputs, "rollingStiffness scalar ${rolling_stiffness}"), 1);
  const std::string params = test::read_file(tmp / "case" / "params.liggghts");
  EXPECT_EQ(param(params, "rolling_damping"), "0.25") << params;
  EXPECT_EQ(param(params, "rolling_stiffness"), "3") << params;
  EXPECT_EQ(param(params, "mu_r_pp"), "0.2") << params;
}

}  // namespace
}  // namespace demsa
