#include "orchestrator/exec/progress.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <cmath>

namespace demsa::exec {

std::string format_duration(double seconds) {
  if (!(seconds >= 0)) return "?";
  if (seconds < 60) return fmt::format("{:.1f} s", seconds);
  const long s = std::lround(seconds);
  if (s < 3600) return fmt::format("{} min {:02d} s", s / 60, s % 60);
  return fmt::format("{} h {:02d} min", s / 3600, (s % 3600) / 60);
}

double estimate_remaining(int remaining, int parallel, double mean_case_seconds) {
  if (remaining <= 0) return 0.0;
  if (!(mean_case_seconds > 0) || parallel < 1) return -1.0;
  // Whole waves of `parallel` cases: the last, partly filled wave takes a full case time too.
  const int waves = (remaining + parallel - 1) / parallel;
  return waves * mean_case_seconds;
}

std::string progress_line(const ProgressCounts& c, double elapsed, double eta) {
  return fmt::format("[demsa] done {}/{}, running {}, failed {}, elapsed {}, ETA {}", c.done, c.total, c.running,
                     c.failed, format_duration(elapsed), eta < 0 ? std::string("?") : format_duration(eta));
}

Progress::Progress(std::FILE* out, bool live, double interval)
    : m_out(out), m_live(live), m_interval(interval), m_start(std::chrono::steady_clock::now()), m_last(m_start) {}

bool Progress::is_terminal(std::FILE* out) { return out != nullptr && ::isatty(::fileno(out)) == 1; }

double Progress::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
}

void Progress::update(const ProgressCounts& counts, double eta) {
  if (m_out == nullptr) return;
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - m_last).count();
  if (m_live) {
    if (m_printed && since < 0.2) return;
    fmt::print(m_out, "\r\033[K{}", progress_line(counts, elapsed(), eta));
  } else {
    if (m_printed && since < m_interval && counts.failed == m_last_failed) return;
    fmt::print(m_out, "{}\n", progress_line(counts, elapsed(), eta));
  }
  std::fflush(m_out);
  m_last = now;
  m_last_failed = counts.failed;
  m_printed = true;
}

void Progress::finish(const ProgressCounts& counts) {
  if (m_out == nullptr) return;
  if (m_live)
    fmt::print(m_out, "\r\033[K{}\n", progress_line(counts, elapsed(), 0.0));
  else
    fmt::print(m_out, "{}\n", progress_line(counts, elapsed(), 0.0));
  std::fflush(m_out);
}

}  // namespace demsa::exec
