#pragma once
// Progress of a study run on stderr: on a terminal one live line rewritten in place (done, running, failed, total,
// elapsed, ETA); otherwise (a log file, CI) one plain line every `interval` seconds and at each change of the
// failed count.
#include <chrono>
#include <cstdio>
#include <string>

namespace demsa::exec {

struct ProgressCounts {
  int done = 0;
  int running = 0;
  int failed = 0;
  int total = 0;
};

/// "12.3 s", "4 min 05 s", "2 h 03 min".
std::string format_duration(double seconds);

/// ETA [s] for `remaining` cases at `parallel` at once from the mean wall time per case, or a negative number when
/// nothing is known yet.
double estimate_remaining(int remaining, int parallel, double mean_case_seconds);

/// The text of one progress line (no newline).
std::string progress_line(const ProgressCounts& counts, double elapsed, double eta);

class Progress {
 public:
  /// `out` is where lines go; `live` = rewrite one line (terminal) or print periodic lines.
  Progress(std::FILE* out, bool live, double interval);
  /// Whether `out` is a terminal.
  static bool is_terminal(std::FILE* out);
  /// Shows the counts (rate-limited: a live line at most 5 times a second, log lines every `interval`).
  void update(const ProgressCounts& counts, double eta);
  /// Final line (always printed), then a newline on a terminal.
  void finish(const ProgressCounts& counts);
  double elapsed() const;

 private:
  std::FILE* m_out;
  bool m_live;
  double m_interval;
  std::chrono::steady_clock::time_point m_start;
  std::chrono::steady_clock::time_point m_last;
  int m_last_failed = 0;
  bool m_printed = false;
};

}  // namespace demsa::exec
