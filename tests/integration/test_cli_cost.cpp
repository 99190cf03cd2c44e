// `demsa run STUDY --dry-run --json` prints the study's bill (exec/cost.hpp) at the fake LIGGGHTS's rate, measured
// once and then reused; after the cases ran, `demsa status --json` takes the study's own rate and ratio, and the
// store holds predicted against actual per case.
#include "orchestrator/exec/cost.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/errors.hpp"

#include "support/process.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

namespace demsa {
namespace {

namespace fs = std::filesystem;

int lines_of(const fs::path& file) {
  const std::string text = fs::exists(file) ? test::read_file(file) : "";
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

TEST(CliCost, DryRunJsonThenStatusAfterTheRun) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml",
                   test::StudyToml{.name = "cost",
                                   .samples = 4,
                                   .tables = "[pile]\nparticles = 300\n",
                                   .run = test::fake_liggghts_run_lines() + "parallel = 2\noversubscribe = true\n",
                                   .analysis = "metamodels = [\"rsm2\"]\nbootstrap = 0\nbase_samples = 512\n"
                                               "second_order = false\n"}
                       .text());
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  ::setenv("DEMSA_RATE_CACHE", (tmp / "cache" / "rates.json").c_str(), 1);
  ::setenv("FAKE_LIGGGHTS_RATE", "5e6", 1);

  const test::CommandResult dry = test::run_demsa(test::run_args(tmp, {"--dry-run", "--json"}));
  ASSERT_EQ(dry.exit_code, 0) << dry.out << dry.err;
  const nlohmann::json j = nlohmann::json::parse(dry.out);
  const nlohmann::json& e = j.at("estimate");
  const double atom_steps = e.at("atom_steps").get<double>();
  EXPECT_GT(atom_steps, 0.0);
  EXPECT_NEAR(e.at("rate_atom_steps_per_cpu_second").get<double>(), 5e6, 1.0);
  EXPECT_NEAR(e.at("cpu_seconds").get<double>(), atom_steps / 5e6, 1e-9 * atom_steps);
  EXPECT_GT(e.at("wall_seconds").get<double>(), 0.0);
  EXPECT_LE(e.at("wall_seconds").get<double>(), e.at("cpu_seconds").get<double>());
  EXPECT_EQ(e.at("cases").size(), 4U);
  EXPECT_EQ(e.at("slots").get<int>(), 2);
  double sum = 0.0;
  for (const nlohmann::json& c : e.at("cases")) sum += c.at("atom_steps").get<double>();
  EXPECT_DOUBLE_EQ(sum, atom_steps);
  EXPECT_EQ(lines_of(tmp / "rate_starts.log"), 1);

