#include "orchestrator/exec/point_run.hpp"

#include "orchestrator/cases/case_writer.hpp"
#include "orchestrator/exec/case_vtk.hpp"
#include "orchestrator/exec/executor.hpp"
#include "orchestrator/exec/liggghts_locator.hpp"
#include "orchestrator/exec/measure.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/process.hpp"

#include <fmt/core.h>

#include <chrono>

namespace demsa::exec {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::cases;

namespace fs = std::filesystem;

study::PointRun run_point(const study::StudyConfig& config, const fs::path& where, const std::vector<double>& unit) {
  study::PointRun run;
  const fs::path folder = fs::absolute(where);
  clear_case_folder(folder);
  cases::CaseRequest request = cases::request_from_unit_point(config, -1, unit);
  request.demsa_executable = util::self_executable();
  if (const auto info = query_liggghts()) request.liggghts_version = info->version;
  cases::write_case(config, request, folder);
  run.folder = folder;

  std::unique_ptr<Executor> executor = make_local_executor(config.run, folder.parent_path());
  const auto start = std::chrono::steady_clock::now();
  executor->submit({CaseTask{-1, 1, folder}});
  std::vector<FinishedCase> finished;
  while (finished.empty()) finished = executor->poll(std::chrono::milliseconds(1000));
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const CaseExit& exit = finished.front().exit;
  if (exit.exit_code != 0) {
    run.error = exit.timed_out    ? fmt::format("the case timed out after {} s", config.run.timeout)
                : exit.signal > 0 ? fmt::format("the case was killed by signal {}", exit.signal)
                                  : fmt::format("the case ended with status {}", exit.exit_code);
    run.error += fmt::format("; see {}", (folder / study::k_run_output_file).string());
    return run;
  }
  try {
    run.observables = measure_case(folder);
    write_case_vtk_or_warn(folder);
  } catch (const std::exception& e) {
    run.error = fmt::format("the case ran but could not be measured: {}", e.what());
  }
  return run;
}

}  // namespace demsa::exec
