#include "orchestrator/experiments/oedometer/driver.hpp"

#include "orchestrator/driver/liggghts_library.hpp"
#include "orchestrator/experiments/oedometer/oedometer.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

namespace demsa::experiments::oedometer {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::driver;

namespace {

/// MPI_Init for the life of the object and MPI_Finalize at its end, also when the driver throws (run_cli() then
/// prints the error after MPI has been shut down).
class MpiSession {
 public:
  explicit MpiSession(const LiggghtsLibrary& lib) : m_lib(lib) {
    int initialized = 0;
    m_lib.mpi_initialized(&initialized);
    if (!initialized) m_lib.mpi_init(nullptr, nullptr);
  }
  ~MpiSession() {
    int finalized = 0;
    m_lib.mpi_finalized(&finalized);
    if (!finalized) m_lib.mpi_finalize();
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const {
    int rank = 0;
    m_lib.mpi_comm_rank(m_lib.comm_world, &rank);
    return rank;
  }

 private:
  const LiggghtsLibrary& m_lib;
};

/// One LIGGGHTS instance on MPI_COMM_WORLD.
class Liggghts {
 public:
  explicit Liggghts(const LiggghtsLibrary& lib) : m_lib(lib) {
    std::vector<std::string> args{"liggghts", "-log", k_case_log, "-screen", k_case_screen};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    m_lib.open(static_cast<int>(argv.size()), argv.data(), m_lib.comm_world, &m_lmp);
  }
  ~Liggghts() { m_lib.close(m_lmp); }
  Liggghts(const Liggghts&) = delete;
  Liggghts& operator=(const Liggghts&) = delete;

  void command(const std::string& line) { m_lib.command(m_lmp, line.c_str()); }
  /// `include` sent as a command is only queued; files go through lammps_file.
  void file(const std::string& path) { m_lib.file(m_lmp, path.c_str()); }
  /// Element i (0-based) of a fix's global vector; LIGGGHTS mallocs the value.
  double fix_vector(const std::string& id, int i) {
    auto* p = static_cast<double*>(m_lib.extract_fix(m_lmp, id.c_str(), 0, 1, i, 0));
    const double v = p ? *p : NAN;
    std::free(p);
    return v;
  }
  double variable(const std::string& name) {
    std::string n = name;
    auto* p = static_cast<double*>(m_lib.extract_variable(m_lmp, n.data(), nullptr));
    const double v = p ? *p : NAN;
    std::free(p);
    return v;
  }

