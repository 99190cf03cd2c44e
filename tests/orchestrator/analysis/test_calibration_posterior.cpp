// The printed form of a posterior (analysis/calibration_posterior.hpp): what is listed and what is left to
// posterior.json.
#include "orchestrator/analysis/calibration_posterior.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <string>

using namespace demsa::analysis;

namespace demsa::test {
namespace {

/// Seven parameters whose only strong correlation is p1 ~ p2 (-0.6); p3 ~ p4 at 0.3 is on the threshold.
PosteriorOutcome seven_parameters() {
  PosteriorOutcome o;
  o.studies = {"pile"};
  for (int j = 1; j <= 7; ++j) {
    PosteriorParameter p;
    p.name = fmt::format("p{}", j);
    p.identified = "no";
    o.parameters.push_back(p);
  }
  o.correlation.assign(7, std::vector<double>(7, 0.05));
  for (int j = 0; j < 7; ++j) o.correlation[j][j] = 1.0;
  o.correlation[0][1] = o.correlation[1][0] = -0.6;
  o.correlation[2][3] = o.correlation[3][2] = 0.3;
  return o;
}

TEST(PosteriorText, ListsOnlyTheStrongCorrelationsAndCountsTheOthers) {
  const std::string text = posterior_text(seven_parameters());
  EXPECT_NE(text.find("correlations with |r| >= 0.3 (19 other pairs below, all in posterior.json):\n"
                      "  p1 ~ p2: -0.600\n  p3 ~ p4: +0.300\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("p1 ~ p3"), std::string::npos) << text;
  // The full matrix stays in the JSON.
  EXPECT_NE(posterior_to_json(seven_parameters()).find("\"correlation\""), std::string::npos);
}

}  // namespace
}  // namespace demsa::test
