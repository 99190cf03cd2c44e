// [design] replicates end to end against the fake LIGGGHTS (tests/integration/fake_liggghts, its pile angle with
// FAKE_LIGGGHTS_NOISE: a normal draw seeded by the case's assembly seed): the replicate cases run through
// `demsa run`, show in `status`, survive SIGKILL at random moments, and the analysis measures the noise, sets the GP
// nugget from it and reports the noise share.
#include "orchestrator/study/store.hpp"

#include "support/process.hpp"
#include "support/test_support.hpp"

#include <signal.h>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

namespace demsa {

using namespace demsa::study;
namespace {

namespace fs = std::filesystem;

std::string study_text(int samples, int points, int repeats, const std::string& metamodels, int parallel) {
  std::string text = test::StudyToml{.name = "fake-noise",
                                     .experiment = "pile",
                                     .seed = 7,
                                     .samples = samples,
                                     .parameters =
                                         "mu_pp = { low = 0.2, high = 0.8 }\n"
                                         "mu_r_pp = { low = 0.05, high = 0.3 }\n",
                                     .tables = "[pile]\nparticles = 300\n",
                                     .run = test::fake_liggghts_run_lines() +
                                            fmt::format("parallel = {}\noversubscribe = true\nretries = 1\n", parallel),
                                     .analysis = "metamodels = " + metamodels +
                                                 "\nbootstrap = 0\nbase_samples = 512\nsecond_order = false\n"}
                         .text();
  const std::string design = "[design]\n";
  const std::size_t at = text.find(design);
  EXPECT_NE(at, std::string::npos) << text;
  text.insert(at + design.size(), fmt::format("replicates = {{ points = {}, repeats = {} }}\n", points, repeats));
  return text;
}

std::map<int, int> starts_per_sample(const fs::path& state) {
  std::map<int, int> starts;
  std::istringstream in(test::read_file(state / "starts.log"));
  int sample = 0;
  while (in >> sample) ++starts[sample];
  return starts;
}

const nlohmann::json& observable(const nlohmann::json& analysis, const std::string& name) {
  for (const nlohmann::json& o : analysis.at("observables"))
    if (o.at("name") == name) return o;
  throw std::runtime_error("no observable " + name);
}

/// Checks that each of the `design` samples and the points x (repeats - 1) replicate cases has exactly one done run,
/// its last, and was started at most once per run row; returns the starts per case.
std::map<int, int> expect_each_case_done_once(const Store& store, const fs::path& state, int design, int points,
                                              int repeats) {
  std::vector<int> cases;
  for (int k = 0; k < design; ++k) cases.push_back(k);
  for (int point = 0; point < points; ++point)
    for (int repeat = 1; repeat < repeats; ++repeat) cases.push_back(replicate_sample_id(point, repeat));
  std::map<int, std::vector<RunRow>> runs;
  for (const RunRow& r : store.runs()) runs[r.sample].push_back(r);
  EXPECT_EQ(runs.size(), cases.size());
  const std::map<int, int> starts = starts_per_sample(state);
  for (const int k : cases) {
    SCOPED_TRACE(fmt::format("case {}", k));
    const std::vector<RunRow>& rows = runs[k];
    EXPECT_FALSE(rows.empty());
    if (rows.empty()) continue;
    int done = 0;
    for (const RunRow& r : rows) done += r.state == RunState::done;
    EXPECT_EQ(done, 1);
    EXPECT_EQ(rows.back().state, RunState::done);
    const auto it = starts.find(k);
    EXPECT_LE(it == starts.end() ? 0 : it->second, static_cast<int>(rows.size()));
  }
  return starts;
}

TEST(RunReplicates, NoiseIsMeasuredSetsTheNuggetAndIsReported) {
  test::TempDir tmp;
  // 10 samples; 5 points x 4 repeats: 15 replicate cases, 15 degrees of freedom. Noise sd 1.5 degrees.
  test::write_file(tmp / "study.toml", study_text(10, 5, 4, "[\"rsm2\", \"gp\"]", 2));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::ScopedEnv noise("FAKE_LIGGGHTS_NOISE", "1.5");
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("10 of 10 samples done"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("replicate cases (DEM noise): 15 of 15 done"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("share of the variance over the design"), std::string::npos) << run.out;

  // Every case ran once: 10 design samples and 15 replicates with their own ids.
  const std::map<int, int> starts = starts_per_sample(tmp.path());
  EXPECT_EQ(starts.size(), 25u);
  for (const auto& [sample, n] : starts) EXPECT_EQ(n, 1) << sample;
  EXPECT_EQ(starts.count(replicate_sample_id(4, 3)), 1u);
  EXPECT_EQ(starts.count(replicate_sample_id(5, 1)), 0u);

  // A replicate case is its point with another packing: same parameters, another assembly seed and other radii.
  const fs::path design_case = tmp / "study" / "cases" / fmt::format("{:06d}", 2);
  const fs::path replicate_case = tmp / "study" / "cases" / fmt::format("{:06d}", replicate_sample_id(2, 1));
  const nlohmann::json a = nlohmann::json::parse(test::read_file(design_case / "case.json"));
  const nlohmann::json b = nlohmann::json::parse(test::read_file(replicate_case / "case.json"));
  EXPECT_EQ(a.at("parameters"), b.at("parameters"));
  EXPECT_EQ(a.at("unit_point"), b.at("unit_point"));
  EXPECT_FALSE(a.contains("replicate"));
  EXPECT_EQ(b.at("replicate").at("point").get<int>(), 2);
  EXPECT_EQ(b.at("replicate").at("repeat").get<int>(), 1);
  // `demsa case --sample` takes a replicate's id (as `demsa status` prints it) and writes that case again, with its
  // assembly seed; before the study has a folder, the ids come from the study file's design and replicates.
  const int id = replicate_sample_id(2, 1);
  const test::CommandResult written = test::run_demsa(
      {"case", (tmp / "study.toml").string(), "--sample", std::to_string(id), "-o", (tmp / "again").string()});
  ASSERT_EQ(written.exit_code, 0) << written.out << written.err;
  const nlohmann::json c = nlohmann::json::parse(test::read_file(tmp / "again" / "case.json"));
  EXPECT_EQ(c.at("sample"), id);
  EXPECT_EQ(c.at("replicate"), b.at("replicate"));
  EXPECT_EQ(c.at("parameters"), b.at("parameters"));
  EXPECT_EQ(c.at("assembly"), b.at("assembly"));
  const test::CommandResult fresh =
      test::run_demsa({"case", (tmp / "study.toml").string(), "--sample", std::to_string(id), "--dir",
                       (tmp / "none").string(), "-o", (tmp / "fresh").string()});
  ASSERT_EQ(fresh.exit_code, 0) << fresh.out << fresh.err;
  EXPECT_EQ(nlohmann::json::parse(test::read_file(tmp / "fresh" / "case.json")).at("replicate"), b.at("replicate"));
  const test::CommandResult unknown =
      test::run_demsa({"case", (tmp / "study.toml").string(), "--sample", "1000005", "-o", (tmp / "unknown").string()});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("design samples 0-9; replicate cases 1000001-1000003, 1001001-1001003"), std::string::npos)
      << unknown.err;
  EXPECT_NE(b.at("replicate").at("assembly_seed").get<std::uint64_t>(), a.at("seed").get<std::uint64_t>());
  EXPECT_NE(a.at("assembly"), b.at("assembly"));  // other radii: other extremes and volume

  // status: the replicates apart from the design's samples.
  const test::CommandResult status = test::run_demsa({"status", (tmp / "study").string(), "--json"});
  ASSERT_EQ(status.exit_code, 0) << status.err;
  const nlohmann::json st = nlohmann::json::parse(status.out);
  EXPECT_EQ(st.at("samples").get<int>(), 10);
  EXPECT_EQ(st.at("done").get<int>(), 10);
  EXPECT_EQ(st.at("replicates").at("cases").get<int>(), 15);
  EXPECT_EQ(st.at("replicates").at("done").get<int>(), 15);
  const test::CommandResult status_text = test::run_demsa({"status", (tmp / "study").string()});
  EXPECT_NE(status_text.out.find("replicate cases 15 (DEM noise): done 15"), std::string::npos) << status_text.out;

  // The analysis: trained on the 10 design samples only; the noise from the 5 points (20 cases, 15 dof).
  const nlohmann::json analysis = nlohmann::json::parse(test::read_file(tmp / "study" / "analysis" / "analysis.json"));
  EXPECT_EQ(analysis.at("samples_used").size(), 10u);
  const nlohmann::json& angle = observable(analysis, "angle");
  ASSERT_TRUE(angle.contains("noise")) << angle.dump();
  const nlohmann::json& n = angle.at("noise");
  EXPECT_EQ(n.at("points").get<int>(), 5);
  EXPECT_EQ(n.at("values").get<int>(), 20);
  EXPECT_EQ(n.at("dof").get<int>(), 15);
  // The true noise variance is 2.25 (plus the angle estimator's own scatter); 15 dof put the estimate within
  // [0.41, 1.83] x 2.25 at 99 %.
  const double variance = n.at("variance").get<double>();
  EXPECT_GT(variance, 0.41 * 2.25) << n.dump();
  EXPECT_LT(variance, 1.83 * 2.25 + 0.5) << n.dump();
  EXPECT_LT(n.at("lower").get<double>(), variance);
  EXPECT_GT(n.at("upper").get<double>(), variance);
  const double sd = angle.at("sd").get<double>();
  EXPECT_NEAR(n.at("share").get<double>(), variance / (sd * sd), 1e-12);
  // The GP's nugget comes from the measured noise: σ² τ = the noise variance (the GP's σ² is in the output's units).
  const nlohmann::json* gp = nullptr;
  for (const nlohmann::json& m : angle.at("models"))
    if (m.at("model") == "gp") gp = &m;
  ASSERT_NE(gp, nullptr);
  ASSERT_TRUE(gp->at("ok").get<bool>()) << gp->dump();
  const nlohmann::json& parameters = gp->at("quality").at("parameters");
  EXPECT_NEAR(parameters.at("process_variance").get<double>() * parameters.at("nugget").get<double>(), variance,
              0.01 * variance)
      << parameters.dump();
  // The replicates beside their design case.
  const std::string csv = test::read_file(tmp / "study" / "analysis" / "replicates.csv");
  EXPECT_EQ(csv.rfind("point,repeat,sample,assembly_seed,angle", 0), 0u) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 21);

