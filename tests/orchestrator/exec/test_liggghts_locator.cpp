// Finding LIGGGHTS and reading its version: $DEMSA_LIGGGHTS, a path with a quote and spaces (run without a shell).
#include "orchestrator/exec/liggghts_locator.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/util/errors.hpp"

#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

namespace demsa {

using namespace demsa::exec;
namespace {

namespace fs = std::filesystem;

/// Sets an environment variable for the life of the object, then puts the old value back.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : m_name(name) {
    if (const char* old = std::getenv(name)) m_old = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (m_old)
      ::setenv(m_name, m_old->c_str(), 1);
    else
      ::unsetenv(m_name);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* m_name;
  std::optional<std::string> m_old;
};

TEST(LiggghtsLocator, QueriesAFakeLiggghtsWhosePathHoldsAQuote) {
  test::TempDir tmp;
  const fs::path dir = tmp / "it's a dir";
  fs::create_directories(dir);
  const fs::path fake = dir / "liggghts";
  // like the real one: the banner on stdout, usage on stderr, exit status 1; asked with `-log none` (issue 45: else
  // LIGGGHTS leaves log.liggghts in the current folder)
  test::write_file(fake,
                   "#!/bin/bash\n"
                   "[ \"$*\" = '-log none -h' ] || exit 2\n"
                   "echo 'LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, compiled 2026-01-01-00:00:00 by demsa)'\n"
                   "echo 'Usage example: liggghts -var t 300 -echo screen -in in.alloy' >&2\n"
                   "exit 1\n");
  fs::permissions(fake, fs::perms::owner_all, fs::perm_options::add);
  const ScopedEnv env("DEMSA_LIGGGHTS", fake.string());
  ASSERT_EQ(find_liggghts_executable(), fake.string());
  const std::optional<LiggghtsInfo> info = query_liggghts();
  ASSERT_TRUE(info.has_value());
  EXPECT_EQ(info->executable, fake.string());
  EXPECT_EQ(info->version, "3.8.0");
}

TEST(LiggghtsLocator, AMissingExecutableIsNotFound) {
  test::TempDir tmp;
  const ScopedEnv env("DEMSA_LIGGGHTS", (tmp / "it's not there" / "liggghts").string());
  EXPECT_FALSE(find_liggghts_executable().has_value());
  EXPECT_FALSE(query_liggghts().has_value());
}

/// A fake `liggghts -h` that lists the stock rolling models (the layout of LIGGGHTS 3.8.0's help).
fs::path fake_stock_liggghts(const fs::path& dir) {
  fs::create_directories(dir);
  const fs::path fake = dir / "liggghts";
  test::write_file(fake,
                   "#!/bin/bash\n"
                   "echo 'LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, compiled 2026-01-01-00:00:00 by demsa)'\n"
                   "echo '* Rolling models for pair gran:'\n"
                   "echo\n"
                   "echo 'cdt                             epsd                            epsd2                 '\n"
                   "echo 'epsd3                           luding                          '\n"
                   "echo\n"
                   "echo '* Surface models for pair gran:'\n"
                   "echo\n"
                   "echo 'default                         multicontact'\n"
                   "exit 1\n");
  fs::permissions(fake, fs::perms::owner_all, fs::perm_options::add);
  return fake;
}

TEST(LiggghtsLocator, ReadsTheRollingModelsOfTheHelp) {
  test::TempDir tmp;
  const LiggghtsInfo info = query_liggghts_at(fake_stock_liggghts(tmp / "stock").string());
  EXPECT_EQ(info.version, "3.8.0");
  EXPECT_EQ(info.rolling_models, (std::vector<std::string>{"cdt", "epsd", "epsd2", "epsd3", "luding"}));
  EXPECT_TRUE(parse_liggghts_help("x", "LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0)\n").rolling_models.empty());
}

study::StudyConfig rolling_study(const std::string& model, const std::string& liggghts) {
  return experiments::parse_study(
      "[study]\nname = \"t\"\nexperiment = \"pile\"\n[parameters]\n"
      "mu_r_pp = { low = 1e-6, high = 2e-6 }\n[contact]\nrolling_model = \"" +
          model + "\"\n[run]\nliggghts = \"" + liggghts + "\"\n",
      "study.toml");
}

TEST(LiggghtsLocator, AStudyWhoseRollingModelTheBinaryLacksIsRefusedSayingHowToGetIt) {
  test::TempDir tmp;
  const fs::path fake = fake_stock_liggghts(tmp / "stock");
  study::StudyConfig viscous = rolling_study("viscous", fake.string());
  const std::string message = test::message_of<util::UserError>([&] { resolve_liggghts(viscous, true); });
  EXPECT_NE(message.find("study.toml"), std::string::npos) << message;
  EXPECT_NE(message.find("rolling_model = \"viscous\""), std::string::npos) << message;
  EXPECT_NE(message.find("cdt, epsd, epsd2, epsd3, luding"), std::string::npos) << message;
  EXPECT_NE(message.find("scripts/build-liggghts.sh"), std::string::npos) << message;
  // Without `refuse` (a dry run, `demsa case`): a warning only, and the executable is recorded.
  study::StudyConfig again = rolling_study("viscous", fake.string());
  EXPECT_NO_THROW(resolve_liggghts(again, false));
  EXPECT_EQ(again.run.liggghts, fake.string());
  // A stock model passes.
  study::StudyConfig epsd3 = rolling_study("epsd3", fake.string());
  EXPECT_NO_THROW(resolve_liggghts(epsd3, true));
}

TEST(LiggghtsLocator, TheCachedBuildIsTheDefaultWhenNothingNamesALiggghts) {
  test::TempDir tmp;
  const ScopedEnv xdg("XDG_CACHE_HOME", (tmp / "cache").string());
  const ScopedEnv unset("DEMSA_LIGGGHTS", "");
  EXPECT_FALSE(cached_liggghts_executable().has_value());
  const fs::path prefix = tmp / "cache" / "demsa" / "liggghts-3.8.0-0123456789abcdef";
  fake_stock_liggghts(prefix / "bin");
  // Incomplete until demsa-liggghts.txt exists (the build script writes it last).
  EXPECT_FALSE(cached_liggghts_executable().has_value());
  test::write_file(prefix / "demsa-liggghts.txt", "LIGGGHTS 3.8.0\n");
  ASSERT_EQ(cached_liggghts_executable(), (prefix / "bin" / "liggghts").string());
  study::StudyConfig viscous = rolling_study("viscous", "liggghts");
  resolve_liggghts(viscous, false);
  EXPECT_EQ(viscous.run.liggghts, (prefix / "bin" / "liggghts").string());
  // The build is the default for the stock models too (the faster, by the same trajectories), `cdt` included; a
  // LIGGGHTS that [run] liggghts names stays.
  for (const char* model : {"cdt", "epsd3"}) {
    study::StudyConfig stock = rolling_study(model, "liggghts");
    resolve_liggghts(stock, true);
    EXPECT_EQ(stock.run.liggghts, (prefix / "bin" / "liggghts").string()) << model;
  }
  study::StudyConfig named = rolling_study("cdt", "/usr/bin/true");
  resolve_liggghts(named, true);
  EXPECT_EQ(named.run.liggghts, "/usr/bin/true");
}

}  // namespace
}  // namespace demsa
