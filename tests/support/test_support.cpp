#include "support/test_support.hpp"

#include <fmt/core.h>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace demsa::test {
namespace fs = std::filesystem;

TempDir::TempDir() {
  const char* base = std::getenv("TMPDIR");
  fs::path root = base != nullptr && *base != '\0' ? fs::path(base) : fs::temp_directory_path();
  std::string pattern = (root / "demsa-test-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr)
    throw std::runtime_error("mkdtemp failed: " + std::string(std::strerror(errno)));
  m_path = pattern;
}

TempDir::~TempDir() {
  if (std::getenv("DEMSA_KEEP_TEST_DIRS") != nullptr) {
    fmt::print(stderr, "kept test dir {}\n", m_path.string());
    return;
  }
  std::error_code ec;
  fs::remove_all(m_path, ec);
}

CommandResult run_command(const std::vector<std::string>& argv, const fs::path& cwd) {
  int out_pipe[2];
  int err_pipe[2];
  if (::pipe(out_pipe) != 0 || ::pipe(err_pipe) != 0) throw std::runtime_error("pipe failed");
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    ::dup2(out_pipe[1], 1);
    ::dup2(err_pipe[1], 2);
    ::close(out_pipe[0]);
    ::close(err_pipe[0]);
    ::close(out_pipe[1]);
    ::close(err_pipe[1]);
    const int devnull = ::open("/dev/null", O_RDONLY);
    if (devnull >= 0) ::dup2(devnull, 0);
    if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) ::_exit(127);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);
  CommandResult result;
  pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
  int open_count = 2;
  char buffer[65536];
  while (open_count > 0) {
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || (fds[i].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
      const ssize_t n = ::read(fds[i].fd, buffer, sizeof buffer);
      if (n > 0) {
        (i == 0 ? result.out : result.err).append(buffer, static_cast<size_t>(n));
      } else {
        ::close(fds[i].fd);
        fds[i].fd = -1;
        --open_count;
      }
    }
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

std::string project_liggghts(std::string& why) {
  const fs::path script = fs::path(DEMSA_SOURCE_DIR) / "scripts" / "build-liggghts.sh";
  const CommandResult p = run_command({"bash", script.string(), "--print-prefix"});
  std::string prefix = p.out;
  while (!prefix.empty() && (prefix.back() == '\n' || prefix.back() == ' ')) prefix.pop_back();
  const fs::path exe = fs::path(prefix) / "bin" / "liggghts";
  if (p.exit_code == 0 && fs::exists(fs::path(prefix) / "demsa-liggghts.txt") && fs::exists(exe)) return exe.string();
  why = "no LIGGGHTS of scripts/build-liggghts.sh for this checkout: run the script (" + p.err + ")";
  return "";
}

CommandResult run_demsa(const std::vector<std::string>& args, const fs::path& cwd) {
  std::vector<std::string> argv{DEMSA_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_command(argv, cwd);
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_file(const fs::path& path, const std::string& text) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + path.string());
  out << text;
}

fs::path data_path(const std::string& relative) { return fs::path(DEMSA_TEST_DATA_DIR) / relative; }

ScopedEnv::ScopedEnv(std::string name, const std::string& value) : m_name(std::move(name)) {
  ::setenv(m_name.c_str(), value.c_str(), 1);
}

ScopedEnv::~ScopedEnv() { ::unsetenv(m_name.c_str()); }

FakeLiggghtsEnvironment::FakeLiggghtsEnvironment(const std::string& plan, const fs::path& state, double seconds) {
  ::setenv("FAKE_LIGGGHTS_PLAN", plan.c_str(), 1);
  ::setenv("FAKE_LIGGGHTS_STATE", state.c_str(), 1);
  ::setenv("FAKE_LIGGGHTS_SECONDS", fmt::format("{}", seconds).c_str(), 1);
}

FakeLiggghtsEnvironment::~FakeLiggghtsEnvironment() {
  ::unsetenv("FAKE_LIGGGHTS_PLAN");
  ::unsetenv("FAKE_LIGGGHTS_STATE");
  ::unsetenv("FAKE_LIGGGHTS_SECONDS");
}

std::vector<std::string> run_args(const TempDir& tmp, const std::vector<std::string>& more) {
  std::vector<std::string> args{"run", (tmp / "study.toml").string(), "--dir", (tmp / "study").string()};
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

std::map<int, int> starts_per_sample(const fs::path& state) {
  std::map<int, int> starts;
  std::ifstream in(state / "starts.log");
  int sample = 0;
  while (in >> sample) ++starts[sample];
  return starts;
}

std::string fake_liggghts_run_lines() {
  const fs::path dir = fs::path(DEMSA_SOURCE_DIR) / "tests" / "integration" / "fake_liggghts";
  return fmt::format("liggghts = \"{}\"\nmpirun = \"{}\"\n", (dir / "liggghts").string(), (dir / "mpirun").string());
}

std::string StudyToml::text() const {
  std::string text = fmt::format("\n[study]\nname = \"{}\"\nexperiment = \"{}\"\nseed = {}\n", name, experiment, seed);
  text += fmt::format("\n[design]\nmethod = \"{}\"\nsamples = {}\n", method, samples);
  text += "\n[parameters]\n" + parameters;
  if (!tables.empty()) text += "\n" + tables;
  if (!run.empty()) text += "\n[run]\n" + run;
  if (!analysis.empty()) text += "\n[analysis]\n" + analysis;
  return text + extra;
}

}  // namespace demsa::test
