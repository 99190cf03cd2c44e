// [contact]: the rolling model and its settings, the unit of the viscous μ_R, and the hash of a study at the default.
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <string>

namespace demsa {

using namespace demsa::study;
using namespace demsa::experiments;
namespace {

const std::string k_base =
    "[study]\nname = \"t\"\nexperiment = \"pile\"\n[parameters]\nmu_r_pp = { low = 0.45, high = 4.5 }\n";

TEST(ContactSettings, TheDefaultIsCdtAndKeepsTheHash) {
  const StudyConfig plain = parse_study(k_base, "study.toml");
  EXPECT_EQ(plain.contact.rolling_model, RollingModel::cdt);
  const StudyConfig explicit_cdt = parse_study(k_base + "[contact]\nrolling_model = \"cdt\"\n", "study.toml");
  EXPECT_EQ(design_hash(plain), design_hash(explicit_cdt));
  EXPECT_EQ(settings_table().hash_text(plain).find("contact."), std::string::npos);
}

TEST(ContactSettings, EveryModelIsReadAndChangesTheHash) {
  const std::string plain = design_hash(parse_study(k_base, "study.toml"));
  for (const std::string model : {"epsd", "epsd2", "epsd3", "viscous"}) {
    const StudyConfig c = parse_study(k_base + "[contact]\nrolling_model = \"" + model + "\"\n", "study.toml");
    EXPECT_EQ(rolling_model_name(c.contact.rolling_model), model);
    EXPECT_NE(design_hash(c), plain) << model;
  }
  const StudyConfig paper =
      parse_study(k_base + "[contact]\nrolling_model = \"viscous\"\nviscous_unit = \"mm*ms\"\n", "study.toml");
  EXPECT_EQ(paper.contact.viscous_unit, ViscousUnit::mm_ms);
  EXPECT_DOUBLE_EQ(viscous_unit_factor(paper.contact.viscous_unit), 1e-6);
  EXPECT_NE(design_hash(paper),
            design_hash(parse_study(k_base + "[contact]\nrolling_model = \"viscous\"\n", "study.toml")));
}

TEST(ContactSettings, BadValuesNameTheLineAndTheValue) {
  const std::string unknown = test::message_of<util::UserError>(
      [] { parse_study(k_base + "[contact]\nrolling_model = \"model-b\"\n", "study.toml"); });
  EXPECT_NE(unknown.find("study.toml:7"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("model-b"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("viscous"), std::string::npos) << unknown;
  const std::string damping = test::message_of<util::UserError>(
      [] { parse_study(k_base + "[contact]\nrolling_model = \"epsd\"\nrolling_damping = 1.5\n", "study.toml"); });
  EXPECT_NE(damping.find("study.toml:8"), std::string::npos) << damping;
  const std::string unit = test::message_of<util::UserError>(
      [] { parse_study(k_base + "[contact]\nviscous_unit = \"mm ms\"\n", "study.toml"); });
  EXPECT_NE(unit.find("mm ms"), std::string::npos) << unit;
}

}  // namespace
}  // namespace demsa