  // `demsa sensitivity --repeats` measures the same noise from the same files.
  const test::CommandResult sens = test::run_demsa(
      {"sensitivity", "--data", (tmp / "study" / "analysis" / "observables.csv").string(), "--inputs", "mu_pp,mu_r_pp",
       "--response", "angle", "--repeats", (tmp / "study" / "analysis" / "replicates.csv").string(), "--metamodels",
       "gp", "--bootstrap", "0", "--base", "512", "--json", (tmp / "sensitivity.json").string()});
  ASSERT_EQ(sens.exit_code, 0) << sens.out << sens.err;
  EXPECT_EQ(sens.err.find("deprecated"), std::string::npos) << sens.err;
  // The old spelling, --replicates, still works, with a warning naming the new one.
  const test::CommandResult old = test::run_demsa(
      {"sensitivity", "--data", (tmp / "study" / "analysis" / "observables.csv").string(), "--inputs", "mu_pp,mu_r_pp",
       "--response", "angle", "--replicates", (tmp / "study" / "analysis" / "replicates.csv").string(), "--metamodels",
       "gp", "--bootstrap", "0", "--base", "512", "--json", "-"});
  ASSERT_EQ(old.exit_code, 0) << old.out << old.err;
  EXPECT_NE(old.err.find("--replicates is deprecated and will be removed in the next version: use --repeats"),
            std::string::npos)
      << old.err;
  EXPECT_EQ(nlohmann::json::parse(old.out).at("outputs").at(0).at("noise").at("dof").get<int>(), 15);
  EXPECT_NE(sens.out.find("share of the variance over the design"), std::string::npos) << sens.out;
  const nlohmann::json sj = nlohmann::json::parse(test::read_file(tmp / "sensitivity.json"));
  EXPECT_NEAR(sj.at("outputs").at(0).at("noise").at("variance").get<double>(), variance, 1e-9 * variance);
  EXPECT_EQ(sj.at("outputs").at(0).at("noise").at("dof").get<int>(), 15);

