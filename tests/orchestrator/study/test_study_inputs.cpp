// What the study-file reader refuses of a hostile or careless file, at its line and naming the key and value: an
// integer the field cannot hold (it used to be narrowed), a size the machine cannot hold, an empty command, the
// table of the other experiment, a folder or an endless file given as the study file; and what it corrects with a
// warning (a base sample count that is not a power of two).
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/errors.hpp"

#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace demsa {

using namespace demsa::study;
using namespace demsa::experiments;
namespace {

namespace fs = std::filesystem;

const std::string k_pile =
    "[study]\nname = \"s\"\nexperiment = \"pile\"\n[parameters]\nE = { low = 1e8, high = 1e9 }\n";
const std::string k_oedometer =
    "[study]\nname = \"s\"\nexperiment = \"oedometer\"\n[parameters]\nE = { low = 1e8, high = 1e9 }\n";

std::string error_of(const std::string& text) {
  return test::message_of<util::UserError>([&] { parse_study(text, "study.toml"); });
}

/// The study text that gives `key` of `section` the TOML value `value` (at line 7), in a study of the row's experiment.
std::string with_value(const Setting& s, const std::string& value) {
  if (s.section == "study") {
    // The [study] table is already there: give the key inside it.
    return fmt::format(
        "[study]\nname = \"s\"\nexperiment = \"pile\"\n{} = {}\n[parameters]\nE = {{ low = 1e8, high = "
        "1e9 }}\n",
        s.key, value);
  }
  return (s.section == "oedometer" ? k_oedometer : k_pile) + fmt::format("[{}]\n{} = {}\n", s.section, s.key, value);
}

TEST(StudyInputs, EveryIntegerBeyondItsFieldIsRefusedNotNarrowed) {
  // 4294967304 = 2^32 + 8 was read into an int as 8; 9223372036854775807 as -1.
  int rows = 0;
  for (const Setting& s : settings_table().rows()) {
    if (s.type != SettingType::integer) continue;
    ++rows;
    for (const std::string value : {"4294967304", "9223372036854775807", "-4294967295"}) {
      if (s.key == "seed" && value[0] != '-') continue;  // a 64-bit seed holds every non-negative TOML integer
      if (value == "4294967304" && s.bounds.high->value >= 4294967304.0) continue;  // a 64-bit step count holds it
      const std::string e = error_of(with_value(s, value));
      EXPECT_NE(e.find("study.toml:"), std::string::npos) << s.key << ": " << e;
      EXPECT_NE(e.find(fmt::format("[{}] {}:", s.section, s.key)), std::string::npos) << e;
      EXPECT_NE(e.find("got " + value), std::string::npos) << e;
    }
  }
  EXPECT_GE(rows, 17);
}

TEST(StudyInputs, EveryIntegerRowHasAnUpperBound) {
  for (const Setting& s : settings_table().rows()) {
    if (s.type != SettingType::integer || s.key == "seed") continue;
    EXPECT_TRUE(s.bounds.high.has_value()) << s.section << "." << s.key;
    EXPECT_EQ(s.range_text.find("e+"), std::string::npos) << s.key << ": " << s.range_text;  // 100000, not 1e+05
  }
}

TEST(StudyInputs, SizesTheMachineCannotHoldAreRefusedNamingTheKey) {
  EXPECT_EQ(error_of(k_pile + "[design]\nsamples = 2000000000\n"),
            "study.toml:7: [design] samples: must lie in [2, 100000], got 2000000000: the analysis needs at least 2 "
            "samples, one case alone is `demsa case`; each sample is a case folder");
  EXPECT_NE(error_of(k_pile + "[pile]\nparticles = 2000000000\n")
                .find("study.toml:7: [pile] particles: must lie in [1, 10000000], got 2000000000: the case writer"),
            std::string::npos);
  EXPECT_NE(error_of(k_oedometer + "[oedometer]\nparticles = 2000000000\n").find("[oedometer] particles"),
            std::string::npos);
  EXPECT_NE(error_of(k_pile + "[analysis]\nbase_samples = 9223372036854775807\n")
                .find("study.toml:7: [analysis] base_samples: must lie in [16, 1048576], got 9223372036854775807"),
            std::string::npos);
  // The optimised Latin hypercubes keep an N x N matrix: fewer samples than the other designs.
  EXPECT_NE(error_of(k_pile + "[design]\nsamples = 50000\n")
                .find("study.toml:7: [design] samples: method \"lhs-maximin\" takes at most 4096 samples"),
            std::string::npos);
  // ... the bound sobol::make_design holds (5000 passed the study and failed when `demsa run` drew the design).
  EXPECT_NE(error_of(k_pile + "[design]\nsamples = 5000\n").find("study.toml:7: [design] samples: method"),
            std::string::npos);
  EXPECT_NO_THROW(parse_study(k_pile + "[design]\nsamples = 4096\n", "study.toml"));
  EXPECT_NO_THROW(parse_study(k_pile + "[design]\nsamples = 50000\nmethod = \"lhs\"\n", "study.toml"));
  // The reasons are in the docs' rows.
  EXPECT_NE(settings_table().find("pile", "particles")->doc.find("bounds: the case writer"), std::string::npos);
}

TEST(StudyInputs, OneSampleIsRefusedForEveryDesignAsTheDocsSay) {
  // A study exists for its analysis, which needs two samples; the docs give the same minimum for every design.
  for (const std::string method : {"lhs", "lhs-maximin", "sobol"}) {
    const std::string e = error_of(k_pile + "[design]\nsamples = 1\nmethod = \"" + method + "\"\n");
    EXPECT_NE(e.find("study.toml:7: [design] samples: must lie in [2, 100000], got 1"), std::string::npos) << e;
    EXPECT_NE(e.find("`demsa case`"), std::string::npos) << e;
  }
  EXPECT_EQ(settings_table().find("design", "samples")->range_text.rfind("[2, 100000]", 0), 0u);
  EXPECT_NO_THROW(parse_study(k_pile + "[design]\nsamples = 2\n", "study.toml"));
}

TEST(StudyInputs, BaseSamplesAreRoundedUpToAPowerOfTwoWithAWarning) {
  testing::internal::CaptureStderr();
  const StudyConfig c = parse_study(k_pile + "[analysis]\nbase_samples = 10000\n", "study.toml");
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(c.analysis.base_samples, 16384);
  EXPECT_EQ(err, "demsa: warning: [analysis] base_samples = 10000 is not a power of two; the analysis uses 16384\n");

  testing::internal::CaptureStderr();
  EXPECT_EQ(parse_study(k_pile + "[analysis]\nbase_samples = 4096\n", "study.toml").analysis.base_samples, 4096);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(StudyInputs, EmptyCommandsAreRefused) {
  EXPECT_EQ(error_of(k_pile + "[run]\nliggghts = \"\"\n"), "study.toml:7: [run] liggghts: must not be empty");
  EXPECT_EQ(error_of(k_pile + "[run]\nmpirun = \"  \"\n"), "study.toml:7: [run] mpirun: must not be blank");
  EXPECT_EQ(settings_table().find("run", "liggghts")->range_text, "non-empty");
}

TEST(StudyInputs, TheOtherExperimentsTableIsRefusedAtItsLine) {
  EXPECT_EQ(error_of(k_oedometer + "[pile]\nparticles = 100\n"),
            "study.toml:6: [pile] does not apply to this study: [study] experiment = \"oedometer\" (line 3); remove "
            "the table or change the experiment");
  EXPECT_EQ(error_of(k_pile + "[oedometer]\nparticles = 100\n"),
            "study.toml:6: [oedometer] does not apply to this study: [study] experiment = \"pile\" (line 3); remove "
            "the table or change the experiment");
  EXPECT_NO_THROW(parse_study(k_oedometer + "[oedometer]\nparticles = 100\n", "study.toml"));
}

TEST(StudyInputs, ANonAsciiCharacterAfterALineEndingBackslashIsReadAsText) {
  // toml++ 3.3 reaches TOML_UNREACHABLE in is_non_ascii_horizontal_whitespace() on "μ" after a line-ending backslash
  // (bench/fuzz-study-file.sh found it; the fuzz build leaves that check out). demsa's build reads such a string as
  // TOML says, and reports the malformed one: this pins that behaviour.
  const std::string study =
      "[study]\nname = \"\"\"a\\\n  \u03bcb\"\"\"\nexperiment = 'pile'\n[parameters]\n"
      "E = { low = 1e8, high = 1e9 }\n";
  EXPECT_EQ(parse_study(study, "study.toml").name, "a\u03bcb");
  EXPECT_EQ(error_of(k_pile + "[run.slurm]\nprologue = \"\"\"a\\ \u03bc\"\"\"\n"),
            "study.toml:7: Error while parsing string: line-ending backslashes must be the last non-whitespace "
            "character on the line");
}

TEST(StudyInputs, NonAsciiOutsideStringsIsRefusedBeforeTomlReadsIt) {
  // toml++ 3.3 reaches undefined behaviour on such a character (bench/fuzz-study-file.sh found "\u00a7" there).
  EXPECT_EQ(error_of(k_pile + "[pile]\nparticles \u00a7 = 100\n"),
            "study.toml:7: a non-ASCII character outside a string or a comment (TOML allows them only in strings and "
            "comments, and demsa only in the strings of values)");
  // ... also after a quote where TOML has no string (toml++ reads on as code there).
  EXPECT_NE(error_of(k_pile + "[analysis]\nmetamodels = [\"rsm2\",-\"\u048bps\"]\n").find("study.toml:7: a non-ASCII"),
            std::string::npos);
  // ... and in keys, where a multi-line quote is no string to toml++ (the fuzz found UB after '"""' there), and
  // after an '=', a '[' or a '{' inside a malformed value, which toml++ reads as code.
  for (const std::string key :
       {R"("""§""" = 1)", R"("é" = 1)", R"('é' = 1)", R"(a."é" = 1)", R"(["é"])", R"(x = { "é" = 1 })",
        R"(x = [{ 'é' = 1 }])", "n=-n=\"\xef\xbb\xbe", "a=5.6[\"\u02a4\"]", "a=5.6{b=\"\u02a4\"}"})
    EXPECT_NE(error_of(k_pile + key + "\n").find("study.toml:6: a non-ASCII character"), std::string::npos) << key;
  // In the strings of values (arrays and inline tables included) and in comments they are welcome, as is a byte
  // order mark.
  const std::string text =
      "\xEF\xBB\xBF# \u00a73 Table 2\n[study]\nname = \"p\u00e9 \\\" \u00a7\"\nexperiment = 'pile'\n"
      "[parameters]\nE = { low = 1e8, high = 1e9 } # \u00e9\n[run.slurm]\n"
      "prologue = \"\"\"\nmodule load \u00e9\"\"\"\naccount = '''\u00e9'''\n";
  const StudyConfig c = parse_study(text, "study.toml");
  EXPECT_EQ(c.name, "p\u00e9 \" \u00a7");
  EXPECT_EQ(c.run.slurm.account, "\u00e9");
  const std::string values = R"([analysis]
metamodels = ["é", [ 'é' ], # é
  """é""", '''é''', { y = "é" }]
)";
  const std::string refused = error_of(k_pile + values);
  EXPECT_EQ(refused.find("non-ASCII"), std::string::npos) << refused;
}

TEST(StudyInputs, AFolderOrAnEndlessFileIsNotReadAsAStudy) {
  test::TempDir tmp;
  fs::create_directories(tmp / "study");
  const std::string folder = test::message_of<util::UserError>([&] { load_study(tmp / "study"); });
  EXPECT_NE(folder.find("is a folder, not a study file"), std::string::npos) << folder;
  EXPECT_EQ(folder.find("name is required"), std::string::npos) << folder;

  // /dev/zero never ends: refused before it is opened, as every file that is not a regular one (a FIFO would block).
  const std::string endless = test::message_of<util::UserError>([] { load_study("/dev/zero"); });
  EXPECT_EQ(endless,
            "/dev/zero: a character device, not a regular file: demsa reads regular files only (a read from a FIFO or "
            "a device can wait for ever)");
}

}  // namespace
}  // namespace demsa
