// util::rename_fields: the fields the libraries' messages name ("OedometerOptions.box_side"), written in a front end's
// words; a longer field of the same start is left alone.
#include "orchestrator/util/text.hpp"

#include <gtest/gtest.h>

#include <string>

namespace demsa::test {
namespace {

TEST(RenameFields, WritesEachNamedFieldAsItsReplacement) {
  const std::vector<std::pair<std::string, std::string>> names{{"box_side", "--box-side"}, {"base", "--base"}};
  EXPECT_EQ(util::rename_fields("OedometerOptions.box_side = nan", names), "--box-side = nan");
  EXPECT_EQ(util::rename_fields("SensitivityChoiceOptions.base 8 and MetamodelSobolOptions.base 8", names),
            "--base 8 and --base 8");
  EXPECT_EQ(util::rename_fields("OedometerOptions.box_side_x 1", names), "OedometerOptions.box_side_x 1");
  EXPECT_EQ(util::rename_fields("Options.floor_z 1", names), "Options.floor_z 1");
  EXPECT_EQ(util::rename_fields("no field here", names), "no field here");
}

}  // namespace
}  // namespace demsa::test
