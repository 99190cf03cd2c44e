// Finding LIGGGHTS and reading its version: $DEMSA_LIGGGHTS, a path with a quote and spaces (run without a shell).
#include "orchestrator/exec/liggghts_locator.hpp"

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
  // like the real one: the banner on stdout, usage on stderr, exit status 1
  test::write_file(fake,
                   "#!/bin/bash\n"
                   "[ \"$1\" = -h ] || exit 2\n"
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

}  // namespace
}  // namespace demsa