  // The report shows the noise share beside the indices.
  const test::CommandResult report = test::run_demsa({"report", (tmp / "study").string()});
  ASSERT_EQ(report.exit_code, 0) << report.out << report.err;
  const std::string md = test::read_file(tmp / "study" / "report" / "report.md");
  EXPECT_NE(md.find("DEM noise"), std::string::npos) << md;
}

TEST(RunReplicates, NoiseThatDominatesIsFlagged) {
  test::TempDir tmp;
  // Noise sd 10 degrees against a design spread of about 4 degrees (sd); every one of the 6 samples replicated.
  test::write_file(tmp / "study.toml", study_text(6, 6, 4, "[\"rsm1\"]", 2));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::ScopedEnv noise("FAKE_LIGGGHTS_NOISE", "10");
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("NOISE DOMINATES"), std::string::npos) << run.out;
  EXPECT_NE(run.err.find("the noise dominates"), std::string::npos) << run.err;
  const nlohmann::json analysis = nlohmann::json::parse(test::read_file(tmp / "study" / "analysis" / "analysis.json"));
  const nlohmann::json& n = observable(analysis, "angle").at("noise");
  EXPECT_TRUE(n.at("dominates").get<bool>()) << n.dump();
  EXPECT_GT(n.at("share").get<double>(), 0.5) << n.dump();
  EXPECT_EQ(n.at("dof").get<int>(), 18);
}

