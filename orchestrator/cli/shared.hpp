#pragma once
// What more than one command of cli/ needs: the Sobol' tables that `demsa run` and `demsa analyze` print, and the
// check of library options that come from the command line (`demsa postprocess`, `demsa compare`).
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/util/errors.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace demsa::cli {

/// Sample numbers separated by spaces: "3 5 7".
std::string sample_list(const std::vector<int>& samples);

/// Prints the first-order Sobol' table of every observable, the samples left out, and where the analysis is.
void print_analysis_tables(const analysis::AnalysisSummary& summary);

/// Runs `options.validate()` on options filled from the command line. The postprocess library reports a bad option
/// as std::invalid_argument, a programming error for its other callers; here the value came from the user, so it is
/// a util::UserError (exit 2), not an internal failure.
template <typename Options>
void validate_command_line(const Options& options) {
  try {
    options.validate();
  } catch (const std::invalid_argument& e) {
    throw util::UserError(e.what());
  }
}

}  // namespace demsa::cli
