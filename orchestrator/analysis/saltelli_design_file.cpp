#include "orchestrator/analysis/saltelli_design_file.hpp"

#include "orchestrator/util/errors.hpp"
#include "sobol/error.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <span>

namespace demsa::analysis {

using util::CsvTable;
using util::UserError;

void write_saltelli_design(const std::string& file, const sobol::SaltelliDesign& design, const Eigen::MatrixXd& values,
                           const std::vector<std::string>& names) {
  // Block and replicate are computed on the way (block_codes() order), never held for every row.
  const int extra = design.replicates > 1 ? 2 : 1;  // 'block' and, with replicates, 'replicate' (1..R)
  const Eigen::Index per_replicate = design.base / design.replicates;
  std::vector<std::string> header{"block"};
  if (extra == 2) header.emplace_back("replicate");
  header.insert(header.end(), names.begin(), names.end());
  util::write_csv_rows(file, header, values.rows(), [&](Eigen::Index r, std::span<double> cells) {
    cells[0] = static_cast<double>(r / design.base);
    if (extra == 2) cells[1] = static_cast<double>(1 + (r % design.base) / per_replicate);
    for (Eigen::Index k = 0; k < values.cols(); ++k) cells[static_cast<std::size_t>(extra + k)] = values(r, k);
  });
}

CsvTable read_saltelli_csv(const std::string& file) {
  util::CsvReadOptions options;
  options.require_varying = true;
  return util::read_csv(file, options);
}

int SaltelliDesignFile::replicates() const {
  return replicate.empty() ? 1 : 1 + *std::max_element(replicate.begin(), replicate.end());
}

int SaltelliDesignFile::base() const {
  return static_cast<int>(std::count(codes.begin(), codes.end(), 0)) / replicates();
}

SaltelliDesignFile saltelli_design_of(CsvTable table, const std::vector<std::string>& response_columns) {
  SaltelliDesignFile design;
  design.table = std::move(table);
  const CsvTable& t = design.table;
  design.block_column = t.column_index("block");
  for (int k = 0; k < static_cast<int>(t.columns.size()); ++k)
    if (t.columns[static_cast<std::size_t>(k)] == "replicate") design.replicate_column = k;
  const auto is_response = [&](int k) {
    return std::find(response_columns.begin(), response_columns.end(), t.columns[static_cast<std::size_t>(k)]) !=
           response_columns.end();
  };
  for (int k = 0; k < static_cast<int>(t.columns.size()); ++k)
    if (k != design.block_column && k != design.replicate_column && !is_response(k)) {
      design.parameters.push_back(t.columns[static_cast<std::size_t>(k)]);
      design.parameter_columns.push_back(k);
    }
  const int d = static_cast<int>(design.parameters.size());
  if (d < 1) t.fail(-1, -1, "no parameter column besides 'block'");
  design.codes.resize(static_cast<std::size_t>(t.rows()));
  for (int r = 0; r < t.rows(); ++r) {
    const double c = t.values(r, design.block_column);
    if (c != std::floor(c) || c < 0 || c > 2 * d + 1)
      t.fail(r, design.block_column,
             fmt::format("'{}' is not a block code 0..{} (0 = A, 1 = B, 1+i = AB_i, 1+{}+i = BA_i)", c, 2 * d + 1, d));
    design.codes[static_cast<std::size_t>(r)] = static_cast<int>(c);
  }
  // The parameter values must form a Saltelli design (AB_i from A and B, A and B independent): indices computed
  // from anything else are wrong without any sign in the numbers.
  Eigen::MatrixXd x(t.rows(), d);
  for (int k = 0; k < d; ++k) x.col(k) = t.values.col(design.parameter_columns[static_cast<std::size_t>(k)]);
  try {
    sobol::check_saltelli_inputs(x, design.codes, d);
  } catch (const sobol::DataError& e) {
    t.fail(e.row(),
           e.column() >= 0 ? design.parameter_columns[static_cast<std::size_t>(e.column())] : design.block_column,
           e.detail());
  } catch (const sobol::InputError& e) {
    throw UserError(t.file, 0, e.what());
  }
  if (design.replicate_column >= 0) {
    std::vector<long long> labels(static_cast<std::size_t>(t.rows()));
    for (int r = 0; r < t.rows(); ++r) {
      const double v = t.values(r, design.replicate_column);
      if (v != std::floor(v) || std::abs(v) > 1e15)
        t.fail(r, design.replicate_column, fmt::format("'{}' is not a replicate number (an integer)", v));
      labels[static_cast<std::size_t>(r)] = static_cast<long long>(v);
    }
    try {
      design.replicate = sobol::base_row_replicates(design.codes, labels, d);
    } catch (const sobol::DataError& e) {
      t.fail(e.row(), design.replicate_column, e.detail());
    }
  }
  return design;
}

}  // namespace demsa::analysis