TEST(RunReplicates, ResumeAfterSigkillAtRandomMomentsDoesEachCaseExactlyOnce) {
  test::TempDir tmp;
  // 6 samples and 3 points x 3 repeats: 12 cases (rsm1: rsm2's 6 terms on 6 samples leave its Q² not computable).
  test::write_file(tmp / "study.toml", study_text(6, 3, 3, "[\"rsm1\"]", 2));
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.4);
  const test::ScopedEnv noise("FAKE_LIGGGHTS_NOISE", "1");
  const std::vector<std::string> args = test::run_args(tmp, {"--no-analyze", "--quiet"});
  test::kill_at_random_moments(args, tmp / "demsa.log", 1811, 7, 100, 1100);
  const test::CommandResult final_run = test::run_demsa(args);
  ASSERT_EQ(final_run.exit_code, 0) << final_run.out << final_run.err << test::read_file(tmp / "demsa.log");
  const Store store = Store::open_read_only((tmp / "study" / "study.db").string());
  EXPECT_EQ(store.integrity_check(), "ok");
  EXPECT_EQ(store.replicates().size(), 6u);
  EXPECT_EQ(store.samples().size(), 6u);
  expect_each_case_done_once(store, tmp.path(), 6, 3, 3);
  std::map<int, long> last_run;
  for (const RunRow& r : store.runs()) last_run[r.sample] = r.id;
  for (const auto& [k, run] : last_run) {
    SCOPED_TRACE(fmt::format("case {}", k));
    const nlohmann::json result =
        nlohmann::json::parse(test::read_file(tmp / "study" / "cases" / fmt::format("{:06d}", k) / "result.json"));
    EXPECT_EQ(result.at("run").get<long>(), run);
    EXPECT_TRUE(store.observables().at(k).count("angle"));
  }
  EXPECT_EQ(last_run.size(), 12u);
  const StoreCounts c = store.counts();
  EXPECT_EQ(c.done, 6);
  EXPECT_EQ(c.replicates_done, 6);
  // A further run starts nothing; the analysis measures the noise from the 3 points.
  const std::size_t starts_before = test::read_file(tmp / "starts.log").size();
  const test::CommandResult again = test::run_demsa(test::run_args(tmp, {"--quiet"}));
  EXPECT_EQ(again.exit_code, 0) << again.out << again.err;
  EXPECT_EQ(test::read_file(tmp / "starts.log").size(), starts_before);
  EXPECT_NE(again.out.find("from 3 points, 9 cases, 6 degrees of freedom"), std::string::npos) << again.out;
}

