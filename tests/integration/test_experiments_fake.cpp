// The new experiments end to end against the fake LIGGGHTS (tests/integration/fake_liggghts): `demsa run` measures
// their cases into the observables their descriptors name, and a study killed with SIGKILL resumes without repeating a
// finished case.
#include "orchestrator/study/store.hpp"

#include "support/process.hpp"
#include "support/test_support.hpp"

#include <signal.h>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>
#include <string>

namespace demsa {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

/// A study of `experiment` over μ_PW and μ_R,PW (the fake's first two unit-cube coordinates), run by the fake.
std::string study(const std::string& experiment, int samples, const std::string& tables = "") {
  return test::StudyToml{
      .name = "fake-" + experiment,
      .experiment = experiment,
      .samples = samples,
      .parameters = "mu_pw = { low = 0.4, high = 1.9 }\nmu_r_pw = { low = 0.05, high = 0.5 }\n",
      .tables = tables,
      .run = test::fake_liggghts_run_lines() + "parallel = 2\noversubscribe = true\n",
      .analysis = "metamodels = [\"rsm1\"]\nbootstrap = 0\nbase_samples = 64\nsecond_order = false\n"}
      .text();
}

TEST(ExperimentsFake, InclineOnsetsAreMeasuredFromTheProbes) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study("incline", 6));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const study::Store store = study::Store::open_read_only((tmp / "study" / "study.db").string());
  std::map<int, std::vector<double>> units;
  for (const study::SampleRow& s : store.samples()) units[s.sample] = s.unit;
  for (const auto& [sample, values] : store.observables()) {
    SCOPED_TRACE(fmt::format("sample {}", sample));
    // The fake starts its free probes at 5 + 20 u0 degrees and its locked ones at 20 + 30 u1.
    EXPECT_NEAR(values.at("roll_angle"), 5 + 20 * units.at(sample)[0], 0.05);
    EXPECT_NEAR(values.at("slide_angle"), 20 + 30 * units.at(sample)[1], 0.05);
    EXPECT_EQ(values.at("probes_rolled"), 12);
  }
  EXPECT_EQ(store.observables().size(), 6u);
}

TEST(ExperimentsFake, MeasureRefusesAnInclineItCannotHaveMeasured) {
  // issue 45: `demsa measure` stored onsets above the case's maximum tilt and measured a dump with one probe's id on
  // two rows (taking either).
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study("incline", 2));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet", "--no-analyze"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const fs::path folder = tmp / "study" / "cases" / "000000";
  const test::CommandResult as_run = test::run_demsa({"measure", folder.string(), "--json"});
  ASSERT_EQ(as_run.exit_code, 0) << as_run.err;
  const double slide = nlohmann::json::parse(as_run.out).at("observables").at("slide_angle").get<double>();
  // The schedule said the tilt stops below the locked probes' onsets: they have none, and the case has no slide_angle.
  nlohmann::json doc = nlohmann::json::parse(test::read_file(folder / "case.json"));
  doc["incline"]["max_angle_deg"] = slide - 1.0;
  test::write_file(folder / "case.json", doc.dump(2));
  const test::CommandResult capped = test::run_demsa({"measure", folder.string(), "--json"});
  EXPECT_EQ(capped.exit_code, 2) << capped.out << capped.err;
  EXPECT_NE(capped.err.find("slide_angle not measured: 12 of 12 free probes rolled and 0 of 12 locked probes slid"),
            std::string::npos)
      << capped.err;
  // One probe's id on two rows of a frame: exit 2 naming the file and the id.
  std::string dump = test::read_file(folder / "incline_probes.dump");
  const std::size_t atoms = dump.find("ITEM: ATOMS");
  const std::size_t first_row = dump.find('\n', atoms) + 1;
  const std::size_t second_row = dump.find('\n', first_row) + 1;
  const std::string first_id = dump.substr(first_row, dump.find(' ', first_row) - first_row);
  const std::size_t second_id_end = dump.find(' ', second_row);
  dump.replace(second_row, second_id_end - second_row, first_id);
  test::write_file(folder / "incline_probes.dump", dump);
  const test::CommandResult twice = test::run_demsa({"measure", folder.string()});
  EXPECT_EQ(twice.exit_code, 2) << twice.out << twice.err;
  EXPECT_NE(twice.err.find((folder / "incline_probes.dump").string() + ":"), std::string::npos) << twice.err;
  EXPECT_NE(twice.err.find("atom id " + first_id + " appears twice"), std::string::npos) << twice.err;
}