  // The text form says which rate and where it is cached; the second dry run reuses it.
  const test::CommandResult text = test::run_demsa(test::run_args(tmp, {"--dry-run"}));
  ASSERT_EQ(text.exit_code, 0) << text.out << text.err;
  EXPECT_NE(text.out.find("atom-steps per CPU-second"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find((tmp / "cache" / "rates.json").string()), std::string::npos) << text.out;
  EXPECT_EQ(lines_of(tmp / "rate_starts.log"), 1);

  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet", "--no-analyze"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const study::Store store = study::Store::open_read_only((tmp / "study" / "study.db").string());
  const std::vector<study::CaseCostRow> rows = store.case_costs();
  ASSERT_EQ(rows.size(), 4U);
  double cpu = 0;
  for (const study::CaseCostRow& r : rows) {
    EXPECT_GT(r.cap_atom_steps, 0.0);
    EXPECT_GT(r.atom_steps, 0.0);  // the fake log's Loop line
    // The run's own CPU (wait4's rusage of run.sh and the fake): well under the 0.5 s its log claims.
    EXPECT_GT(r.cpu_seconds, 0.0);
    EXPECT_LT(r.cpu_seconds, 0.5);
    cpu += r.cpu_seconds;
  }
  const test::CommandResult status = test::run_demsa({"status", (tmp / "study").string(), "--json"});
  ASSERT_EQ(status.exit_code, 0) << status.out << status.err;
  const nlohmann::json s = nlohmann::json::parse(status.out).at("estimate");
  EXPECT_EQ(s.at("finished_cases").get<int>(), 4);
  EXPECT_NE(s.at("rate_source").get<std::string>().find("this study's 4 finished case"), std::string::npos);
  EXPECT_NEAR(s.at("cpu_seconds").get<double>(), cpu, 1e-9 * cpu);  // the study's own rate over its own cases
  const test::CommandResult status_text = test::run_demsa({"status", (tmp / "study").string()});
  EXPECT_NE(status_text.out.find("predicted against actual"), std::string::npos) << status_text.out;
  // The report: the totals and one row per done case.
  const test::CommandResult report = test::run_demsa({"report", (tmp / "study").string(), "--no-html"});
  ASSERT_EQ(report.exit_code, 0) << report.out << report.err;
  const std::string md = test::read_file(tmp / "study" / "report" / "report.md");
  EXPECT_NE(md.find("## What the cases cost"), std::string::npos) << md;
  EXPECT_NE(md.find("4 done cases: "), std::string::npos) << md;
  EXPECT_NE(md.find("| sample | cap atom-steps | predicted atom-steps"), std::string::npos) << md;
  ::unsetenv("DEMSA_RATE_CACHE");
  ::unsetenv("FAKE_LIGGGHTS_RATE");
}

/// A study of `samples` piles of 300 particles on the fake LIGGGHTS, one case at a time (the probe's tests).
void write_probe_study(const test::TempDir& tmp, int samples) {
  test::write_file(tmp / "study.toml", test::StudyToml{.name = "probe",
                                                       .samples = samples,
                                                       .tables = "[pile]\nparticles = 300\n",
                                                       .run = test::fake_liggghts_run_lines() + "parallel = 1\n"}
                                           .text());
}

// `--probe` runs the first case from a copy of its folder: its rate and its ratio to the cap price the rest, the first
// case's stored prediction uses them, and a probe that completes no LIGGGHTS run in its budget says so and hangs
// nothing.
TEST(CliCost, AProbeRunsTheFirstCaseAndPricesTheStudyByIt) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml",
                   test::StudyToml{.name = "probe",
                                   .samples = 3,
                                   .tables = "[pile]\nparticles = 300\n",
                                   .run = test::fake_liggghts_run_lines() + "parallel = 1\n",
                                   .analysis = "metamodels = [\"rsm2\"]\nbootstrap = 0\nbase_samples = 512\n"
                                               "second_order = false\n"}
                       .text());
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  test::ScopedEnv cache("DEMSA_RATE_CACHE", (tmp / "cache" / "rates.json").string());

  const test::CommandResult dry = test::run_demsa(test::run_args(tmp, {"--dry-run", "--json", "--probe", "60"}));
  ASSERT_EQ(dry.exit_code, 0) << dry.out << dry.err;
  const nlohmann::json e = nlohmann::json::parse(dry.out).at("estimate");
  const nlohmann::json& probe = e.at("probe");
  ASSERT_TRUE(probe.is_object()) << dry.out;
  EXPECT_EQ(probe.at("sample").get<int>(), 0);
  EXPECT_TRUE(probe.at("finished").get<bool>());
  // The fake's pile log: one `Loop time` line of 300 atoms; the probe's CPU is the run's rusage.
  const double atom_steps = probe.at("atom_steps").get<double>();
  const double rate = probe.at("atom_steps_per_cpu_second").get<double>();
  EXPECT_GT(atom_steps, 0.0);
  EXPECT_EQ(std::fmod(atom_steps, 300.0), 0.0);
  EXPECT_NEAR(rate, atom_steps / probe.at("cpu_seconds").get<double>(), 1e-9 * rate);
  EXPECT_NEAR(e.at("rate_atom_steps_per_cpu_second").get<double>(), rate, 1e-9 * rate);
  EXPECT_NEAR(e.at("early_ratio").get<double>(), atom_steps / probe.at("cap_atom_steps").get<double>(), 1e-12);
  EXPECT_TRUE(fs::exists(tmp / "study" / "cost_probe.json"));
  EXPECT_FALSE(fs::exists(tmp / "study" / ".cost-probe"));                        // the copy is gone
  EXPECT_FALSE(fs::exists(tmp / "study" / "cases" / "000000" / "log.liggghts"));  // the case itself never ran