TEST(RunReplicates, RaisedReplicatesAddCasesAndKeepTheDoneOnes) {
  test::TempDir tmp;
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.0);
  const test::ScopedEnv noise("FAKE_LIGGGHTS_NOISE", "1");
  const std::vector<std::string> args = test::run_args(tmp, {"--quiet"});
  // 6 samples, 2 points x 2 repeats: 8 cases.
  test::write_file(tmp / "study.toml", study_text(6, 2, 2, "[\"rsm1\"]", 2));
  const test::CommandResult first = test::run_demsa(args);
  ASSERT_EQ(first.exit_code, 0) << first.out << first.err;
  EXPECT_EQ(starts_per_sample(tmp.path()).size(), 8u);

  // Raised to 3 points x 3 repeats: the 2 replicate cases done stay, 4 more run (the repeats 2 of points 0 and 1,
  // both of point 2), and the noise is measured from the 3 points.
  test::write_file(tmp / "study.toml", study_text(6, 3, 3, "[\"rsm1\"]", 2));
  const test::CommandResult grown = test::run_demsa(args);
  ASSERT_EQ(grown.exit_code, 0) << grown.out << grown.err;
  EXPECT_NE(grown.out.find("from 3 points, 9 cases, 6 degrees of freedom"), std::string::npos) << grown.out;
  std::map<int, int> starts = starts_per_sample(tmp.path());
  EXPECT_EQ(starts.size(), 12u);
  for (const auto& [sample, n] : starts) EXPECT_EQ(n, 1) << sample;
  EXPECT_EQ(starts.count(replicate_sample_id(2, 2)), 1u);
  {
    const Store store = Store::open_read_only((tmp / "study" / "study.db").string());
    EXPECT_EQ(store.replicates().size(), 6u);
    EXPECT_EQ(store.design_samples(), 6);
    bool event = false;
    for (const EventRow& e : store.events())
      event = event || e.message == "replicates grown from 2 points x 2 repeats to 3 x 3";
    EXPECT_TRUE(event);
  }

  // Fewer points, fewer repeats or none at all are refused, and nothing runs.
  const std::size_t starts_before = test::read_file(tmp / "starts.log").size();
  for (const auto& [points, repeats] : {std::pair{2, 3}, std::pair{3, 2}}) {
    test::write_file(tmp / "study.toml", study_text(6, points, repeats, "[\"rsm1\"]", 2));
    const test::CommandResult shrunk = test::run_demsa(args);
    EXPECT_EQ(shrunk.exit_code, 2) << shrunk.out;
    EXPECT_NE(shrunk.err.find("replicates can grow, not shrink"), std::string::npos) << shrunk.err;
    EXPECT_NE(shrunk.err.find("has replicates = { points = 3, repeats = 3 } already"), std::string::npos) << shrunk.err;
  }
  std::string none = study_text(6, 3, 3, "[\"rsm1\"]", 2);
  none.erase(none.find("replicates = "), std::string("replicates = { points = 3, repeats = 3 }\n").size());
  test::write_file(tmp / "study.toml", none);
  const test::CommandResult dropped = test::run_demsa(args);
  EXPECT_EQ(dropped.exit_code, 2) << dropped.out;
  EXPECT_NE(dropped.err.find("[design] replicates = none, but"), std::string::npos) << dropped.err;
  EXPECT_EQ(test::read_file(tmp / "starts.log").size(), starts_before);

  // Samples and replicates raised together: 2 design samples and point 3's 2 replicate cases more.
  test::write_file(tmp / "study.toml", study_text(8, 4, 3, "[\"rsm1\"]", 2));
  const test::CommandResult both = test::run_demsa(args);
  ASSERT_EQ(both.exit_code, 0) << both.out << both.err;
  EXPECT_NE(both.out.find("8 of 8 samples done"), std::string::npos) << both.out;
  EXPECT_NE(both.out.find("replicate cases (DEM noise): 8 of 8 done"), std::string::npos) << both.out;
  starts = starts_per_sample(tmp.path());
  EXPECT_EQ(starts.size(), 16u);
  for (const auto& [sample, n] : starts) EXPECT_EQ(n, 1) << sample;
  EXPECT_EQ(starts.count(7), 1u);
  EXPECT_EQ(starts.count(replicate_sample_id(3, 2)), 1u);
}

TEST(RunReplicates, GrowthSurvivesSigkillAtRandomMoments) {
  test::TempDir tmp;
  test::FakeLiggghtsEnvironment env("", tmp.path(), 0.4);
  const test::ScopedEnv noise("FAKE_LIGGGHTS_NOISE", "1");
  const std::vector<std::string> args = test::run_args(tmp, {"--no-analyze", "--quiet"});
  test::write_file(tmp / "study.toml", study_text(6, 2, 2, "[\"rsm1\"]", 2));
  ASSERT_EQ(test::run_demsa(args).exit_code, 0);
  // Samples and replicates raised together (2 design samples and 8 replicate cases more), killed at random moments.
  test::write_file(tmp / "study.toml", study_text(8, 4, 3, "[\"rsm1\"]", 2));
  test::kill_at_random_moments(args, tmp / "demsa.log", 2027, 6, 100, 900);
  const test::CommandResult final_run = test::run_demsa(args);
  ASSERT_EQ(final_run.exit_code, 0) << final_run.out << final_run.err << test::read_file(tmp / "demsa.log");
  const Store store = Store::open_read_only((tmp / "study" / "study.db").string());
  EXPECT_EQ(store.integrity_check(), "ok");
  EXPECT_EQ(store.design_samples(), 8);
  EXPECT_EQ(store.replicates().size(), 8u);
  const std::map<int, int> starts = expect_each_case_done_once(store, tmp.path(), 8, 4, 3);
  // The cases done before the growth ran once.
  for (const int k : {0, 5, replicate_sample_id(0, 1), replicate_sample_id(1, 1)}) EXPECT_EQ(starts.at(k), 1) << k;
  const StoreCounts c = store.counts();
  EXPECT_EQ(c.done, 8);
  EXPECT_EQ(c.replicates_done, 8);
}

}  // namespace
}  // namespace demsa
