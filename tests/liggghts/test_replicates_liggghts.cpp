// [design] replicates on real LIGGGHTS (Debian's, `liggghts` on PATH): a study of 3 tiny piles (300 particles of
// set 1, tests/data/cases/tiny_pile.toml's settings) with one replicate of its first point, run by `demsa run`. The
// replicate is the same point with another packing: other radii, another angle; the analysis measures the noise from
// the pair. About a minute on one core.
#include "orchestrator/study/store.hpp"

#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <string>

namespace demsa {
namespace {

namespace fs = std::filesystem;

TEST(ReplicatesLiggghts, TinyPileReplicateHasAnotherPackingAndTheNoiseIsMeasured) {
  test::TempDir tmp;
  test::write_file(tmp / "study.toml", R"(
[study]
name = "tiny-pile-replicates"
experiment = "pile"
seed = 2024

[design]
method = "lhs"
samples = 4
replicates = { points = 1, repeats = 2 }

[parameters]
E = { low = 1e8, high = 1e9, scale = "log" }
mu_r_pp = { low = 0.05, high = 0.5 }

[material]
nu = 0.3
mu_pp = 0.7
mu_pw = 0.7
e_r = 0.4
mu_r_pw = 0.3

[pile]
particles = 300
fill_height = 0.06
settle_time = 0.35

[run]
ranks = 1
parallel = 2
retries = 0

[analysis]
metamodels = ["rsm1"]
bootstrap = 0
base_samples = 512
second_order = false
)");
  const test::CommandResult run = test::run_demsa(test::run_args(tmp, {"--quiet"}));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("replicate cases (DEM noise): 1 of 1 done"), std::string::npos) << run.out;
  const fs::path design_case = tmp / "study" / "cases" / "000000";
  const fs::path replicate_case = tmp / "study" / "cases" / fmt::format("{:06d}", study::replicate_sample_id(0, 1));
  // Same contact parameters, another packing (whose smallest radius sets the time step: the rest of
  // params.liggghts follows the packing).
  const auto contact_block = [](const std::string& params) { return params.substr(0, params.find("# integration")); };
  EXPECT_EQ(contact_block(test::read_file(design_case / "params.liggghts")),
            contact_block(test::read_file(replicate_case / "params.liggghts")));
  EXPECT_NE(test::read_file(design_case / "pile_particles.data"),
            test::read_file(replicate_case / "pile_particles.data"));
  const study::Store store = study::Store::open_read_only((tmp / "study" / "study.db").string());
  const auto observables = store.observables();
  const double a = observables.at(0).at("angle");
  const double b = observables.at(study::replicate_sample_id(0, 1)).at("angle");
  EXPECT_GT(a, 10.0);
  EXPECT_LT(a, 45.0);
  EXPECT_GT(b, 10.0);
  EXPECT_LT(b, 45.0);
  EXPECT_NE(a, b) << "another packing gives another angle";
  const nlohmann::json analysis = nlohmann::json::parse(test::read_file(tmp / "study" / "analysis" / "analysis.json"));
  for (const nlohmann::json& o : analysis.at("observables")) {
    if (o.at("name") != "angle") continue;
    ASSERT_TRUE(o.contains("noise")) << o.dump();
    EXPECT_EQ(o.at("noise").at("dof").get<int>(), 1);
    EXPECT_NEAR(o.at("noise").at("variance").get<double>(), 0.5 * (a - b) * (a - b), 1e-9 * (1 + a * a));
  }
}

}  // namespace
}  // namespace demsa
