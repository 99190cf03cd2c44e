// [design] replicates (DEM noise): the setting, its errors, the design hash, and the replicate case rows of the
// store (apart from the design's samples, with ids that do not depend on the design's size).
#include "orchestrator/analysis/analysis_json.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/errors.hpp"

#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <string>

namespace demsa {

using namespace demsa::study;
using namespace demsa::experiments;
namespace {

const char* k_study = R"(
[study]
name = "s"
experiment = "pile"

[parameters]
mu_pp = { low = 0.2, high = 0.8 }
e_r = { low = 0.3, high = 0.7 }

[design]
samples = 6
)";

std::string error_of(const std::string& text) {
  return test::message_of<util::UserError>([&] { parse_study(text, "study.toml"); });
}

TEST(Replicates, SettingIsReadAndOffByDefault) {
  EXPECT_FALSE(parse_study(k_study, "study.toml").replicates.enabled());
  const StudyConfig c = parse_study(std::string(k_study) + "replicates = { points = 4, repeats = 3 }\n", "study.toml");
  EXPECT_EQ(c.replicates.points, 4);
  EXPECT_EQ(c.replicates.repeats, 3);
  EXPECT_EQ(c.replicates.extra_cases(), 8);
}

TEST(Replicates, BadValuesNameLineAndRule) {
  const std::string base(k_study);
  EXPECT_EQ(error_of(base + "replicates = { points = 7, repeats = 3 }\n"),
            "study.toml:12: [design] replicates: points = 7 exceeds [design] samples = 6: the replicates are taken at "
            "the first P design points");
  EXPECT_NE(error_of(base + "replicates = { points = 2, repeats = 1 }\n")
                .find("study.toml:12: [design.replicates] "
                      "repeats: must be in [2, 1000], got 1"),
            std::string::npos);
  EXPECT_NE(error_of(base + "replicates = { points = 0, repeats = 3 }\n").find("points: must be in [1, "),
            std::string::npos);
  EXPECT_NE(error_of(base + "replicates = { points = 2 }\n").find("needs both 'points' and 'repeats'"),
            std::string::npos);
  EXPECT_NE(error_of(base + "replicates = { points = 2, repeats = 3, seed = 4 }\n").find("unknown key 'seed'"),
            std::string::npos);
  EXPECT_NE(error_of(base + "replicates = { points = 2.5, repeats = 3 }\n").find("expected an integer"),
            std::string::npos);
}

TEST(Replicates, HashIsUnchangedWithoutThemAndChangesWithThem) {
  const StudyConfig plain = parse_study(k_study, "study.toml");
  const StudyConfig with = parse_study(std::string(k_study) + "replicates = { points = 2, repeats = 3 }\n", "s.toml");
  const StudyConfig more = parse_study(std::string(k_study) + "replicates = { points = 2, repeats = 4 }\n", "s.toml");
  EXPECT_EQ(settings_table().hash_text(plain).find("replicates"), std::string::npos);
  EXPECT_NE(design_hash(plain), design_hash(with));
  EXPECT_NE(design_hash(with), design_hash(more));
}

TEST(Replicates, SeedsDifferFromTheStudySeedAndFromEachOther) {
  std::set<std::uint64_t> seeds;
  for (int point = 0; point < 20; ++point)
    for (int repeat = 1; repeat < 10; ++repeat) {
      const std::uint64_t seed = cases::replicate_assembly_seed(12345, point, repeat);
      EXPECT_NE(seed, 12345u);
      EXPECT_EQ(seed, cases::replicate_assembly_seed(12345, point, repeat));
      seeds.insert(seed & 0xffffffffULL);  // GSL's MT19937 keeps the low 32 bits
    }
  EXPECT_EQ(seeds.size(), 180u);
}

TEST(Replicates, RowsKeepTheirIdsWhenTheDesignGrows) {
  StudyConfig c = parse_study(std::string(k_study) + "replicates = { points = 2, repeats = 3 }\n", "study.toml");
  const std::vector<ReplicateRow> small = exec::replicate_rows(c, exec::draw_design(c));
  c.samples = 9;
  const std::vector<SampleRow> grown_design = exec::draw_design(c);
  ASSERT_EQ(small.size(), 4u);
  EXPECT_EQ(small[0].sample, replicate_sample_id(0, 1));
  EXPECT_EQ(small[3].sample, k_replicate_sample_base + 1 * k_max_replicate_repeats + 2);
  EXPECT_EQ(small[3].point, 1);
  EXPECT_EQ(small[3].repeat, 2);
  // The ids and seeds depend on the point and repeat only, never on the design's size.
  const std::vector<ReplicateRow> grown = exec::replicate_rows(c, grown_design);
  for (std::size_t i = 0; i < small.size(); ++i) {
    EXPECT_EQ(grown[i].sample, small[i].sample);
    EXPECT_EQ(grown[i].seed, small[i].seed);
  }
  c.replicates.points = 10;
  EXPECT_THROW(exec::replicate_rows(c, grown_design), util::UserError);
}

TEST(Replicates, StoreKeepsThemApartFromTheDesign) {
  test::TempDir tmp;
  Store store((tmp / "study.db").string());
  const std::vector<SampleRow> design{{0, {0.1, 0.2}, {1.0, 2.0}}, {1, {0.3, 0.4}, {3.0, 4.0}}};
  store.initialize("h", "s", design);
  ReplicateRow r;
  r.sample = replicate_sample_id(1, 1);
  r.point = 1;
  r.repeat = 1;
  r.seed = 0x7fffffffffffff01ULL;  // above 2^62: stored as text, read back whole
  r.unit = design[1].unit;
  r.physical = design[1].physical;
  store.add_replicates({r});
  store.add_replicates({r});  // again (a resumed run): nothing changes
  EXPECT_EQ(store.samples().size(), 2u);
  const std::vector<ReplicateRow> back = store.replicates();
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].sample, r.sample);
  EXPECT_EQ(back[0].point, 1);
  EXPECT_EQ(back[0].seed, r.seed);
  EXPECT_EQ(back[0].physical, design[1].physical);
  // A replicate runs and is done like any case; the counts keep it apart.
  const long run = store.add_run(r.sample, 1);
  RunOutcome ok;
  ok.exit_code = 0;
  store.record_done(run, ok, {{"angle", 31.0}});
  const StoreCounts c = store.counts();
  EXPECT_EQ(c.samples, 2);
  EXPECT_EQ(c.done, 0);
  EXPECT_EQ(c.pending, 2);
  EXPECT_EQ(c.replicates, 1);
  EXPECT_EQ(c.replicates_done, 1);
  EXPECT_EQ(store.observables().at(r.sample).at("angle"), 31.0);
  EXPECT_EQ(Store::open_read_only((tmp / "study.db").string()).replicates().size(), 1u);
}

