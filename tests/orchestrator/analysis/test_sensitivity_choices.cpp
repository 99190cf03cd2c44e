// The choices of `demsa sensitivity` as text and numbers (analysis/sensitivity_choices.hpp): the bounds syntax, the
// interval method, the metamodels and the GP by name, and the numbers; each mistake names the field and the value.
#include "orchestrator/analysis/sensitivity_choices.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace demsa::analysis;
using demsa::util::UserError;

namespace demsa::test {
namespace {

const std::vector<std::string> k_inputs{"a", "b", "c"};

TEST(SensitivityChoices, BoundsOfTheInputsNamed) {
  const auto bounds = parse_input_bounds("a=0:1,b=1:100:log", k_inputs);
  ASSERT_EQ(bounds.size(), 2u);
  EXPECT_DOUBLE_EQ(bounds.at("a").high, 1.0);
  EXPECT_DOUBLE_EQ(bounds.at("b").low, 1.0);
  EXPECT_EQ(bounds.at("b").scale, sobol::Scale::log_uniform);
  EXPECT_TRUE(parse_input_bounds("", k_inputs).empty());
}

TEST(SensitivityChoices, BoundsMistakesNameTheItem) {
  EXPECT_EQ(message_of<UserError>([] { parse_input_bounds("a=0:x", k_inputs); }),
            "DataSensitivityOptions.bounds 'a=0:x': 'x' is not a number");
  EXPECT_EQ(message_of<UserError>([] { parse_input_bounds("z=0:1", k_inputs); }),
            "DataSensitivityOptions.bounds 'z=0:1': expected NAME=LOW:HIGH[:log] with NAME one of "
            "DataSensitivityOptions.inputs");
  EXPECT_EQ(message_of<UserError>([] { parse_input_bounds("a=0", k_inputs); }),
            "DataSensitivityOptions.bounds 'a=0': expected NAME=LOW:HIGH[:log]");
  EXPECT_EQ(message_of<UserError>([] { parse_input_bounds("a=0:1,a=0:2", k_inputs); }),
            "DataSensitivityOptions.bounds: 'a' is given twice");
  EXPECT_EQ(message_of<UserError>([] { parse_input_bounds("a=0:1:cube", k_inputs); }),
            "DataSensitivityOptions.bounds 'a=0:1:cube': unknown scale 'cube' (valid: uniform, log)");
}

TEST(SensitivityChoices, IntervalFollowsTheBootstrap) {
  SensitivityChoiceOptions o;
  EXPECT_EQ(saltelli_interval_choice(o), sobol::SaltelliInterval::replicates);
  o.bootstrap = 50;
  EXPECT_EQ(saltelli_interval_choice(o), sobol::SaltelliInterval::bootstrap);
  o.interval = "replicates";
  EXPECT_EQ(message_of<UserError>([&] { saltelli_interval_choice(o); }),
            "SensitivityChoiceOptions.bootstrap 50 gives the resamples of SensitivityChoiceOptions.interval "
            "bootstrap, not of SensitivityChoiceOptions.interval replicates");
  o.bootstrap.reset();
  o.interval = "none";
  EXPECT_EQ(saltelli_interval_choice(o), sobol::SaltelliInterval::none);
  o.interval = "foo";
  EXPECT_EQ(message_of<UserError>([&] { saltelli_interval_choice(o); }),
            "SensitivityChoiceOptions.interval: unknown interval method 'foo' (valid: replicates, bootstrap, none)");
}

TEST(SensitivityChoices, NumbersAreChecked) {
  SensitivityChoiceOptions o;
  o.data = "data.csv";
  EXPECT_NO_THROW(check_sensitivity_choices(o));
  o.base = 8;
  EXPECT_EQ(message_of<UserError>([&] { check_sensitivity_choices(o); }),
            "SensitivityChoiceOptions.base 8: must be at least 16 (a power of two, e.g. 16384, balances best)");
  o.base = sobol::k_max_base_samples + 1;
  EXPECT_NE(message_of<UserError>([&] { check_sensitivity_choices(o); }).find("at most 2^20"), std::string::npos);
  o.base = 1024;
  o.confidence = 1.0;
  EXPECT_EQ(message_of<UserError>([&] { check_sensitivity_choices(o); }),
            "SensitivityChoiceOptions.confidence 1: must be strictly between 0 and 1 (e.g. 0.95)");
  o.confidence = 0.9;
  o.bootstrap = -1;
  EXPECT_EQ(message_of<UserError>([&] { check_sensitivity_choices(o); }),
            "SensitivityChoiceOptions.bootstrap -1: must be >= 0 (0: no intervals)");
}

TEST(SensitivityChoices, OptionsOfOnePathAreRefusedOnTheOther) {
  SensitivityChoiceOptions o;
  EXPECT_EQ(message_of<UserError>([&] { check_sensitivity_choices(o); }),
            "give exactly one of SensitivityChoiceOptions.design DESIGN.csv (with "
            "SaltelliSensitivityOptions.responses_file) or SensitivityChoiceOptions.data DATA.csv");
  o.design = "design.csv";
  o.data = "data.csv";
  EXPECT_NE(message_of<UserError>([&] { check_sensitivity_choices(o); }).find("exactly one"), std::string::npos);
  o.design.clear();
  o.interval = "bootstrap";
  EXPECT_EQ(message_of<UserError>([&] { check_sensitivity_choices(o); }),
            "SensitivityChoiceOptions.interval goes with SensitivityChoiceOptions.design: the intervals of "
            "SensitivityChoiceOptions.data are design-bootstrap refits of each metamodel "
            "(SensitivityChoiceOptions.bootstrap)");
  o.interval.clear();
  o.repeats = "repeats.csv";
  o.save_model = "model.json";
  EXPECT_NO_THROW(check_sensitivity_choices(o));
  o.data.clear();
  o.design = "design.csv";
  EXPECT_EQ(message_of<UserError>([&] { check_sensitivity_choices(o); }),
            "SensitivityChoiceOptions.repeats goes with SensitivityChoiceOptions.data: the noise sets the nugget of "
            "the metamodels fitted to the data");
  o.repeats.clear();
  EXPECT_EQ(message_of<UserError>([&] { check_sensitivity_choices(o); }),
            "SensitivityChoiceOptions.save_model: a Saltelli design gives indices without a metamodel: nothing to "
            "save (use SensitivityChoiceOptions.data)");
  o.interval = "jackknife";  // the design's interval is checked before what it cannot save
  EXPECT_EQ(
      message_of<UserError>([&] { check_sensitivity_choices(o); }).rfind("SensitivityChoiceOptions.interval: ", 0), 0u);
  o.interval = "replicates";
  o.save_model.clear();
  EXPECT_NO_THROW(check_sensitivity_choices(o));
}

TEST(SensitivityChoices, MetamodelsAndGpByName) {
  const std::vector<sobol::MetamodelKind> kinds = choose_metamodels({"rsm2", "gp"});
  ASSERT_EQ(kinds.size(), 2u);
  EXPECT_EQ(kinds[1], sobol::MetamodelKind::gp);
  EXPECT_EQ(message_of<UserError>([] {
              choose_metamodels({"rsm2", "foo"});
            }),
            "DataSensitivityOptions.metamodels: unknown metamodel 'foo' (valid: rsm1, rsm2, rsm3, rbf-cubic, rbf-tps, "
            "gp)");
  sobol::GpOptions gp;
  choose_gp({"matern52", "linear"}, gp);
  EXPECT_EQ(gp.kernel, sobol::GpKernel::matern52);
  EXPECT_EQ(gp.trend, sobol::GpTrend::linear);
  EXPECT_EQ(message_of<UserError>([&] {
              choose_gp({"foo", "linear"}, gp);
            }),
            "GpChoiceOptions.kernel: unknown GP kernel 'foo' (valid: squared-exponential, matern52)");
  EXPECT_EQ(message_of<UserError>([&] {
              choose_gp({"matern52", "cubic"}, gp);
            }),
            "GpChoiceOptions.trend: unknown GP trend 'cubic' (valid: constant, linear)");
}

}  // namespace
}  // namespace demsa::test
