#include "orchestrator/exec/failure.hpp"
#include "orchestrator/experiments/registry.hpp"

#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <stdexcept>

namespace demsa {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::experiments;
using namespace demsa::exec;
namespace {

using test::write_file;

std::string dump_text(int atoms, int rows) {
  std::string text = fmt::format(
      "ITEM: TIMESTEP\n1000\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS ff ff ff\n-0.1 0.1\n-0.1 0.1\n0 0.3\n"
      "ITEM: ATOMS id type x y z radius vx vy vz\n",
      atoms);
  for (int i = 0; i < rows; ++i) text += fmt::format("{} 1 0.001 0.002 {} 0.002 0 0 0\n", i + 1, 0.01 + 0.001 * i);
  return text;
}

const char* k_clean_log =
    "LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0)\n"
    "Step Atoms KinEng c_ke\n"
    "       0      10            0            0 \n"
    "    1000      10    0.0012       0.0012 \n"
    "Loop time of 1.5 on 1 procs for 1000 steps with 10 atoms\n";

CaseExit clean_exit() {
  CaseExit exit;
  exit.exit_code = 0;
  return exit;
}

/// A study of `experiment` (an oedometer's with three loads).
const study::StudyConfig& study_of(const std::string& experiment) {
  static const study::StudyConfig pile = experiments::parse_study(
      "[study]\nname = \"s\"\nexperiment = \"pile\"\n[parameters]\nE = { low = 1e8, high = 1e9 }\n", "s.toml");
  static const study::StudyConfig oedometer = experiments::parse_study(
      "[study]\nname = \"s\"\nexperiment = \"oedometer\"\n[parameters]\nE = { low = 1e8, high = 1e9 }\n"
      "[oedometer]\nloads = [100, 400, 1100]\n",
      "s.toml");
  return experiment == "pile" ? pile : oedometer;
}

FailureOptions pile_options() {
  FailureOptions options;
  options.config = &study_of("pile");
  options.expected_particles = 10;
  options.lost_fraction = 0.15;
  options.kinetic_energy_limit = 100.0;
  return options;
}

struct CaseFolder {
  test::TempDir tmp;
  CaseFolder(const std::string& log, const std::string& dump) {
    if (!log.empty()) write_file(tmp / "log.liggghts", log);
    if (!dump.empty()) write_file(tmp / "pile_final.dump", dump);
  }
};

TEST(Failure, CleanCaseIsNone) {
  CaseFolder folder(k_clean_log, dump_text(10, 10));
  const FailureReport report = classify_case(clean_exit(), folder.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::none);
  EXPECT_FALSE(report.requeue);
  EXPECT_TRUE(report.log_tail.empty());
}

TEST(Failure, TimeoutWinsOverEverything) {
  CaseFolder folder("ERROR: something\n", "");
  CaseExit exit;
  exit.timed_out = true;
  const FailureReport report = classify_case(exit, folder.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::timeout);
  EXPECT_NE(report.log_tail.find("ERROR: something"), std::string::npos);
}

TEST(Failure, CancelledAndLostAreRequeuedNotFailed) {
  CaseFolder folder("", "");
  CaseExit exit;
  exit.cancelled = true;
  FailureReport report = classify_case(exit, folder.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::none);
  EXPECT_TRUE(report.requeue);
  exit = CaseExit{};
  exit.lost = true;
  report = classify_case(exit, folder.tmp.path(), pile_options());
  EXPECT_TRUE(report.requeue);
}

TEST(Failure, SignalIsReported) {
  CaseFolder folder(k_clean_log, "");
  CaseExit exit;
  exit.signal = 9;
  const FailureReport report = classify_case(exit, folder.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::signal);
  EXPECT_EQ(report.message, "killed by signal 9");
}

TEST(Failure, ShellReportedSignalExitIsASignal) {
  CaseFolder folder(k_clean_log, "");
  CaseExit exit;
  exit.exit_code = 137;  // 128 + SIGKILL, as bash reports a killed mpirun
  const FailureReport report = classify_case(exit, folder.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::signal);
}

TEST(Failure, LiggghtsErrorLineInLogOrScreenOrRunOut) {
  {
    CaseFolder folder(std::string(k_clean_log) + "ERROR: Lost atoms: original 10 current 9 (../thermo.cpp:407)\n",
                      dump_text(10, 10));
    const FailureReport report = classify_case(clean_exit(), folder.tmp.path(), pile_options());
    EXPECT_EQ(report.failure, FailureClass::liggghts_error);
    EXPECT_EQ(report.message, "ERROR: Lost atoms: original 10 current 9 (../thermo.cpp:407)");
  }
  {
    CaseFolder folder(k_clean_log, "");
    write_file(folder.tmp / "run.out", "ERROR on proc 1: Cannot open file pedestal.stl\n");
    CaseExit exit;
    exit.exit_code = 1;
    const FailureReport report = classify_case(exit, folder.tmp.path(), pile_options());
    EXPECT_EQ(report.failure, FailureClass::liggghts_error);
    EXPECT_NE(report.log_tail.find("Cannot open file pedestal.stl"), std::string::npos);
  }
}

TEST(Failure, NanInThermoIsEnergyBlowup) {
  const std::string log = std::string("Step Atoms KinEng\n 0 10 0\n 100 10 nan\nLoop time of 1\n");
  CaseFolder folder(log, dump_text(10, 10));
  const FailureReport report = classify_case(clean_exit(), folder.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::energy_blowup);
  EXPECT_NE(report.message.find("KinEng"), std::string::npos);
}

TEST(Failure, KineticEnergyAboveTheLimitIsEnergyBlowup) {
  const std::string log = std::string("Step Atoms v_ke\n 0 10 0\n 100 10 5e3\nLoop time of 1\n");
  CaseFolder folder(log, dump_text(10, 10));
  const FailureReport report = classify_case(clean_exit(), folder.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::energy_blowup);
  FailureOptions no_limit = pile_options();
  no_limit.kinetic_energy_limit = 0;
  EXPECT_EQ(classify_case(clean_exit(), folder.tmp.path(), no_limit).failure, FailureClass::none);
}

TEST(Failure, NonZeroExitWithoutOtherCause) {
  CaseFolder folder(k_clean_log, dump_text(10, 10));
  CaseExit exit;
  exit.exit_code = 3;
  const FailureReport report = classify_case(exit, folder.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::nonzero_exit);
  EXPECT_EQ(report.message, "exit status 3");
  EXPECT_NE(report.log_tail.find("Loop time"), std::string::npos);
}

TEST(Failure, MissingAndTruncatedDump) {
  {
    CaseFolder folder(k_clean_log, "");
    const FailureReport report = classify_case(clean_exit(), folder.tmp.path(), pile_options());
    EXPECT_EQ(report.failure, FailureClass::missing_dump);
    EXPECT_EQ(report.message, "pile_final.dump is missing");
  }
  {
    CaseFolder folder(k_clean_log, dump_text(10, 7));
    const FailureReport report = classify_case(clean_exit(), folder.tmp.path(), pile_options());
    EXPECT_EQ(report.failure, FailureClass::missing_dump);
    EXPECT_NE(report.message.find("7 of 10"), std::string::npos);
  }
  {
    std::string text = dump_text(10, 10);
    text.resize(text.size() - 12);  // last row cut in the middle
    CaseFolder folder(k_clean_log, text);
    EXPECT_EQ(classify_case(clean_exit(), folder.tmp.path(), pile_options()).failure, FailureClass::missing_dump);
  }
}

TEST(Failure, LostParticlesAboveTheThreshold) {
  CaseFolder folder(k_clean_log, dump_text(8, 8));  // 2 of 10 lost = 20 % > 15 %
  const FailureReport report = classify_case(clean_exit(), folder.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::lost_particles);
  EXPECT_NE(report.message.find("2 of 10"), std::string::npos);
  CaseFolder within(k_clean_log, dump_text(9, 9));  // 10 % <= 15 %
  EXPECT_EQ(classify_case(clean_exit(), within.tmp.path(), pile_options()).failure, FailureClass::none);
}

TEST(Failure, ParticlesRemovedOffThePedestalAreNotLost) {
  const auto settling = [](int removed) {
    return fmt::format(
        "criterion 5\nsettled 1\nend_step 1000\nfastest_on_pedestal 0.001\nspeed_limit 0.002\n"
        "on_pedestal 6\nfast_on_pedestal 0\nremoved {}\n",
        removed);
  };
  CaseFolder removed(k_clean_log, dump_text(6, 6));  // 4 of 10 gone, all removed on purpose
  write_file(removed.tmp / "pile_settling.txt", settling(4));
  EXPECT_EQ(classify_case(clean_exit(), removed.tmp.path(), pile_options()).failure, FailureClass::none);
  CaseFolder lost(k_clean_log, dump_text(6, 6));  // 2 removed, 2 lost = 20 % > 15 %
  write_file(lost.tmp / "pile_settling.txt", settling(2));
  const FailureReport report = classify_case(clean_exit(), lost.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::lost_particles);
  EXPECT_NE(report.message.find("2 of 10 particles lost"), std::string::npos) << report.message;
  EXPECT_NE(report.message.find("2 more removed on purpose"), std::string::npos) << report.message;
  CaseFolder torn(k_clean_log, dump_text(6, 6));  // a settling file the measurement would refuse
  write_file(torn.tmp / "pile_settling.txt", "criterion 5\nremoved\n");
  const FailureReport bad = classify_case(clean_exit(), torn.tmp.path(), pile_options());
  EXPECT_EQ(bad.failure, FailureClass::missing_dump);
  EXPECT_NE(bad.message.find("pile_settling.txt:2"), std::string::npos) << bad.message;
}

TEST(Failure, PlateNotConvergedAndMissingPlateStates) {
  FailureOptions options;
  options.config = &study_of("oedometer");
  test::TempDir tmp;
  write_file(tmp / "log.liggghts", k_clean_log);
  write_file(tmp / "oedometer_final.dump", dump_text(10, 10));
  EXPECT_EQ(classify_case(clean_exit(), tmp.path(), options).failure, FailureClass::missing_dump);
  write_file(tmp / "plate_states.txt", "# load_N plate_z_m force_N converged\n100 0.09 100.01 1\n400 0.089 380 0\n");
  FailureReport report = classify_case(clean_exit(), tmp.path(), options);
  EXPECT_EQ(report.failure, FailureClass::plate_not_converged);
  EXPECT_NE(report.message.find("400"), std::string::npos);
  EXPECT_TRUE(report.final);  // the same run ends the same way: no retry
  write_file(tmp / "plate_states.txt", "# load_N plate_z_m force_N converged\n100 0.09 100.01 1\n400 0.089 400 1\n");
  report = classify_case(clean_exit(), tmp.path(), options);
  EXPECT_EQ(report.failure, FailureClass::plate_not_converged);
  EXPECT_EQ(report.message, "only 2 of 3 load steps reached");
  EXPECT_FALSE(report.final);
  write_file(tmp / "plate_states.txt", "100 0.09 100 1\n400 0.089 400 1\n1100 0.088 1100 1\n");
  EXPECT_EQ(classify_case(clean_exit(), tmp.path(), options).failure, FailureClass::none);
}

TEST(Failure, DumpCutAnywhereInARowIsMissingDump) {
  // A writer that stops (killed, disk full) can cut the dump at any byte; every cut inside the last row, even one
  // that leaves a row with all its values (the end of line or part of the last value gone), is missing_dump.
  const std::string whole = dump_text(10, 10);
  const std::size_t last_row = whole.rfind('\n', whole.size() - 2) + 1;
  for (std::size_t size = last_row + 1; size < whole.size(); ++size) {
    CaseFolder folder(k_clean_log, whole.substr(0, size));
    const FailureReport report = classify_case(clean_exit(), folder.tmp.path(), pile_options());
    EXPECT_EQ(report.failure, FailureClass::missing_dump) << "cut at byte " << size << ": " << report.message;
    EXPECT_NE(report.message.find("pile_final.dump"), std::string::npos) << report.message;
  }
  // Cut in the middle of an earlier row: the row is short.
  const std::size_t fifth_row = whole.find("\n5 1 ") + 1;
  CaseFolder folder(k_clean_log, whole.substr(0, fifth_row + 9));
  EXPECT_EQ(classify_case(clean_exit(), folder.tmp.path(), pile_options()).failure, FailureClass::missing_dump);
}

TEST(Failure, AtomCountThatDisagreesWithTheRowsIsMissingDump) {
  {
    CaseFolder folder(k_clean_log, dump_text(10, 12));  // more rows than NUMBER OF ATOMS
    const FailureReport report = classify_case(clean_exit(), folder.tmp.path(), pile_options());
    EXPECT_EQ(report.failure, FailureClass::missing_dump);
    EXPECT_NE(report.message.find("more rows than NUMBER OF ATOMS"), std::string::npos) << report.message;
  }
  {
    CaseFolder folder(k_clean_log, dump_text(12, 10));  // fewer: the file ends first
    const FailureReport report = classify_case(clean_exit(), folder.tmp.path(), pile_options());
    EXPECT_EQ(report.failure, FailureClass::missing_dump);
    EXPECT_EQ(report.message, "pile_final.dump is truncated: 10 of 12 atom rows");
  }
}

TEST(Failure, DumpTheMeasurementWouldRefuseIsMissingDump) {
  std::string text = dump_text(10, 10);
  text.replace(text.find("\n3 1 0.001"), 10, "\n3 1 nan  ");  // a position that is not a number
  CaseFolder nan_position(k_clean_log, text);
  FailureReport report = classify_case(clean_exit(), nan_position.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::missing_dump);
  EXPECT_EQ(report.message, "pile_final.dump:12: column 'x': 'nan' is not a finite number");

  text = dump_text(10, 10);
  text.replace(text.find("\n4 1 "), 5, "\n4.5 1 ");  // an id that is not an integer
  CaseFolder fractional_id(k_clean_log, text);
  report = classify_case(clean_exit(), fractional_id.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::missing_dump);
  EXPECT_NE(report.message.find("id 4.5 is not an integer"), std::string::npos) << report.message;

  text = dump_text(10, 10);
  text.replace(text.find(" radius "), 8, " r ");  // no radius column
  CaseFolder no_radius(k_clean_log, text);
  report = classify_case(clean_exit(), no_radius.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::missing_dump);
  EXPECT_NE(report.message.find("no column 'radius'"), std::string::npos) << report.message;
}

TEST(Failure, TornOrMalformedPlateStatesIsMissingDump) {
  FailureOptions options;
  options.config = &study_of("oedometer");
  test::TempDir tmp;
  write_file(tmp / "log.liggghts", k_clean_log);
  write_file(tmp / "oedometer_final.dump", dump_text(10, 10));
  const std::string whole =
      "# load_N plate_z_m force_N converged\n100 0.09 100 1\n400 0.089 400 1\n1100 0.088 1100 1\n";
  // Every cut inside the last row leaves it short.
  const std::size_t last_row = whole.rfind('\n', whole.size() - 2) + 1;
  for (std::size_t size = last_row + 1; size + 1 < whole.size(); ++size) {
    write_file(tmp / "plate_states.txt", whole.substr(0, size));
    const FailureReport report = classify_case(clean_exit(), tmp.path(), options);
    EXPECT_EQ(report.failure, FailureClass::missing_dump) << "cut at byte " << size << ": " << report.message;
  }
  write_file(tmp / "plate_states.txt", "100 0.09 100 1\n400 0.089 40x 1\n1100 0.088 1100 1\n");
  FailureReport report = classify_case(clean_exit(), tmp.path(), options);
  EXPECT_EQ(report.failure, FailureClass::missing_dump);
  EXPECT_EQ(report.message, "plate_states.txt:2: column 'force_N': '40x' is not a number");
  write_file(tmp / "plate_states.txt", "100 0.09 100 1\n400 0.089 400 2\n1100 0.088 1100 1\n");
  EXPECT_EQ(classify_case(clean_exit(), tmp.path(), options).failure, FailureClass::missing_dump);
  // A file with no row at all has reached no load, whatever the number of loads asked for.
  write_file(tmp / "plate_states.txt", "# load_N plate_z_m force_N converged\n");
  report = classify_case(clean_exit(), tmp.path(), options);
  EXPECT_EQ(report.failure, FailureClass::plate_not_converged);
  EXPECT_EQ(report.message, "plate_states.txt has no load step");
  write_file(tmp / "plate_states.txt", whole);
  EXPECT_EQ(classify_case(clean_exit(), tmp.path(), options).failure, FailureClass::none);
}

TEST(Failure, NanKineticEnergyInAnIndentedThermoBlockIsEnergyBlowup) {
  // LIGGGHTS indents its thermo header and prints glibc's "-nan" for a NaN.
  const std::string log =
      "LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0)\n"
      "thermo_style custom step atoms ke c_ke\n"
      "    Step    Atoms         KinEng           c_ke \n"
      "       0       10              0              0 \n"
      "    1000       10          0.002          -nan \n"
      "Loop time of 1.5 on 1 procs for 1000 steps with 10 atoms\n";
  CaseFolder folder(log, dump_text(10, 10));
  const FailureReport report = classify_case(clean_exit(), folder.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::energy_blowup);
  EXPECT_EQ(report.message, "thermo column 'c_ke' is -nan at step 1000");
  // An infinite kinetic energy too; a row that does not fit the header is not a thermo row.
  CaseFolder inf(std::string(k_clean_log) + "Step Atoms KinEng\n 2000 10 inf\n", dump_text(10, 10));
  EXPECT_EQ(classify_case(clean_exit(), inf.tmp.path(), pile_options()).message,
            "thermo column 'KinEng' is inf at step 2000");
  CaseFolder echo(std::string(k_clean_log) + "Step Atoms KinEng\n 2000 10 nan 7\n", dump_text(10, 10));
  EXPECT_EQ(classify_case(clean_exit(), echo.tmp.path(), pile_options()).failure, FailureClass::none);
}

TEST(Failure, IndentedErrorLineIsLiggghtsError) {
  CaseFolder folder(std::string(k_clean_log) + "  ERROR on proc 3: Particle out of box (../fix.cpp:12)\n",
                    dump_text(10, 10));
  const FailureReport report = classify_case(clean_exit(), folder.tmp.path(), pile_options());
  EXPECT_EQ(report.failure, FailureClass::liggghts_error);
  EXPECT_EQ(report.message, "ERROR on proc 3: Particle out of box (../fix.cpp:12)");
}

TEST(Failure, NamesRoundTripAndUnknownListsValidNames) {
  for (FailureClass c : {FailureClass::none, FailureClass::nonzero_exit, FailureClass::signal, FailureClass::timeout,
                         FailureClass::liggghts_error, FailureClass::lost_particles, FailureClass::energy_blowup,
                         FailureClass::missing_dump, FailureClass::plate_not_converged, FailureClass::measurement})
    EXPECT_EQ(failure_class_from_string(to_string(c)), c);
  try {
    failure_class_from_string("crash");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("liggghts-error"), std::string::npos);
  }
}

TEST(Failure, OptionsAreValidated) {
  FailureOptions options = pile_options();
  EXPECT_NO_THROW(options.validate());
  options.lost_fraction = 1.5;
  EXPECT_THROW(options.validate(), std::invalid_argument);
  options = pile_options();
  options.tail_lines = 0;
  EXPECT_THROW(options.validate(), std::invalid_argument);
  options = pile_options();
  options.config = nullptr;
  EXPECT_THROW(options.validate(), std::invalid_argument);
}

TEST(Failure, FileTailKeepsTheLastLines) {
  test::TempDir tmp;
  std::string text;
  for (int i = 1; i <= 100; ++i) text += fmt::format("line {}\n", i);
  write_file(tmp / "log", text);
  EXPECT_EQ(file_tail(tmp / "log", 2), "line 99\nline 100\n");
  EXPECT_EQ(file_tail(tmp / "missing", 2), "");
}

}  // namespace
}  // namespace demsa
