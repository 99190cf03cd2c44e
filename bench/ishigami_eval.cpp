// Ishigami's function (Ishigami & Homma 1990) on every row of a design CSV, as a compiled simulator would evaluate
// it: reads the CSV on stdin (a header naming x1, x2, x3 among its columns), writes "y" and one value per row on
// stdout (shortest round-trip decimal). Used by bench/saltelli_pipeline.py --evaluator compiled.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/compile.h>
#include <fmt/format.h>

int main() {
  // The whole input at once: the design of N = 2^14 is 6.5 MB.
  std::string text;
  char chunk[1 << 16];
  for (std::size_t got; (got = std::fread(chunk, 1, sizeof chunk, stdin)) > 0;) text.append(chunk, got);
  std::string_view rest = text;
  const auto next_line = [&rest](std::string_view& line) {
    if (rest.empty()) return false;
    const std::size_t end = rest.find('\n');
    line = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    return true;
  };
  std::string_view line;
  if (!next_line(line)) {
    std::fputs("ishigami_eval: empty input\n", stderr);
    return 2;
  }
  // Column of x1, x2, x3 in the header.
  int col[3] = {-1, -1, -1};
  int k = 0;
  for (std::size_t start = 0;; ++k) {
    const std::size_t end = line.find(',', start);
    const std::string_view name = line.substr(start, end - start);
    for (int j = 0; j < 3; ++j)
      if (name == fmt::format("x{}", j + 1)) col[j] = k;
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  for (int j = 0; j < 3; ++j)
    if (col[j] < 0) {
      std::fprintf(stderr, "ishigami_eval: no column x%d in the header\n", j + 1);
      return 2;
    }
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out), "y\n");
  std::vector<double> cell(static_cast<std::size_t>(k) + 1);
  long row = 1;
  while (next_line(line)) {
    ++row;
    if (line.empty()) continue;
    const char* p = line.data();
    const char* const last = line.data() + line.size();
    for (std::size_t c = 0; c < cell.size(); ++c) {
      const auto [next, ec] = std::from_chars(p, last, cell[c]);
      if (ec != std::errc()) {
        std::fprintf(stderr, "ishigami_eval: line %ld: not a number in column %zu\n", row, c + 1);
        return 2;
      }
      p = next < last ? next + 1 : last;
    }
    const double x1 = cell[static_cast<std::size_t>(col[0])], x2 = cell[static_cast<std::size_t>(col[1])],
                 x3 = cell[static_cast<std::size_t>(col[2])];
    const double s = std::sin(x2), x3sq = x3 * x3;
    fmt::format_to(std::back_inserter(out), FMT_COMPILE("{}\n"),
                   std::sin(x1) + 7 * s * s + 0.1 * x3sq * x3sq * std::sin(x1));
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  return 0;
}
