// Parameter values as text for a hand-written case (exec/hand_case.hpp, parse_parameter_values): "name=value" items
// over one text or several; each mistake names HandCaseOptions.values and the item.
#include "orchestrator/exec/hand_case.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using demsa::exec::parse_parameter_values;
using demsa::util::UserError;

namespace demsa::test {
namespace {

TEST(HandCaseValues, ItemsOverSeveralTexts) {
  const auto values = parse_parameter_values({"E=2e8,mu_pp=0.5,", "nu=0.3"});
  ASSERT_EQ(values.size(), 3u);
  EXPECT_EQ(values[0].first, "E");
  EXPECT_DOUBLE_EQ(values[0].second, 2e8);
  EXPECT_EQ(values[2].first, "nu");
  EXPECT_DOUBLE_EQ(values[2].second, 0.3);
  EXPECT_TRUE(parse_parameter_values({",", ""}).empty());
}

TEST(HandCaseValues, MistakesNameTheItem) {
  const auto mistake = [](const std::vector<std::string>& texts) {
    return message_of<UserError>([&] { parse_parameter_values(texts); });
  };
  EXPECT_EQ(mistake({"E"}), "HandCaseOptions.values: 'E' is not name=value");
  EXPECT_EQ(mistake({"=1"}), "HandCaseOptions.values: '=1' is not name=value");
  EXPECT_EQ(mistake({"E=x"}), "HandCaseOptions.values: E: 'x' is not a number");
  EXPECT_EQ(mistake({"E=inf"}), "HandCaseOptions.values: E: 'inf' is not a number");
  EXPECT_EQ(mistake({"E=1", "E=2"}),
            "HandCaseOptions.values: E is given twice (E=1 and E=2); give each parameter once");
}

}  // namespace
}  // namespace demsa::test