TEST(ExperimentsFake, DrawdownSlopeAndDischargeAreMeasured) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study("drawdown", 4, "[drawdown]\nparticles = 300\n"));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet", "--no-analyze"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const study::Store store = study::Store::open_read_only((tmp / "study" / "study.db").string());
  std::map<int, std::vector<double>> units;
  for (const study::SampleRow& s : store.samples()) units[s.sample] = s.unit;
  for (const auto& [sample, values] : store.observables()) {
    SCOPED_TRACE(fmt::format("sample {}", sample));
    EXPECT_NEAR(values.at("slope_angle"), 25 + 15 * units.at(sample)[0], 1.5);  // the fake's surface
    EXPECT_NEAR(values.at("discharge_rate"), 0.2 + 0.2 * units.at(sample)[1], 1e-9);
    EXPECT_NEAR(values.at("discharged_mass"), 0.5 * (0.2 + 0.2 * units.at(sample)[1]), 1e-9);
    EXPECT_EQ(values.at("settled"), 1.0);
  }
  EXPECT_EQ(store.observables().size(), 4u);
}

TEST(ExperimentsFake, DrumAngleIsMeasuredFromTheSnapshotsSideView) {
  // A coarse drum study (about 1,150 particles in the case files); the fake's snapshots hold a bed under a straight
  // surface at 25 + 20 u0 degrees, high on the left (clockwise).
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study("drum", 3, "[drum]\npreset = \"granudrum\"\ncoarse_grain = 3\n"));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet", "--no-analyze"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const study::Store store = study::Store::open_read_only((tmp / "study" / "study.db").string());
  std::map<int, std::vector<double>> units;
  for (const study::SampleRow& s : store.samples()) units[s.sample] = s.unit;
  for (const auto& [sample, values] : store.observables()) {
    SCOPED_TRACE(fmt::format("sample {}", sample));
    const double angle = 25 + 20 * units.at(sample)[0];
    EXPECT_NEAR(values.at("dynamic_angle"), angle, 0.5);
    EXPECT_EQ(values.at("snapshots"), 3);
    // The surface falls from left to right by tan(angle) per unit of x (stations at -0.45 R and 0.45 R, R = 42 mm).
    EXPECT_NEAR(values.at("surface_1") - values.at("surface_7"), 0.9 * 0.042 * std::tan(angle * std::numbers::pi / 180),
                1e-3);
    EXPECT_GT(values.at("fill_fraction"), 0.3);
    EXPECT_LT(values.at("fill_fraction"), 0.7);
    const fs::path folder = tmp / "study" / "cases" / fmt::format("{:06d}", sample);
    EXPECT_TRUE(fs::is_regular_file(folder / "occupancy.png"));
    EXPECT_TRUE(fs::is_regular_file(folder / "occupancy_surface.png"));
  }
  EXPECT_EQ(store.observables().size(), 3u);
}

