// The store's side of a growing study: design samples counted apart from refinement samples, samples appended in
// one transaction with the hash of an extension, and the refine history keyed by its number of done samples.
#include "orchestrator/study/store.hpp"

#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace demsa {

using namespace demsa::study;
namespace {

std::vector<SampleRow> rows(int first, int count) {
  std::vector<SampleRow> r;
  for (int i = first; i < first + count; ++i) r.push_back({i, {0.01 * i, 0.5}, {1.0 * i, 2.0}});
  return r;
}

TEST(StoreGrowth, DesignAndRefinementSamplesAreCountedApart) {
  test::TempDir tmp;
  Store store((tmp / "study.db").string());
  store.initialize("hash-4", "growth", rows(0, 4));
  EXPECT_EQ(store.design_samples(), 4);  // no count stored yet: every sample is the design's
  store.add_samples(rows(4, 2), "refined", "two refinement points");
  EXPECT_EQ(store.design_samples(), 4);
  EXPECT_EQ(*store.design_hash(), "hash-4");
  store.add_samples(rows(6, 3), "extended", "three design points", std::string("hash-7"));
  EXPECT_EQ(store.design_samples(), 7);
  EXPECT_EQ(*store.design_hash(), "hash-7");
  ASSERT_EQ(store.samples().size(), 9u);
  EXPECT_EQ(store.samples().back().unit, rows(8, 1).front().unit);
  int extended = 0;
  for (const EventRow& e : store.events()) extended += e.kind == "extended";
  EXPECT_EQ(extended, 1);
}

TEST(StoreGrowth, ReplicateCasesNeitherCountAsDesignNorShiftTheNextIndex) {
  test::TempDir tmp;
  Store store((tmp / "study.db").string());
  store.initialize("hash-3", "growth", rows(0, 3));
  ReplicateRow r;
  r.sample = replicate_sample_id(1, 1);  // far above the design's indices
  r.point = 1;
  r.repeat = 1;
  r.seed = 99;
  r.unit = rows(1, 1).front().unit;
  r.physical = rows(1, 1).front().physical;
  store.add_replicates({r});
  EXPECT_EQ(store.design_samples(), 3);  // no count stored yet: the design's samples, not the replicate
  store.add_samples(rows(3, 2), "extended", "two design points", std::string("hash-5"));
  EXPECT_EQ(store.design_samples(), 5);
  ASSERT_EQ(store.samples().size(), 5u);
  EXPECT_EQ(store.samples().back().sample, 4);
  EXPECT_EQ(store.replicates().size(), 1u);
}

TEST(StoreGrowth, SamplesThatDoNotContinueTheStoreAreRefusedWhole) {
  test::TempDir tmp;
  Store store((tmp / "study.db").string());
  store.initialize("h", "growth", rows(0, 3));
  std::vector<SampleRow> bad = rows(3, 2);
  bad[1].sample = 7;
  EXPECT_THROW(store.add_samples(bad, "refined", "gap"), std::logic_error);
  EXPECT_EQ(store.samples().size(), 3u);  // the first of the two was rolled back with the transaction
}

TEST(StoreGrowth, RefineHistoryIsKeyedBySamplesAndReadsBackNaN) {
  test::TempDir tmp;
  {
    Store store((tmp / "study.db").string());
    store.initialize("h", "growth", rows(0, 3));
    EXPECT_TRUE(store.refine_history().empty());
    RefineStep step;
    step.iteration = 1;
    step.samples = 3;
    step.target = 0.05;
    step.decision = "added 2";
    step.max_half_width = {{"angle", 0.2}, {"pile_height", std::nan("")}};
    step.indices_json = "{}";
    store.record_refine_step(step);
    step.decision = "added 4";  // the same step again (a restarted refine): replaced, not added
    store.record_refine_step(step);
    step.iteration = 2;
    step.samples = 7;
    step.decision = "reached";
    step.max_half_width = {{"angle", 0.04}, {"pile_height", 0.03}};
    store.record_refine_step(step);
  }
  const Store store = Store::open_read_only((tmp / "study.db").string());
  const std::vector<RefineStep> history = store.refine_history();
  ASSERT_EQ(history.size(), 2u);
  EXPECT_EQ(history[0].decision, "added 4");
  EXPECT_DOUBLE_EQ(history[0].max_half_width.at("angle"), 0.2);
  EXPECT_TRUE(std::isnan(history[0].max_half_width.at("pile_height")));
  EXPECT_EQ(history[1].samples, 7);
  EXPECT_EQ(history[1].decision, "reached");
}

}  // namespace
}  // namespace demsa
