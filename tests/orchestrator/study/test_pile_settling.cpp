// The pile's settling and removal settings ([pile] settle_speed, settle_quantile, settle_window, remove_fallen), the
// retired ke_stop, and the unsettled samples read back from the stored observables.
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/observables.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <string>

namespace demsa {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::experiments;
namespace {

const char* k_minimal = R"(
[study]
name = "s"
experiment = "pile"

[parameters]
E = { low = 1e8, high = 1e9, scale = "log" }
)";

std::string error_of(const std::string& text) {
  return test::message_of<UserError>([&] { parse_study(text, "study.toml"); });
}

}  // namespace

TEST(PileSettling, SettingsAreReadAndTheDefaultIsThePapersSchedule) {
  // Default: no criterion, nothing removed: settle for settle_time (paper §3.2), as before the criterion existed.
  const StudyConfig d = parse_study(k_minimal, "study.toml");
  EXPECT_EQ(pile::settings(d).settle_speed, 0.0);
  EXPECT_FALSE(pile::settings(d).remove_fallen);
  const StudyConfig c = parse_study(std::string(k_minimal) +
                                        "[pile]\nsettle_speed = 0.02\nsettle_quantile = 1\nsettle_window = 0.1\n"
                                        "remove_fallen = true\n",
                                    "study.toml");
  EXPECT_EQ(pile::settings(c).settle_speed, 0.02);
  EXPECT_EQ(pile::settings(c).settle_quantile, 1.0);
  EXPECT_EQ(pile::settings(c).settle_window, 0.1);
  EXPECT_TRUE(pile::settings(c).remove_fallen);
}

TEST(PileSettling, DefaultsKeepTheHashOfTheVersionWithKeStopAndEachSettingChangesIt) {
  // The version with `ke_stop` hashed `pile.ke_stop=0` between settle_time and settle_check_time.
  const StudyConfig d = parse_study(k_minimal, "study.toml");
  const std::string text = settings_table().hash_text(d);
  EXPECT_NE(text.find("pile.settle_time=0.59999999999999998\npile.ke_stop=0\npile.settle_check_time="),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("settle_speed"), std::string::npos) << text;
  for (const char* line :
       {"settle_speed = 0.02", "settle_quantile = 0.9", "settle_window = 0.2", "remove_fallen = true"})
    EXPECT_NE(design_hash(parse_study(std::string(k_minimal) + "[pile]\n" + line + "\n", "study.toml")), design_hash(d))
        << line;
}

TEST(PileSettling, RetiredKeStopNamesLineAndItsReplacement) {
  const std::string e = error_of(std::string(k_minimal) + "[pile]\nparticles = 300\nke_stop = 2e-5\n");
  EXPECT_NE(e.find("study.toml:10: unknown key 'ke_stop' in [pile]"), std::string::npos) << e;
  EXPECT_NE(e.find("replaced by `settle_speed`"), std::string::npos) << e;
}

TEST(PileSettling, QuantileAndWindowAreBounded) {
  EXPECT_NE(error_of(std::string(k_minimal) + "[pile]\nsettle_quantile = 0\n").find("settle_quantile"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(k_minimal) + "[pile]\nsettle_quantile = 1.5\n").find("settle_quantile"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(k_minimal) + "[pile]\nsettle_window = 0\n").find("settle_window"), std::string::npos);
  EXPECT_NE(error_of(std::string(k_minimal) + "[pile]\nsettle_speed = -1\n").find("settle_speed"), std::string::npos);
}

TEST(PileSettling, UnsettledSamplesAreThoseThatStoredSettledZero) {
  const std::map<int, std::map<std::string, double>> observables{
      {0, {{"angle", 30.0}, {std::string(k_settled), 1.0}}},
      {1, {{"angle", 31.0}, {std::string(k_settled), 0.0}}},
      {2, {{"angle", 32.0}}},  // criterion off: nothing recorded, nothing flagged
      {5, {{"angle", 29.0}, {std::string(k_settled), 0.0}}}};
  EXPECT_EQ(unsettled_samples(observables), (std::vector<int>{1, 5}));
}

}  // namespace demsa