TEST(ExperimentsFake, ADrumStudyWhoseStationsChangeIsMeasuredAgainNotRunAgain) {
  // Only how the cases are measured changes (the drum's stations): `demsa run` measures the finished cases again from
  // their files, runs nothing, and a dry run says so without touching the store. A change of the cases is refused.
  test::TempDir tmp;
  const std::string drum = "[drum]\npreset = \"granudrum\"\ncoarse_grain = 3\n";
  // 4 samples: rsm1 in two parameters has 3 terms, and on 3 samples its Q² is not computable.
  test::write_file(tmp / "study.toml", study("drum", 4, drum));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  ASSERT_EQ(test::run_demsa(test::run_args(tmp, {"--quiet"})).exit_code, 0);
  ASSERT_TRUE(fs::is_regular_file(tmp / "study" / "analysis" / "table_surface_7.csv"));
  const fs::path db = tmp / "study" / "study.db";
  const std::size_t runs = study::Store::open_read_only(db.string()).runs().size();
  ASSERT_EQ(runs, 4u);
  EXPECT_EQ(study::Store::open_read_only(db.string()).observables().at(0).count("surface_7"), 1u);

  test::write_file(tmp / "study.toml", study("drum", 4, drum + "stations = [-0.3, 0.0, 0.3]\n"));
  const test::CommandResult dry = test::run_demsa(test::run_args(tmp, {"--dry-run"}));
  ASSERT_EQ(dry.exit_code, 0) << dry.out << dry.err;
  EXPECT_NE(dry.out.find("only how cases are measured changed ([drum] stations"), std::string::npos) << dry.out;
  EXPECT_EQ(study::Store::open_read_only(db.string()).observables().at(0).count("surface_7"), 1u);  // untouched

  const test::CommandResult again = test::run_demsa(test::run_args(tmp, {"--no-analyze"}));
  ASSERT_EQ(again.exit_code, 0) << again.out << again.err;
  EXPECT_NE(again.out.find("4 finished case(s) measured again from their files"), std::string::npos) << again.out;
  const study::Store store = study::Store::open_read_only(db.string());
  EXPECT_EQ(store.runs().size(), runs);  // nothing ran again
  std::map<int, std::vector<double>> units;
  for (const study::SampleRow& s : store.samples()) units[s.sample] = s.unit;
  for (const auto& [sample, values] : store.observables()) {
    SCOPED_TRACE(fmt::format("sample {}", sample));
    EXPECT_EQ(values.count("surface_4"), 0u);
    const double angle = 25 + 20 * units.at(sample)[0];
    EXPECT_NEAR(values.at("surface_1") - values.at("surface_3"), 0.6 * 0.042 * std::tan(angle * std::numbers::pi / 180),
                1e-3);
    const nlohmann::json doc =
        nlohmann::json::parse(test::read_file(tmp / "study" / "cases" / fmt::format("{:06d}", sample) / "case.json"));
    EXPECT_NE(doc.dump().find("0.3"), std::string::npos);
  }
  bool event = false;
  for (const study::EventRow& e : store.events()) event = event || e.kind == "remeasured";
  EXPECT_TRUE(event);
  // The analysis keeps no table of a station no longer measured.
  ASSERT_EQ(test::run_demsa({"analyze", (tmp / "study").string()}).exit_code, 0);
  EXPECT_TRUE(fs::is_regular_file(tmp / "study" / "analysis" / "table_surface_3.csv"));
  EXPECT_FALSE(fs::exists(tmp / "study" / "analysis" / "table_surface_4.csv"));

  // A case whose files are gone cannot be measured again: refused, the store as it was.
  fs::remove(tmp / "study" / "cases" / "000001" / "log.liggghts");
  fs::remove(tmp / "study" / "cases" / "000001" / "drum_snapshots.dump");
  test::write_file(tmp / "study.toml", study("drum", 4, drum + "stations = [-0.2, 0.0, 0.2]\n"));
  const test::CommandResult gone = test::run_demsa(test::run_args(tmp, {"--no-analyze"}));
  EXPECT_EQ(gone.exit_code, 2) << gone.out << gone.err;
  EXPECT_NE(gone.err.find("case 1 is done but its files are gone"), std::string::npos) << gone.err;
  EXPECT_EQ(study::Store::open_read_only(db.string()).observables().at(0).count("surface_3"), 1u);

  // A change of the cases themselves (the drum's speed) is refused as before.
  test::write_file(tmp / "study.toml", study("drum", 4, drum + "rpm = 30\nstations = [-0.3, 0.0, 0.3]\n"));
  const test::CommandResult changed = test::run_demsa(test::run_args(tmp, {"--no-analyze"}));
  EXPECT_EQ(changed.exit_code, 2) << changed.out << changed.err;
  EXPECT_NE(changed.err.find("design-relevant settings differ"), std::string::npos) << changed.err;
}