 private:
  const LiggghtsLibrary& m_lib;
  void* m_lmp = nullptr;
};

}  // namespace

TrialStepOptions read_trial_step_options(const std::filesystem::path& case_dir) {
  const std::filesystem::path file = case_dir / k_case_json;
  std::ifstream in(file);
  if (!in) throw UserError(file.string() + ": cannot read the case description");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
    const nlohmann::json& o = doc.at("oedometer");
    if (!o.contains("trial_step"))
      throw UserError(file.string() + ": not a trial-step oedometer case (plate_mode is not \"trial-step\")");
    const nlohmann::json& t = o.at("trial_step");
    TrialStepOptions options;
    options.loads = o.at("loads_N").get<std::vector<double>>();
    options.tolerance = o.at("load_tolerance_N").get<double>();
    options.trial_steps = t.at("trial_steps").get<long>();
    options.relax_steps = t.at("relax_steps").get<long>();
    options.reduction = t.at("trial_reduction").get<double>();
    options.step0 = t.at("trial_step0_m").get<double>();
    options.floor = t.at("trial_floor").get<double>();
    options.max_trials = t.at("max_trials").get<int>();
    options.dt = doc.at("dt").get<double>();
    return options;
  } catch (const nlohmann::json::exception& e) {
    throw UserError(file.string() + ": " + e.what());
  }
}

double reduced_trial_step(const TrialStepOptions& options, double step, double load, double residual) {
  return std::max(options.floor * options.step0, step * options.reduction * load / (load + residual));
}

int drive_oedometer(const std::filesystem::path& case_dir) {
  const TrialStepOptions options = read_trial_step_options(case_dir);
  const LiggghtsLibrary lib = load_liggghts_library();
  const MpiSession mpi(lib);
  std::filesystem::current_path(case_dir);
  const bool writer = mpi.rank() == 0;

  Liggghts lmp(lib);
  lmp.file(k_case_input);  // pour, settle, place the plate (oedometer_trial.liggghts)
  double z = lmp.variable("plate_z0");

  std::ofstream history;
  if (writer) {
    history.open(k_plate_history, std::ios::trunc);
    history << "# demsa trial-step load plate (paper §4): one row per trial; step counts every integration step\n"
               "# since loading began (restored trials included); accepted 0 = overshoot, backup restored\n"
               "# step load_N plate_z_m force_N trial delta_m accepted\n";
  }
  const auto append_state = [&](double load, double force, bool converged) {
    if (!writer) return;
    std::ofstream states(k_plate_states, std::ios::app);
    states << fmt::format("{:.10g} {:.10g} {:.10g} {}\n", load, z, force, converged ? 1 : 0);
  };

  long steps = 0;
  bool all_converged = true;
  // The backup is written only when the state has moved on since it was written. Right after a restore the state is
  // the backup's, and LIGGGHTS 3.8.0 must not write a restart then: FixContactHistoryMesh::write_restart sorts the
  // mesh contact histories up to each particle's current mesh-neighbour count before any run has rebuilt them for
  // it (pre_exchange skips that sort while `recent_restart` is set; write_restart does not), a read past the end
  // that crashed the trial-step plate at random.
  bool backup_is_current = false;
  for (const double load : options.loads) {
    double step = options.step0;
    double force = NAN;
    bool converged = false;
    for (int trial = 1; trial <= options.max_trials && !converged; ++trial) {
      if (!backup_is_current) lmp.command("write_restart backup.restart");
      backup_is_current = true;
      const double z_backup = z;
      // Trial move: the plate travels δ down at constant speed during the n_s steps.
      lmp.command(fmt::format("fix trial_move all move/mesh mesh plate linear 0. 0. {:.17g}",
                              -step / (static_cast<double>(options.trial_steps) * options.dt)));
      lmp.command(fmt::format("run {}", options.trial_steps));
      backup_is_current = false;
      lmp.command("unfix trial_move");
      z -= step;
      steps += options.trial_steps;
      force = lmp.fix_vector("plate", 2);
      bool accepted = true;
      if (force > load) {
        lmp.command(fmt::format("run {}", options.relax_steps));
        steps += options.relax_steps;
        force = lmp.fix_vector("plate", 2);
        const double residual = std::fabs(force - load);
        if (residual <= options.tolerance) {
          converged = true;
        } else if (force > load) {
          accepted = false;
          if (writer) {
            history << fmt::format("{} {:.10g} {:.10g} {:.10g} {} {:.6g} 0\n", steps, load, z, force, trial, step);
          }
          lmp.command("clear");
          z = z_backup;
          lmp.command(fmt::format("variable plate_z equal {:.17g}", z));
          lmp.command("variable restart_file string backup.restart");
          lmp.file("params.liggghts");
          lmp.file("oedometer_restore.liggghts");
          backup_is_current = true;  // the state is the backup's again
          step = reduced_trial_step(options, step, load, residual);
        }
      }
      if (accepted && writer)
        history << fmt::format("{} {:.10g} {:.10g} {:.10g} {} {:.6g} 1\n", steps, load, z, force, trial, step);
      if (writer) history.flush();
    }
    if (!converged) {
      // The last restore left the backup state: its force is read after one step (never right after a
      // restore, where the mesh force is not yet computed).
      lmp.command("run 1");
      backup_is_current = false;
      steps += 1;
      force = lmp.fix_vector("plate", 2);
    }
    all_converged = all_converged && converged;
    append_state(load, force, converged);
  }
  lmp.command(
      fmt::format("write_dump all custom {} id type x y z radius vx vy vz modify sort id format "
                  "\"%d %d %.10g %.10g %.10g %.10g %.10g %.10g %.10g\"",
                  k_final_dump));
  if (writer) std::filesystem::remove("backup.restart");
  return all_converged ? 0 : 1;
}

}  // namespace demsa::experiments::oedometer
