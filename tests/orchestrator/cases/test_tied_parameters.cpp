// A study with a tied parameter: one design column for the pair, both values in every case (params.liggghts,
// case.json), and `--set` of the tied one refused (tests/orchestrator/study/test_parameter_ties.cpp: the parser).
#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/design_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace demsa {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::experiments;
namespace {

const std::string k_head = "[study]\nname = \"t\"\nexperiment = \"pile\"\nseed = 5\n[parameters]\n";

TEST(TiedParameters, TheDesignHasOneColumnPerPairAndTheCaseBothValues) {
  const StudyConfig c = parse_study(k_head +
                                        "mu_pp = { low = 0.2, high = 0.8 }\nmu_r_pp = { low = 0.05, high = 0.3 }\n"
                                        "mu_pw = { same_as = \"mu_pp\" }\n[design]\nsamples = 6\nmethod = \"lhs\"\n"
                                        "[pile]\nparticles = 300\n",
                                    "study.toml");
  const std::vector<SampleRow> design = exec::draw_design(c);
  ASSERT_EQ(design.size(), 6U);
  for (const SampleRow& row : design) EXPECT_EQ(row.unit.size(), 2U);
  const std::string csv = study::design_csv(c, design);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "sample,u_mu_pp,u_mu_r_pp,mu_pp,mu_r_pp");

  test::TempDir tmp;
  const cases::CaseRequest r = cases::request_from_unit_point(c, 2, {0.75, 0.5});
  cases::write_case(c, r, tmp / "case");
  const std::string params = test::read_file(tmp / "case" / "params.liggghts");
  EXPECT_NE(params.find("variable mu_pp                equal 0.65"), std::string::npos) << params;
  EXPECT_NE(params.find("variable mu_pw                equal 0.65"), std::string::npos) << params;
  const nlohmann::json j = nlohmann::json::parse(test::read_file(tmp / "case" / "case.json"));
  EXPECT_DOUBLE_EQ(j.at("parameters").at("mu_pw").get<double>(), 0.65);
  EXPECT_DOUBLE_EQ(j.at("parameters").at("mu_pp").get<double>(), 0.65);
  EXPECT_FALSE(j.at("parameters").contains("mu_r_pw"));

  // `demsa case --set` names the partner for a tied parameter.
  try {
    cases::request_from_values(c, {{"mu_pw", 0.5}});
    FAIL() << "a tied parameter was set";
  } catch (const UserError& e) {
    EXPECT_EQ(std::string(e.what()), "mu_pw is tied to mu_pp in study.toml (same_as): set mu_pp");
  }
}

}  // namespace
}  // namespace demsa