TEST(Replicates, NoiseDominatesAboveHalfOrAboveTheLargestS1) {
  EXPECT_TRUE(analysis::noise_dominates(0.51, 0.9));
  EXPECT_TRUE(analysis::noise_dominates(0.3, 0.25));
  EXPECT_FALSE(analysis::noise_dominates(0.3, 0.6));
  EXPECT_FALSE(analysis::noise_dominates(0.5, 0.5));
  EXPECT_FALSE(analysis::noise_dominates(0.3, std::nan("")));  // no metamodel: only the 0.5 rule
  EXPECT_TRUE(analysis::noise_dominates(0.6, std::nan("")));
}

TEST(Replicates, MeasuredNoisePoolsEachPointWithItsDesignCase) {
  // Point 0: design case 10, replicates 12 and 14 (SS 8); point 1: design case 20, its replicate failed (no value):
  // one value, no variance. Design variance 4: share = (8 / 2) / 4.
  std::vector<ReplicateRow> replicates;
  for (const auto& [point, repeat] : {std::pair{0, 1}, {0, 2}, {1, 1}}) {
    ReplicateRow r;
    r.sample = replicate_sample_id(point, repeat);
    r.point = point;
    r.repeat = repeat;
    replicates.push_back(r);
  }
  const std::map<int, std::map<std::string, double>> observables{{0, {{"angle", 10.0}}},
                                                                 {1, {{"angle", 20.0}}},
                                                                 {replicate_sample_id(0, 1), {{"angle", 12.0}}},
                                                                 {replicate_sample_id(0, 2), {{"angle", 14.0}}}};
  const std::optional<analysis::NoiseAnalysis> noise =
      analysis::measured_noise(replicates, observables, "angle", 0.95, 2.0);
  ASSERT_TRUE(noise);
  EXPECT_DOUBLE_EQ(noise->estimate.variance, 4.0);
  EXPECT_EQ(noise->estimate.points, 1);
  EXPECT_EQ(noise->estimate.values, 3);
  EXPECT_EQ(noise->estimate.dof, 2);
  EXPECT_DOUBLE_EQ(noise->share, 1.0);
  EXPECT_FALSE(analysis::measured_noise(replicates, observables, "pile_height", 0.95, 2.0));
  EXPECT_FALSE(analysis::measured_noise({}, observables, "angle", 0.95, 2.0));
}

}  // namespace
}  // namespace demsa
