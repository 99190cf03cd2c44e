#include "orchestrator/exec/executor.hpp"

#include "orchestrator/util/errors.hpp"

#if __has_include("orchestrator/exec/slurm/executor.hpp")
#include "orchestrator/exec/slurm/executor.hpp"
#define DEMSA_HAVE_SLURM_EXECUTOR 1
#endif

namespace demsa::exec {

using namespace demsa::util;
using namespace demsa::study;

std::unique_ptr<Executor> make_executor(const RunSettings& run, const std::filesystem::path& study_dir) {
  switch (run.executor) {
    case ExecutorKind::local:
      return make_local_executor(run, study_dir);
    case ExecutorKind::slurm:
#ifdef DEMSA_HAVE_SLURM_EXECUTOR
      return make_slurm_executor(run, study_dir);
#else
      throw UserError("[run] executor = \"slurm\": this demsa was built without the SLURM executor; use \"local\"");
#endif
  }
  throw UserError("[run] executor: unknown value");
}

}  // namespace demsa::exec
