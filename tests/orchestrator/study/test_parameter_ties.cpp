// Tied parameters (`[parameters] mu_pw = { same_as = "mu_pp" }`): parsing, the errors at the user's line, the design
// hash and the material of a sample (tests/orchestrator/cases/test_tied_parameters.cpp: the design and a case).
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/parameters.hpp"
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

// Line 6 is the first [parameters] entry.
const std::string k_head = "[study]\nname = \"t\"\nexperiment = \"pile\"\nseed = 5\n[parameters]\n";

std::string error_of(const std::string& parameters) {
  return test::message_of<UserError>([&] { parse_study(k_head + parameters, "study.toml"); });
}

TEST(ParameterTies, InlineAndSubTableFormsTieWithoutAColumn) {
  const StudyConfig inline_form = parse_study(k_head +
                                                  "mu_r_pw = { same_as = \"mu_r_pp\" }\nmu_pp = { low = 0.2, high = "
                                                  "0.8 }\nmu_r_pp = { low = 0.05, high = 0.3 }\nmu_pw = { same_as = "
                                                  "\"mu_pp\" }\n",
                                              "study.toml");
  ASSERT_EQ(inline_form.parameters.size(), 2U);
  EXPECT_EQ(inline_form.parameters[0].name, "mu_pp");
  EXPECT_EQ(inline_form.parameters[1].name, "mu_r_pp");
  ASSERT_EQ(inline_form.ties.size(), 2U);
  EXPECT_EQ(inline_form.ties[0].name, "mu_pw");  // the paper's order, whatever the file's
  EXPECT_EQ(inline_form.ties[0].partner, "mu_pp");
  EXPECT_EQ(inline_form.ties[0].line, 9);
  EXPECT_EQ(inline_form.ties[1].name, "mu_r_pw");
  EXPECT_EQ(inline_form.ties[1].partner, "mu_r_pp");
  ASSERT_NE(find_tie(inline_form.ties, "mu_pw"), nullptr);
  EXPECT_EQ(find_tie(inline_form.ties, "mu_pp"), nullptr);

  const StudyConfig table_form = parse_study(
      k_head + "mu_pp = { low = 0.2, high = 0.8 }\n[parameters.mu_pw]\nsame_as = \"mu_pp\"\n", "study.toml");
  ASSERT_EQ(table_form.parameters.size(), 1U);
  ASSERT_EQ(table_form.ties.size(), 1U);
  EXPECT_EQ(table_form.ties[0].partner, "mu_pp");
}

TEST(ParameterTies, EveryMistakeNamesFileLineAndKey) {
  const std::string mu_pp = "mu_pp = { low = 0.2, high = 0.8 }\n";
  EXPECT_EQ(error_of(mu_pp + "mu_pw = { same_as = \"mu_ww\" }\n"),
            "study.toml:7: [parameters] mu_pw: same_as = \"mu_ww\": not a contact parameter (valid: E, nu, mu_pp, e_r, "
            "mu_r_pp, mu_r_pw)");
  EXPECT_EQ(error_of(mu_pp + "mu_pw = { same_as = \"mu_pw\" }\n"),
            "study.toml:7: [parameters] mu_pw: same_as = \"mu_pw\": a parameter cannot be tied to itself");
  EXPECT_EQ(error_of(mu_pp + "mu_pw = { same_as = \"mu_pp\" }\nmu_r_pw = { same_as = \"mu_pw\" }\n"),
            "study.toml:8: [parameters] mu_r_pw: same_as = \"mu_pw\": mu_pw is itself tied to mu_pp (line 7); tie "
            "mu_r_pw to mu_pp directly");
  EXPECT_EQ(error_of(mu_pp + "mu_pw = { low = 0.1, same_as = \"mu_pp\" }\n"),
            "study.toml:7: [parameters] mu_pw: same_as = \"mu_pp\" ties it to mu_pp, so it has no range of its own: "
            "remove 'low'");
  EXPECT_EQ(error_of(mu_pp + "mu_r_pw = { same_as = \"mu_r_pp\" }\n"),
            "study.toml:7: [parameters] mu_r_pw: same_as = \"mu_r_pp\": mu_r_pp is not varied; give it a range { low, "
            "high } in [parameters], or set both in [material]");
  EXPECT_EQ(error_of(mu_pp + "mu_pw = { same_as = 3 }\n"),
            "study.toml:7: [parameters.mu_pw] same_as: expected a string, got the integer 3");
  // Each value of the partner's range must be admissible for the tied parameter: no Poisson ratio of 1e8.
  EXPECT_NE(error_of("E = { low = 1e7, high = 1e8 }\nnu = { same_as = \"E\" }\n")
                .find("study.toml:7: [parameters] nu: same_as = \"E\": the range [10000000, 100000000] of E (line 6)"),
            std::string::npos)
      << error_of("E = { low = 1e7, high = 1e8 }\nnu = { same_as = \"E\" }\n");
  // A table that is neither a range nor a tie says both.
  EXPECT_NE(error_of(mu_pp + "mu_pw = { }\n").find("needs both 'low' and 'high' (or `same_as = \"KEY\"`"),
            std::string::npos);
}

TEST(ParameterTies, TheTieChangesTheDesignHashAndTheSampleMaterial) {
  const std::string ranges = "mu_pp = { low = 0.2, high = 0.8 }\nmu_r_pp = { low = 0.05, high = 0.3 }\n";
  const StudyConfig free = parse_study(k_head + ranges, "study.toml");
  const StudyConfig tied = parse_study(k_head + ranges + "mu_pw = { same_as = \"mu_pp\" }\n", "study.toml");
  const StudyConfig both = parse_study(
      k_head + ranges + "mu_pw = { same_as = \"mu_pp\" }\nmu_r_pw = { same_as = \"mu_r_pp\" }\n", "study.toml");
  EXPECT_NE(design_hash(free), design_hash(tied));
  EXPECT_NE(design_hash(tied), design_hash(both));
  EXPECT_NE(free.table->hash_text(tied).find("p.mu_pw.same_as=mu_pp\n"), std::string::npos);

  const Material m = material_for(both, {0.55, 0.21});
  EXPECT_DOUBLE_EQ(m.mu_pp, 0.55);
  EXPECT_DOUBLE_EQ(m.mu_pw, 0.55);
  EXPECT_DOUBLE_EQ(m.mu_r_pp, 0.21);
  EXPECT_DOUBLE_EQ(m.mu_r_pw, 0.21);
  const Material untied = material_for(free, {0.55, 0.21});
  EXPECT_DOUBLE_EQ(untied.mu_pw, free.material.mu_pw);  // the [material] value

  // The settings table shows the tie (demsa show-config, the changed-settings message).
  const Setting* row = free.table->find("parameters", "mu_pw");
  ASSERT_NE(row, nullptr);
  EXPECT_EQ(row->show(tied), "{ same_as = \"mu_pp\" }");
  EXPECT_EQ(row->show(free), "not varied");
  EXPECT_EQ(symbol_with_ties("mu_pp", both.ties), "μ_PP = μ_PW");
  EXPECT_EQ(symbol_with_ties("mu_r_pp", both.ties, true), "μ_{R,PP} = μ_{R,PW}");
  EXPECT_EQ(symbol_with_ties("mu_pp", free.ties), "μ_PP");
}

}  // namespace
}  // namespace demsa