TEST(ExperimentsFake, ADrumCaseAgainstItsOwnSideViewMismatchesNowhereAndAgainstAPhotographWhereTheyDiffer) {
  // `demsa measure CASE --photograph IMAGE`: the case's occupancy.png given back as a photograph (material light)
  // coincides with the case; the GranuDrum's 15 rpm photograph (a surface near 40°) differs from the fake's bed.
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", study("drum", 4, "[drum]\npreset = \"granudrum\"\ncoarse_grain = 3\n"));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  ASSERT_EQ(test::run_demsa(test::run_args(tmp, {"--quiet"})).exit_code, 0);
  const fs::path folder = tmp / "study" / "cases" / "000000";
  fs::copy_file(folder / "occupancy.png", tmp / "self.png");
  test::write_file(tmp / "self.png.drum.toml",
                   "preset = \"granudrum\"\nrotation = \"clockwise\"\ndark_material = false\n");
  const test::CommandResult self =
      test::run_demsa({"measure", folder.string(), "--photograph", (tmp / "self.png").string(), "--overlay",
                       (tmp / "self_overlay.png").string(), "--json"});
  ASSERT_EQ(self.exit_code, 0) << self.out << self.err;
  const nlohmann::json same = nlohmann::json::parse(self.out);
  EXPECT_LT(same["mismatch_m2"].get<double>(), 2e-6) << self.out;  // a few pixels of 0.2 mm at most
  EXPECT_TRUE(fs::is_regular_file(tmp / "self_overlay.png"));
  EXPECT_TRUE(fs::is_regular_file(tmp / "self_overlay_photograph.png"));  // the photograph measured on its own
  const fs::path photo = fs::path(DEMSA_SOURCE_DIR) / "examples" / "drum-mcc" / "granudrum_mcc_15rpm.bmp";
  const test::CommandResult lab = test::run_demsa({"measure", folder.string(), "--photograph", photo.string()});
  ASSERT_EQ(lab.exit_code, 0) << lab.out << lab.err;
  EXPECT_NE(lab.out.find("mismatch area"), std::string::npos) << lab.out;
  EXPECT_NE(lab.out.find("within 0.77 R"), std::string::npos) << lab.out;
  EXPECT_TRUE(fs::is_regular_file(folder / "lab_overlay.png"));
  const test::CommandResult lab_json =
      test::run_demsa({"measure", folder.string(), "--photograph", photo.string(), "--json"});
  ASSERT_EQ(lab_json.exit_code, 0) << lab_json.err;
  EXPECT_GT(nlohmann::json::parse(lab_json.out)["mismatch_m2"].get<double>(), 20e-6) << lab_json.out;
  // The report shows the case it shows superimposed on the photograph, with their mismatch area.
  const test::CommandResult report = test::run_demsa(
      {"report", (tmp / "study").string(), "--photograph", photo.string(), "--no-html", "-o", (tmp / "r").string()});
  ASSERT_EQ(report.exit_code, 0) << report.out << report.err;
  const std::string md = test::read_file(tmp / "r" / "report.md");
  EXPECT_NE(md.find("Against the photograph `granudrum_mcc_15rpm.bmp`"), std::string::npos) << md;
  EXPECT_NE(md.find("](lab_overlay.png)"), std::string::npos) << md;
  EXPECT_TRUE(fs::is_regular_file(tmp / "r" / "lab_overlay.png"));
  EXPECT_NE(md.find("](lab_overlay_photograph.png)"), std::string::npos) << md;
  EXPECT_NE(md.find("measured on its own"), std::string::npos) << md;
  EXPECT_TRUE(fs::is_regular_file(tmp / "r" / "lab_overlay_photograph.png"));
  // Not a drum case: refused, naming the file.
  test::write_file(tmp / "pile.toml", study("pile", 4, "[pile]\nparticles = 300\n"));
  ASSERT_EQ(test::run_demsa({"run", (tmp / "pile.toml").string(), "--dir", (tmp / "p").string(), "--quiet"}).exit_code,
            0);
  const test::CommandResult pile =
      test::run_demsa({"measure", (tmp / "p" / "cases" / "000000").string(), "--photograph", photo.string()});
  EXPECT_EQ(pile.exit_code, 2) << pile.out;
  EXPECT_NE(pile.err.find("not a laboratory file of a pile case"), std::string::npos) << pile.err;
  const test::CommandResult pile_report =
      test::run_demsa({"report", (tmp / "p").string(), "--photograph", photo.string(), "--no-html"});
  EXPECT_EQ(pile_report.exit_code, 2) << pile_report.out;
  EXPECT_NE(pile_report.err.find("not a laboratory file of a pile study"), std::string::npos) << pile_report.err;
}