  // A later dry run and the run itself read the stored probe.
  const test::CommandResult again = test::run_demsa(test::run_args(tmp, {"--dry-run"}));
  ASSERT_EQ(again.exit_code, 0) << again.out << again.err;
  EXPECT_NE(again.out.find("probe: sample 0 ran to its end"), std::string::npos) << again.out;
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet", "--no-analyze"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const std::vector<study::CaseCostRow> rows =
      study::Store::open_read_only((tmp / "study" / "study.db").string()).case_costs();
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.front().sample, 0);
  EXPECT_NEAR(rows.front().predicted_cpu_seconds, rows.front().predicted_atom_steps / rate,
              1e-9 * rows.front().predicted_cpu_seconds);

  // `--probe` goes with --dry-run only.
  const test::CommandResult refused = test::run_demsa(test::run_args(tmp, {"--probe", "5"}));
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.err.find("--probe goes with --dry-run"), std::string::npos) << refused.err;
}

TEST(CliCost, AProbeStoppedByItsBudgetCountsItsLoopsAsItsCpu) {
  // A run its budget killed leaves no share of a core to credit its loop times with (its killed parents never waited
  // for their children): its rate is its loops' atom-steps over their loop time, shown and not used.
  test::TempDir tmp;
  write_probe_study(tmp, 2);
  test::FakeLiggghtsEnvironment env("0:slow", tmp.path(), 0.0);  // 1000 steps of 300 atoms in 0.5 s, then never ends
  test::ScopedEnv cache("DEMSA_RATE_CACHE", (tmp / "cache" / "rates.json").string());
  const test::CommandResult dry = test::run_demsa(test::run_args(tmp, {"--dry-run", "--json", "--probe", "2"}));
  ASSERT_EQ(dry.exit_code, 0) << dry.out << dry.err;
  const nlohmann::json e = nlohmann::json::parse(dry.out).at("estimate");
  const nlohmann::json& probe = e.at("probe");
  EXPECT_FALSE(probe.at("finished").get<bool>());
  EXPECT_DOUBLE_EQ(probe.at("atom_steps").get<double>(), 300000.0);
  EXPECT_DOUBLE_EQ(probe.at("cpu_seconds").get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(probe.at("atom_steps_per_cpu_second").get<double>(), 600000.0);
  EXPECT_NE(e.at("rate_source").get<std::string>().find("standard run"), std::string::npos) << dry.out;
}

TEST(CliCost, AProbeThatCompletesNoRunInItsBudgetSaysSo) {
  test::TempDir tmp;
  write_probe_study(tmp, 2);
  test::FakeLiggghtsEnvironment env("0:hang", tmp.path(), 0.0);  // writes a log of 0 steps, then never ends
  test::ScopedEnv cache("DEMSA_RATE_CACHE", (tmp / "cache" / "rates.json").string());
  const test::CommandResult dry = test::run_demsa(test::run_args(tmp, {"--dry-run", "--probe", "2"}));
  EXPECT_NE(dry.exit_code, 0);
  EXPECT_NE(dry.err.find("the probe of sample 0 completed no LIGGGHTS run in 2 s: give --probe more seconds (its "
                         "folder is kept: " +
                         (tmp / "study" / ".cost-probe").string()),
            std::string::npos)
      << dry.err;
  EXPECT_TRUE(fs::exists(tmp / "study" / ".cost-probe" / "log.liggghts"));
  EXPECT_FALSE(fs::exists(tmp / "study" / "cost_probe.json"));
}

TEST(CliCost, AProbeWhoseCaseFailsSaysHowAndKeepsItsFolder) {
  test::TempDir tmp;
  write_probe_study(tmp, 2);
  test::FakeLiggghtsEnvironment env("0:error", tmp.path(), 0.0);
  test::ScopedEnv cache("DEMSA_RATE_CACHE", (tmp / "cache" / "rates.json").string());
  const test::CommandResult dry = test::run_demsa(test::run_args(tmp, {"--dry-run", "--probe", "60"}));
  EXPECT_EQ(dry.exit_code, 2);
  EXPECT_NE(dry.err.find("the probe of sample 0 failed: ./run.sh exited with"), std::string::npos) << dry.err;
  EXPECT_TRUE(fs::exists(tmp / "study" / ".cost-probe" / "log.liggghts"));
  EXPECT_FALSE(fs::exists(tmp / "study" / "cost_probe.json"));
}

TEST(CliCost, ACtrlCStopsTheProbeAtOnceAndStoresNothing) {
  // The probe runs its case in a process group of its own, which the terminal's Ctrl-C does not reach: demsa kills it.
  test::TempDir tmp;
  write_probe_study(tmp, 2);
  test::FakeLiggghtsEnvironment env("0:hang", tmp.path(), 0.0);
  test::ScopedEnv cache("DEMSA_RATE_CACHE", (tmp / "cache" / "rates.json").string());
  const pid_t pid = test::spawn_demsa(
      {"run", (tmp / "study.toml").string(), "--dir", (tmp / "study").string(), "--dry-run", "--probe", "600"},
      tmp / "log.txt");
  // Until the probe's copy of the case has started.
  for (int i = 0; i < 100 && !fs::exists(tmp / "study" / ".cost-probe" / "log.liggghts"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(fs::exists(tmp / "study" / ".cost-probe" / "log.liggghts")) << test::read_file(tmp / "log.txt");
  const auto sent = std::chrono::steady_clock::now();
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  const int status = test::wait_exit(pid);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  EXPECT_EQ(status, 128 + SIGINT) << test::read_file(tmp / "log.txt");
  EXPECT_LT(seconds, 3.0);
  EXPECT_FALSE(fs::exists(tmp / "study" / "cost_probe.json"));
  EXPECT_FALSE(fs::exists(tmp / "study" / ".cost-probe"));
}

TEST(CliCost, VersionShowsTheMeasuredSpeedOfTheLiggghtsItFinds) {
  test::TempDir tmp;
  const fs::path fake = fs::path(DEMSA_SOURCE_DIR) / "tests" / "integration" / "fake_liggghts" / "liggghts";
  const fs::path cache = tmp / "rates.json";
  // The fake's standard run reports 4e6 atom-steps per CPU-second (FAKE_LIGGGHTS_RATE's default).
  EXPECT_DOUBLE_EQ(exec::machine_rate(fake.string(), cache).atom_steps_per_cpu_second, 4e6);
  const test::CommandResult r = test::run_command(
      {"env", "DEMSA_LIGGGHTS=" + fake.string(), "DEMSA_RATE_CACHE=" + cache.string(), DEMSA_BINARY, "--version"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("speed: 4e+06 atom-steps per CPU-second (the standard run of " + fake.string()),
            std::string::npos)
      << r.out;
}

TEST(CliCost, VersionLeavesNoLiggghtsLogWhereItRuns) {
  // issue 45: LIGGGHTS opens log.liggghts before it reads -h, so `demsa --version` left one in the current folder.
  test::TempDir tmp;
  const fs::path fake = fs::path(DEMSA_SOURCE_DIR) / "tests" / "integration" / "fake_liggghts" / "liggghts";
  fs::create_directories(tmp / "here");
  const test::CommandResult r =
      test::run_command({"env", "-C", (tmp / "here").string(), "DEMSA_LIGGGHTS=" + fake.string(),
                         "DEMSA_RATE_CACHE=" + (tmp / "rates.json").string(), DEMSA_BINARY, "--version"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("3.8.0"), std::string::npos) << r.out;  // its help text was read
  EXPECT_TRUE(fs::is_empty(tmp / "here")) << fs::directory_iterator(tmp / "here")->path();
}

TEST(CliCost, ACachedRateOutsideAPlausibleWindowOrOfWrongTypesIsMeasuredAgain) {
  // issue 45: a cached rate of 1e-3 billed 1.2e8 CPU-hours, one of 1e30 billed 0 s, and a size written as a string
  // ended the dry run with exit 3 and nlohmann's type_error.
  test::TempDir tmp;
  const fs::path fake = fs::path(DEMSA_SOURCE_DIR) / "tests" / "integration" / "fake_liggghts" / "liggghts";
  const exec::BinaryKey key = exec::binary_key(fake.string());
  const fs::path cache = tmp / "rates.json";
  const auto entry = [&](const nlohmann::json& size, const nlohmann::json& mtime, const nlohmann::json& rate) {
    return nlohmann::json{
        {"rates", {{{"binary", key.path}, {"size", size}, {"mtime_ns", mtime}, {"atom_steps_per_cpu_second", rate}}}}};
  };
  for (const nlohmann::json& doc :
       {entry(key.size, key.mtime_ns, 1e-3), entry(key.size, key.mtime_ns, 1e30),
        entry(std::to_string(key.size), key.mtime_ns, 5e6), entry(key.size, key.mtime_ns, "5e6"),
        entry(key.size, 1.5, 5e6), entry(nullptr, key.mtime_ns, 5e6)}) {
    SCOPED_TRACE(doc.dump());
    test::write_file(cache, doc.dump());
    EXPECT_FALSE(exec::cached_rate(fake.string(), cache));
    EXPECT_DOUBLE_EQ(exec::machine_rate(fake.string(), cache).atom_steps_per_cpu_second, 4e6);  // measured again
    EXPECT_DOUBLE_EQ(exec::cached_rate(fake.string(), cache)->atom_steps_per_cpu_second, 4e6);
  }
  // A plausible one is used as it is.
  test::write_file(cache, entry(key.size, key.mtime_ns, 5e6).dump());
  EXPECT_DOUBLE_EQ(exec::cached_rate(fake.string(), cache)->atom_steps_per_cpu_second, 5e6);
  // A standard run that reports an implausible speed is an error, not a cached bill.
  fs::remove(cache);
  test::ScopedEnv slow("FAKE_LIGGGHTS_RATE", "1e-3");
  EXPECT_THROW(exec::machine_rate(fake.string(), cache), util::UserError);
  EXPECT_FALSE(fs::exists(cache));
}

TEST(CliCost, ASchedulesOfAMillionOneStepRunsIsRefused) {
  // issue 45: an interval near 0 (here the pile's settling check) made every step a LIGGGHTS run of its own, billed
  // as its steps alone.
  test::TempDir tmp;
  test::write_file(tmp / "study.toml",
                   test::StudyToml{.name = "runs",
                                   .samples = 2,
                                   .tables = "[pile]\nparticles = 300\nsettle_time = 2\nsettle_check_time = 1e-9\n",
                                   .run = test::fake_liggghts_run_lines()}
                       .text());
  test::ScopedEnv cache("DEMSA_RATE_CACHE", (tmp / "cache" / "rates.json").string());
  const test::CommandResult dry = test::run_demsa(test::run_args(tmp, {"--dry-run"}));
  EXPECT_EQ(dry.exit_code, 2) << dry.out << dry.err;
  EXPECT_NE(dry.err.find("[pile] settle_check_time gives"), std::string::npos) << dry.err;
  EXPECT_NE(dry.err.find("LIGGGHTS runs of 1 step in one case, more than 100000"), std::string::npos) << dry.err;
}

TEST(CliCost, AProbeBudgetBelowASecondIsRefusedNotUnlimited) {
  // issue 45: --probe 0.0005 rounded to a timeout of 0 ms, which is no timeout: the probe ran the whole case.
  test::TempDir tmp;
  write_probe_study(tmp, 2);
  test::FakeLiggghtsEnvironment env("0:hang", tmp.path(), 0.0);
  test::ScopedEnv cache("DEMSA_RATE_CACHE", (tmp / "cache" / "rates.json").string());
  for (const char* budget : {"0.0005"}) {
    const test::CommandResult dry = test::run_demsa(test::run_args(tmp, {"--dry-run", "--probe", budget}));
    EXPECT_EQ(dry.exit_code, 2) << dry.out << dry.err;
    EXPECT_NE(dry.err.find(fmt::format("--probe {}: give at least 1 s", budget)), std::string::npos) << dry.err;
    EXPECT_FALSE(fs::exists(tmp / "study" / "cost_probe.json"));
    // Refused before the dry run writes its design and cases (and before it announces a probe of "at most 0 s").
    EXPECT_FALSE(fs::exists(tmp / "study")) << dry.err;
    EXPECT_EQ(dry.err.find("probing:"), std::string::npos) << dry.err;
  }
}

}  // namespace
}  // namespace demsa
