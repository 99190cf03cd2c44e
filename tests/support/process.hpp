#pragma once
// Running the demsa binary in the background for tests that signal it (SIGINT, SIGKILL) while it works.
#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace demsa::test {

/// Starts the demsa binary built with the tests in the background with `args`: stdin from /dev/null (not a
/// terminal: it never asks), standard output and error appended to `log`. Returns its pid.
pid_t spawn_demsa(const std::vector<std::string>& args, const std::filesystem::path& log);

/// Waits for `pid` to end; its exit status, or 128 + signal when a signal killed it.
int wait_exit(pid_t pid);

/// Starts demsa with `args` `rounds` times and kills it with SIGKILL after a delay drawn uniformly from
/// [min_delay, max_delay] ms by an MT19937 seeded with `seed` (so a failure reproduces); output appended to `log`.
void kill_at_random_moments(const std::vector<std::string>& args, const std::filesystem::path& log, unsigned seed,
                            int rounds, int min_delay_ms, int max_delay_ms);

/// Polls `condition` every 20 ms until it holds (true) or `limit` has passed (false).
bool wait_until(const std::function<bool()>& condition, std::chrono::milliseconds limit = std::chrono::seconds(20));

}  // namespace demsa::test
