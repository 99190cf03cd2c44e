// The text syntax of measured values and observables (analysis/target_syntax.hpp): "NAME=V±E", curves, "STUDY:NAME",
// weights and sds parsed into the library's types; every mistake names the label the caller gave and the text.
#include "orchestrator/analysis/target_syntax.hpp"
#include "orchestrator/util/errors.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

using namespace demsa::analysis;
using demsa::util::UserError;

namespace demsa::test {
namespace {

TEST(TargetSyntax, ObservableWithAndWithoutStudy) {
  const QualifiedName plain = parse_observable("obs", " angle ");
  EXPECT_EQ(plain.study, "");
  EXPECT_EQ(plain.name, "angle");
  const QualifiedName q = parse_observable("obs", "pile:angle");
  EXPECT_EQ(q.study, "pile");
  EXPECT_EQ(q.name, "angle");
  EXPECT_EQ(q.label(), "pile:angle");
  EXPECT_EQ(message_of<UserError>([] { parse_observable("obs", "pile:"); }),
            "obs 'pile:': expected NAME or STUDY:NAME (STUDY: a study's [study] name)");
  EXPECT_EQ(message_of<UserError>([] { parse_observable("obs", " "); }), "obs ' ': no observable named");
}

TEST(TargetSyntax, MeasuredValueCurveAndUncertainties) {
  const std::vector<MeasuredTarget> one = parse_measured("target", "angle=31.5±0.5");
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].name, "angle");
  EXPECT_DOUBLE_EQ(one[0].value, 31.5);
  EXPECT_DOUBLE_EQ(one[0].sd, 0.5);
  const std::vector<MeasuredTarget> exact = parse_measured("target", "angle=31.5");
  EXPECT_DOUBLE_EQ(exact[0].sd, 0.0);
  const std::vector<MeasuredTarget> curve = parse_measured("target", "oed:settlement=1e-3,2e-3,+-1e-4,2e-4");
  ASSERT_EQ(curve.size(), 2u);
  EXPECT_EQ(curve[0].study, "oed");
  EXPECT_EQ(curve[1].name, "settlement_2");
  EXPECT_DOUBLE_EQ(curve[1].value, 2e-3);
  EXPECT_DOUBLE_EQ(curve[1].sd, 2e-4);
}

TEST(TargetSyntax, MeasuredValueMistakesNameTheText) {
  EXPECT_EQ(message_of<UserError>([] { parse_measured("--target", "31.5"); }),
            "--target '31.5': expected NAME=VALUE±ERROR");
  EXPECT_EQ(message_of<UserError>([] { parse_measured("--target", "angle=x±1"); }),
            "--target 'angle=x±1': 'x' is not a number");
  EXPECT_EQ(message_of<UserError>([] { parse_measured("--target", "angle=1±"); }),
            "--target 'angle=1±': no uncertainty after '±'");
  EXPECT_EQ(message_of<UserError>([] { parse_measured("--target", "s=1,2,3±1,2"); }),
            "--target 's=1,2,3±1,2': 2 uncertainties for 3 values (give one or one per value)");
  EXPECT_NE(message_of<UserError>([] {
              parse_measured("--target", "angle=1±0");
            }).find("--target 'angle=1±0': uncertainty 0 must be > 0"),
            std::string::npos);
}

TEST(TargetSyntax, WeightAndSd) {
  const auto [label, weight] = parse_weight("weight", "pile:angle=2");
  EXPECT_EQ(label, "pile:angle");
  EXPECT_DOUBLE_EQ(weight, 2.0);
  EXPECT_EQ(message_of<UserError>([] { parse_weight("--weight", "angle=-1"); }),
            "--weight 'angle=-1': one value >= 0 expected");
  EXPECT_EQ(message_of<UserError>([] { parse_weight("--weight", "angle"); }), "--weight 'angle': expected NAME=W");
  const ObservableSd sd = parse_observable_sd("sd", "pile:angle=0.8");
  EXPECT_EQ(sd.observable.label(), "pile:angle");
  EXPECT_DOUBLE_EQ(sd.sd, 0.8);
  EXPECT_EQ(message_of<UserError>([] { parse_observable_sd("--sd", "angle"); }),
            "--sd 'angle': expected NAME=SD or STUDY:NAME=SD");
  EXPECT_NE(message_of<UserError>([] {
              parse_observable_sd("--sd", "angle=wide");
            }).find("--sd 'angle=wide': 'wide' must be a number > 0"),
            std::string::npos);
}

TEST(TargetSyntax, TargetFileMistakesNameTheText) {
  EXPECT_EQ(message_of<UserError>([] { read_target_file("--target-file", "curve.csv"); }),
            "--target-file 'curve.csv': expected NAME=FILE.csv");
  const std::string missing = (std::filesystem::temp_directory_path() / "demsa-no-such-curve.csv").string();
  EXPECT_EQ(message_of<UserError>([&] { read_target_file("--target-file", "s=" + missing); }),
            "--target-file 's=" + missing + "': " + missing + " does not exist");
}

}  // namespace
}  // namespace demsa::test
