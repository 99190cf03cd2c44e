#pragma once
// Helpers shared by the tests: a temporary directory per test, running the demsa binary, reading files.
#include <filesystem>
#include <string>
#include <vector>

namespace demsa::test {

/// A fresh directory under $TMPDIR (or /tmp), removed when the object goes out of scope unless
/// DEMSA_KEEP_TEST_DIRS is set (then its path is printed).
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return m_path; }
  std::filesystem::path operator/(const std::string& name) const { return m_path / name; }

 private:
  std::filesystem::path m_path;
};

struct CommandResult {
  int exit_code = -1;  ///< exit status; 128 + signal when killed by a signal
  std::string out;     ///< standard output
  std::string err;     ///< standard error
};

/// Runs the demsa binary built with the tests, with `args`, in `cwd` (empty: current directory).
CommandResult run_demsa(const std::vector<std::string>& args, const std::filesystem::path& cwd = {});

/// Runs any program (argv[0] looked up on PATH) and captures its output.
CommandResult run_command(const std::vector<std::string>& argv, const std::filesystem::path& cwd = {});

std::string read_file(const std::filesystem::path& path);
void write_file(const std::filesystem::path& path, const std::string& text);

/// Path of a file under tests/data.
std::filesystem::path data_path(const std::string& relative);

}  // namespace demsa::test