TEST(ExperimentsFake, OedometerErrorAgainstMeasuredSettlements) {
  // The measured settlements reach the measurement through case.json's list (oedometer.measured_settlements_m.K).
  test::TempDir tmp;
  test::write_file(tmp / "study.toml",
                   study("oedometer", 2, "[oedometer]\nmeasured_settlements = [0.4e-3, 1.0e-3, 1.8e-3]\n"));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet", "--no-analyze"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const study::Store store = study::Store::open_read_only((tmp / "study" / "study.db").string());
  std::map<int, std::vector<double>> units;
  for (const study::SampleRow& s : store.samples()) units[s.sample] = s.unit;
  for (const auto& [sample, values] : store.observables()) {
    SCOPED_TRACE(fmt::format("sample {}", sample));
    // The fake's plate sinks 1e-5 m per newton over its stiffness 1 + 4 u0 + 0.5 u1, at loads 100, 400, 1100, 2700 N.
    const double stiffness = 1.0 + 4.0 * units.at(sample)[0] + 0.5 * units.at(sample)[1];
    double sum = 0;
    const double measured[] = {0.4e-3, 1.0e-3, 1.8e-3};
    const double loads[] = {400, 1100, 2700};
    for (int i = 0; i < 3; ++i) {
      const double s = 1e-5 * (loads[i] - 100) / stiffness;
      sum += (measured[i] - s) * (measured[i] - s);
    }
    EXPECT_NEAR(values.at("settlement_error"), std::sqrt(sum), 1e-9);
  }
  EXPECT_EQ(store.observables().size(), 2u);
}

class ExperimentResume : public testing::TestWithParam<std::string> {};

TEST_P(ExperimentResume, AStudyKilledWithSigkillResumesWithoutRepeatingAFinishedCase) {
  test::TempDir tmp;
  const int samples = 6;
  test::write_file(tmp / "study.toml", study(GetParam(), samples));
  const std::vector<std::string> args = test::run_args(tmp, {"--no-analyze", "--quiet"});
  std::set<int> finished;
  {
    test::FakeLiggghtsEnvironment env("", tmp.path(), 0.4);
    const pid_t pid = test::spawn_demsa(args, tmp / "demsa.log");
    // Killed once two cases are done and others run.
    test::wait_until(
        [&] {
          int done = 0;
          for (int k = 0; k < samples; ++k)
            done += fs::exists(tmp / "study" / "cases" / fmt::format("{:06d}", k) / "result.json");
          return done >= 2;
        },
        30s);
    ::kill(pid, SIGKILL);
    test::wait_exit(pid);
    const study::Store store = study::Store::open_read_only((tmp / "study" / "study.db").string());
    for (const auto& [sample, values] : store.observables()) finished.insert(sample);
  }
  ASSERT_GE(finished.size(), 1u);
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::CommandResult resumed = test::run_demsa(args);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.out << resumed.err;
  const study::Store store = study::Store::open_read_only((tmp / "study" / "study.db").string());
  EXPECT_EQ(store.observables().size(), static_cast<std::size_t>(samples));
  const std::map<int, int> starts = test::starts_per_sample(tmp.path());
  for (const int sample : finished) EXPECT_EQ(starts.at(sample), 1) << "sample " << sample << " ran again";
  ASSERT_EQ(test::run_demsa({"analyze", (tmp / "study").string()}).exit_code, 0);
  const test::CommandResult report = test::run_demsa({"report", (tmp / "study").string()});
  EXPECT_EQ(report.exit_code, 0) << report.out << report.err;
}

INSTANTIATE_TEST_SUITE_P(NewExperiments, ExperimentResume, testing::Values("incline", "drawdown"));

}  // namespace
}  // namespace demsa
