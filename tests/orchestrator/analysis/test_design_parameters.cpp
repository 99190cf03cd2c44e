// The parameters of a design as a front end names them (analysis/simulator_design.hpp): "NAME:LOW:HIGH[:log]" specs
// or a dimension, and the kind of a Latin hypercube; each mistake names the field and the spec.
#include "orchestrator/analysis/simulator_design.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace demsa::analysis;
using demsa::util::UserError;

namespace demsa::test {
namespace {

std::string mistake(const DesignParameterOptions& options) {
  return message_of<UserError>([&] { parse_design_parameters(options); });
}

TEST(DesignParameters, SpecsAndDimension) {
  const DesignParameters named = parse_design_parameters({{"a:0:1", "b:1:100:log"}, std::nullopt});
  EXPECT_TRUE(named.named);
  ASSERT_EQ(named.names.size(), 2u);
  EXPECT_EQ(named.names[1], "b");
  EXPECT_DOUBLE_EQ(named.bounds[1].high, 100.0);
  EXPECT_EQ(named.bounds[1].scale, sobol::Scale::log_uniform);
  const DesignParameters cube = parse_design_parameters({{}, 3});
  EXPECT_FALSE(cube.named);
  ASSERT_EQ(cube.names.size(), 3u);
  EXPECT_EQ(cube.names[2], "x3");
  EXPECT_DOUBLE_EQ(cube.bounds[2].high, 1.0);
}

TEST(DesignParameters, MistakesNameTheSpec) {
  EXPECT_EQ(mistake({{"a:0:x"}, std::nullopt}), "DesignParameterOptions.parameters 'a:0:x': high: 'x' is not a number");
  EXPECT_EQ(mistake({{"a:0"}, std::nullopt}),
            "DesignParameterOptions.parameters 'a:0': expected NAME:LOW:HIGH or NAME:LOW:HIGH:log");
  EXPECT_EQ(mistake({{"a:0:1", "a:1:2"}, std::nullopt}),
            "DesignParameterOptions.parameters 'a:1:2': parameter 'a' given twice");
  EXPECT_EQ(mistake({{"a:0:1:cube"}, std::nullopt}),
            "DesignParameterOptions.parameters 'a:0:1:cube': unknown scale 'cube' (valid: uniform, log)");
  EXPECT_EQ(mistake({{"a:1:0"}, std::nullopt}),
            "DesignParameterOptions.parameters: parameter 'a': low (1) must be less than high (0)");
  EXPECT_EQ(mistake({{}, 0}),
            "DesignParameterOptions.dimension 0: not a valid dimension, the number of parameters must be at least 1");
  EXPECT_NE(mistake({{"a:0:1"}, 2}).find("not both"), std::string::npos);
  EXPECT_NE(mistake({{}, std::nullopt}).find("give the dimension"), std::string::npos);
}

TEST(DesignParameters, LhsKind) {
  EXPECT_EQ(lhs_kind({}), sobol::DesignKind::lhs);
  EXPECT_EQ(lhs_kind({true, ""}), sobol::DesignKind::lhs_centred);
  EXPECT_EQ(lhs_kind({false, "cl2"}), sobol::lhs_criterion_from_string("cl2"));
  EXPECT_EQ(message_of<UserError>([] {
              lhs_kind({true, "maximin"});
            }),
            "LhsKindOptions.centred and LhsKindOptions.criterion cannot be combined");
  EXPECT_EQ(message_of<UserError>([] {
              lhs_kind({false, "foo"});
            }),
            "LhsKindOptions.criterion: unknown LHS criterion 'foo' (valid: maximin, cl2)");
}

}  // namespace
}  // namespace demsa::test
