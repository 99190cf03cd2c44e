#include "orchestrator/analysis/measured_target.hpp"

#include "orchestrator/util/csv.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>

#include <cmath>

namespace demsa::analysis {

using util::UserError;

std::string MeasuredTarget::label() const { return study.empty() ? name : study + ":" + name; }

std::string MeasuredTarget::text() const {
  return sd > 0 ? fmt::format("{}={:.12g}±{:.12g}", label(), value, sd) : fmt::format("{}={:.12g}", label(), value);
}

std::string curve_point_name(const std::string& name, std::size_t k) { return fmt::format("{}_{}", name, k); }

namespace {

/// d₂(n), the expected range of n standard normal values (Tippett 1925; the control-chart constants of
/// ASTM E2587): σ ≈ range / d₂(n).
double d2(int n) {
  static const double table[] = {1.128, 1.693, 2.059, 2.326, 2.534, 2.704, 2.847, 2.970, 3.078, 3.173,
                                 3.258, 3.336, 3.407, 3.472, 3.532, 3.588, 3.640, 3.689, 3.735};
  return table[n - 2];
}

}  // namespace

std::vector<MeasuredTarget> read_measured_curve(const std::string& study, const std::string& name,
                                                const std::filesystem::path& file) {
  const util::CsvTable table = util::read_csv(file);
  const int mean = table.column_index("mean");
  std::vector<MeasuredTarget> out;
  for (int r = 0; r < table.rows(); ++r) {
    const std::string where = fmt::format("{}:{}", file.string(), table.lines[r]);
    double sd = 0.0;
    if (table.has_column("sd")) {
      sd = table.values(r, table.column_index("sd"));
    } else if (table.has_column("low") && table.has_column("high") && table.has_column("tests")) {
      const double low = table.values(r, table.column_index("low"));
      const double high = table.values(r, table.column_index("high"));
      const double tests = table.values(r, table.column_index("tests"));
      if (tests != std::floor(tests) || tests < 2 || tests > 20)
        throw UserError(fmt::format("{}: column 'tests': {} must be a whole number in 2..20", where, tests));
      if (high < low) throw UserError(fmt::format("{}: high {} is below low {}", where, high, low));
      sd = (high - low) / d2(static_cast<int>(tests));
    } else {
      throw UserError(fmt::format("{}: needs a column 'sd', or the columns 'low', 'high' and 'tests' (columns: {})",
                                  file.string(), util::join(table.columns)));
    }
    if (!(sd > 0))
      throw UserError(
          fmt::format("{}: {} {:g} must be > 0 (a measurement's spread)", where,
                      table.has_column("sd") ? "column 'sd':" : "the spread (high - low) / d2(tests) =", sd));
    out.push_back({study, table.rows() == 1 ? name : curve_point_name(name, static_cast<std::size_t>(r) + 1),
                   table.values(r, mean), sd});
  }
  return out;
}

}  // namespace demsa::analysis
