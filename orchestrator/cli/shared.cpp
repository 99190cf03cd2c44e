#include "orchestrator/cli/shared.hpp"

#include <fmt/core.h>

namespace demsa::cli {

std::string sample_list(const std::vector<int>& samples) {
  std::string text;
  for (int v : samples) {
    if (!text.empty()) text += ' ';
    text += std::to_string(v);
  }
  return text;
}

void print_analysis_tables(const analysis::AnalysisSummary& summary) {
  for (const analysis::ObservableAnalysis& o : summary.observables)
    fmt::print("\n{}", analysis::s1_table_text(summary, o));
  if (!summary.samples_left_out.empty())
    fmt::print("\nleft out of the analysis (not done): samples {}\n", sample_list(summary.samples_left_out));
  fmt::print("\ntables, metamodels and indices with confidence intervals: {}\n", summary.out_dir.string());
}

}  // namespace demsa::cli
