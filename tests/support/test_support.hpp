#pragma once
// Helpers shared by the tests: a temporary directory per test, running the demsa binary, reading files.
#include <filesystem>
#include <map>
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

/// bin/liggghts of this checkout's build by scripts/build-liggghts.sh (its --print-prefix, with the marker file
/// demsa-liggghts.txt); "" with the reason in `why` when it is absent.
std::string project_liggghts(std::string& why);

std::string read_file(const std::filesystem::path& path);
void write_file(const std::filesystem::path& path, const std::string& text);

/// The message of the `E` that `f()` throws; "" when it throws nothing (any other exception passes through).
template <class E, class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}

/// Path of a file under tests/data.
std::filesystem::path data_path(const std::string& relative);

/// An environment variable set for one test and removed at its end (FAKE_LIGGGHTS_NOISE, FAKE_LIGGGHTS_DRIFT).
struct ScopedEnv {
  ScopedEnv(std::string name, const std::string& value);
  ~ScopedEnv();
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string m_name;
};

/// The fake LIGGGHTS's environment (tests/integration/fake_liggghts) for one test, removed again at the end: `plan`
/// (FAKE_LIGGGHTS_PLAN, "" = no failures), `state` (FAKE_LIGGGHTS_STATE: its starts.log and markers) and the
/// seconds each case takes (FAKE_LIGGGHTS_SECONDS).
struct FakeLiggghtsEnvironment {
  FakeLiggghtsEnvironment(const std::string& plan, const std::filesystem::path& state, double seconds);
  ~FakeLiggghtsEnvironment();
  FakeLiggghtsEnvironment(const FakeLiggghtsEnvironment&) = delete;
  FakeLiggghtsEnvironment& operator=(const FakeLiggghtsEnvironment&) = delete;
};

/// How often the fake LIGGGHTS started each sample: the lines of STATE/starts.log (none when it does not exist).
std::map<int, int> starts_per_sample(const std::filesystem::path& state);

/// `demsa run TMP/study.toml --dir TMP/study` followed by `more`.
std::vector<std::string> run_args(const TempDir& tmp, const std::vector<std::string>& more);

/// [run] lines that run the cases with the fake LIGGGHTS and mpirun of tests/integration/fake_liggghts
/// (`liggghts = ...` and `mpirun = ...`).
std::string fake_liggghts_run_lines();

/// The text of a study file, table by table: [study], [design], [parameters], the experiment's own tables, [run],
/// [analysis], then `extra` as is. A table body is TOML lines; an empty [run] or [analysis] body leaves the table out.
struct StudyToml {
  std::string name = "synthetic";   ///< [study] name
  std::string experiment = "pile";  ///< [study] experiment
  int seed = 7;                     ///< [study] seed
  std::string method = "lhs";       ///< [design] method
  int samples = 10;                 ///< [design] samples
  std::string parameters = "mu_pp = { low = 0.7, high = 1.9 }\nmu_r_pp = { low = 0.05, high = 0.5 }\n";  ///< body
  std::string tables = "";  ///< the experiment's tables with their headers ([pile], [oedometer], [material]); may be ""
  std::string run = "";     ///< body of [run]
  std::string analysis = "metamodels = [\"rsm2\", \"rbf-cubic\"]\n";  ///< body of [analysis]
  std::string extra = "";                                             ///< appended after everything else

  std::string text() const;
};

}  // namespace demsa::test
