#include "orchestrator/cases/case_writer.hpp"

#include "orchestrator/experiments/case_files.hpp"
#include "orchestrator/experiments/physics.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/parameters.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"
#include "orchestrator/version.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <chrono>
#include <cmath>
#include <fstream>
#include <numbers>

namespace demsa::cases {

using util::shell_quote;

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::experiments;

namespace {

namespace fs = std::filesystem;

double contact_value(const Material& m, std::string_view key) {
  const auto member = material_member(key);
  assert(member && "contact parameter without a Material member");
  return m.*member;
}

/// "Young's modulus [Pa], LIGGGHTS youngsModulus": the comment of a contact parameter in params.liggghts.
std::string params_note(const ContactParameter& p) {
  const std::string unit = p.unit == "-" ? std::string{} : fmt::format(" [{}]", p.unit);
  return fmt::format("{}{}, LIGGGHTS {}", p.label, unit, p.liggghts);
}

void add_common_params(Params& p, const Material& m, const TimestepChoice& ts, const StudyConfig& c) {
  p.comment("contact parameters (paper eq. 1) and density");
  const RollingModel rolling = c.contact.rolling_model;
  for (const ContactParameter& cp : contact_parameters()) {
    const bool rolling_coefficient = cp.key == "mu_r_pp" || cp.key == "mu_r_pw";
    if (!rolling_coefficient || rolling == RollingModel::cdt) {
      p.number(std::string(cp.key), contact_value(m, cp.key), params_note(cp));
      continue;
    }
    const std::string pair = cp.key == "mu_r_pp" ? "particle-particle" : "particle-wall";
    p.number(std::string(cp.key), liggghts_rolling_coefficient(c.contact, contact_value(m, cp.key)),
             rolling == RollingModel::viscous
                 ? fmt::format("{} rolling viscosity mu_R [s*m], LIGGGHTS coefficientRollingViscosity", pair)
                 : fmt::format("{} rolling friction [-], LIGGGHTS coefficientRollingFriction ({})", pair,
                               rolling_model_name(rolling)));
  }
  if (rolling == RollingModel::epsd || rolling == RollingModel::epsd3)
    p.number("rolling_damping", c.contact.rolling_damping,
             "rolling viscous damping ratio [-], LIGGGHTS coefficientRollingViscousDamping");
  if (rolling == RollingModel::epsd3)
    p.number("rolling_stiffness", c.contact.rolling_stiffness,
             "rolling stiffness factor [-], LIGGGHTS rollingStiffness");
  p.number("density", m.density, "particle density [kg/m^3]");
  p.number("gravity", m.gravity, "|g| [m/s^2]");
  p.word("soft_particles", m.soft_particles ? "yes" : "no", "allow E < 5e6 Pa");
  p.word("hard_particles", m.hard_particles ? "yes" : "no", "allow E > 1e9 Pa");
  p.comment("integration");
  p.number("dt", ts.dt,
           ts.mode == TimestepMode::rayleigh ? fmt::format("time step [s] = {} x Rayleigh time", c.timestep.fraction)
                                             : std::string("time step [s], fixed"));
  p.number("rayleigh_time", ts.rayleigh_time, "Rayleigh time of the smallest particle [s]");
  p.number("skin", c.timestep.skin, "neighbor skin [m]");
  p.integer("thermo_steps", steps_for(0.01, ts.dt, "the thermo output interval"), "thermo output every 0.01 s");
}

/// case.json "material": the contact parameters in the paper's order, then density and gravity.
nlohmann::ordered_json material_json(const Material& m) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const ContactParameter& cp : contact_parameters()) j[std::string(cp.key)] = contact_value(m, cp.key);
  j["density"] = m.density;
  j["gravity"] = m.gravity;
  return j;
}

std::string run_script(const StudyConfig& c, const CaseRequest& request) {
  const std::string driver_command = experiments::of(c).driver_command(c);
  const bool driver = !driver_command.empty();
  std::string program;
  std::string find_demsa;
  if (driver) {
    assert(!request.demsa_executable.empty() && "a trial-step oedometer case needs the demsa executable");
    // The build that wrote the case is only a default, so that the folder can move to another machine.
    find_demsa = fmt::format(
        "# The trial-step loop runs inside demsa: $DEMSA if set, else the demsa that wrote this case; when that is\n"
        "# not an executable here (the folder moved to another machine), demsa from PATH.\n"
        "demsa_built={}\n"
        "demsa=\"${{DEMSA:-$demsa_built}}\"\n"
        "if ! command -v \"$demsa\" > /dev/null 2>&1; then\n"
        "  if ! command -v demsa > /dev/null 2>&1; then\n"
        "    echo \"run.sh: no demsa executable: $demsa is not one and demsa is not on PATH; set "
        "DEMSA=/path/to/demsa\" >&2\n"
        "    exit 127\n"
        "  fi\n"
        "  demsa=demsa\n"
        "fi\n",
        shell_quote(request.demsa_executable.string()));
    program = fmt::format("\"$demsa\" {} .", driver_command);
    // The viscous rolling model is in the library of scripts/build-liggghts.sh only: demsa, which loads
    // libliggghts.so.3 at run time as the dynamic loader finds it (driver/liggghts_library.hpp), finds that one.
    if (c.contact.rolling_model == RollingModel::viscous)
      if (const auto lib = liggghts_library_dir(c.run.liggghts))
        find_demsa += fmt::format(
            "# The LIGGGHTS library with the viscous rolling model (scripts/build-liggghts.sh).\n"
            "export LD_LIBRARY_PATH={}${{LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}}\n",
            shell_quote(lib->string()));
  } else {
    program =
        shell_quote(c.run.liggghts) + " -in " + k_case_input + " -log " + k_case_log + " -screen " + k_case_screen;
  }
  return fmt::format(
      "#!/bin/bash\n"
      "# Generated by demsa: runs this case from its own folder (cd into it and ./run.sh, or call it by path).\n"
      "# Exit status: LIGGGHTS's. Output: {log}, {screen}.\n"
      "set -u\n"
      "cd \"$(dirname \"$0\")\" || exit 2\n"
      "{find_demsa}"
      "# Open MPI refuses to run as root unless told to.\n"
      "root_flag=()\n"
      "if [ \"$(id -u)\" -eq 0 ]; then root_flag=(--allow-run-as-root); fi\n"
      "# Line-buffered output: the last lines before an MPI abort are not lost. No binding: Open MPI binds the ranks\n"
      "# of each mpirun to cores counted from core 0, so cases run side by side would all share the first cores.\n"
      "stdbuf -oL -eL {mpirun} ${{root_flag[@]+\"${{root_flag[@]}}\"}} --bind-to none -np {ranks} {program}\n"
      "status=$?\n"
      "exit $status\n",
      fmt::arg("log", k_case_log), fmt::arg("screen", k_case_screen), fmt::arg("mpirun", shell_quote(c.run.mpirun)),
      fmt::arg("ranks", c.run.ranks), fmt::arg("find_demsa", find_demsa), fmt::arg("program", program));
}

/// Entries of `dir` (none when it does not exist): the files a run writes first, then the others, each by name.
std::vector<std::string> folder_entries(const fs::path& dir) {
  std::vector<std::string> names;
  if (!fs::is_directory(dir)) return names;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  // What a run writes: the log and screen, and the outputs of every experiment.
  std::vector<std::string> outputs{k_case_log, k_case_screen};
  for (const Experiment* e : experiments::all())
    for (std::string& name : e->run_outputs()) outputs.push_back(std::move(name));
  std::stable_partition(names.begin(), names.end(), [&](const std::string& n) {
    return std::find(outputs.begin(), outputs.end(), n) != outputs.end();
  });
  return names;
}

/// "a, b, c and 4 more".
std::string some_of(const std::vector<std::string>& names, std::size_t shown = 3) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < shown; ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > shown) out += fmt::format(" and {} more", names.size() - shown);
  return out;
}

/// True when `file` lies inside `dir` (at any depth); both must exist.
bool lies_inside(const fs::path& file, const fs::path& dir) {
  std::error_code ec;
  const fs::path f = fs::canonical(file, ec);
  if (ec) return false;
  const fs::path d = fs::canonical(dir, ec);
  if (ec) return false;
  const auto [end_d, at_f] = std::mismatch(d.begin(), d.end(), f.begin(), f.end());
  return end_d == d.end();
}

/// Applies `existing` to the case folder before anything is written.
void prepare_folder(const StudyConfig& config, const fs::path& dir, ExistingCaseFiles existing) {
  if (fs::exists(dir) && !fs::is_directory(dir))
    throw UserError(fmt::format("{}: cannot write a case there: it is a file, not a folder", dir.string()));
  if (existing == ExistingCaseFiles::rewrite) return;
  const std::vector<std::string> names = folder_entries(dir);
  if (names.empty()) return;
  if (existing == ExistingCaseFiles::refuse) {
    throw UserError(fmt::format(
        "{}: the case folder is not empty ({}); files of an earlier run there would not match the new case: write "
        "the case into a new folder, or give --overwrite to empty this one first",
        dir.string(), some_of(names)));
  }
  // Only a case folder is ever emptied: `-o ~ --overwrite` must not cost anyone their home directory.
  if (!fs::exists(dir / k_case_json))
    throw UserError(
        fmt::format("{}: holds files ({}) but no {}: it is not a case folder, and --overwrite empties "
                    "only case folders; write the case into a new folder",
                    dir.string(), some_of(names), k_case_json));
  if (lies_inside(config.file, dir))
    throw UserError(fmt::format("{}: will not empty the folder that holds the study file {}; choose another folder",
                                dir.string(), config.file.string()));
  for (const std::string& name : names) {
    std::error_code ec;
    fs::remove_all(dir / name, ec);
    if (ec) throw UserError(fmt::format("{}: cannot remove: {}", (dir / name).string(), ec.message()));
  }
}

/// Removes what a write that failed left in the case folder, unless done(): the folder itself when the write created
/// it, its files otherwise (prepare_folder left it empty; with `rewrite` the caller empties the folder itself).
class PartialCase {
 public:
  PartialCase(fs::path dir, bool existed, ExistingCaseFiles existing)
      : m_dir(std::move(dir)), m_existed(existed), m_existing(existing) {}
  PartialCase(const PartialCase&) = delete;
  PartialCase& operator=(const PartialCase&) = delete;
  ~PartialCase() {
    if (m_done) return;
    std::error_code ec;
    if (!m_existed) {
      fs::remove_all(m_dir, ec);
    } else if (m_existing != ExistingCaseFiles::rewrite) {
      for (fs::directory_iterator it(m_dir, ec), end; !ec && it != end; it.increment(ec)) {
        std::error_code ignored;
        fs::remove_all(it->path(), ignored);
      }
    }
  }
  void done() { m_done = true; }

 private:
  fs::path m_dir;
  bool m_existed;
  ExistingCaseFiles m_existing;
  bool m_done = false;
};

}  // namespace

void clear_case_folder(const fs::path& folder) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(folder, ec))) return;
  const fs::path stale = folder.parent_path() / ".stale";
  fs::create_directories(stale, ec);
  if (ec) throw util::IoError(fmt::format("{}: cannot create: {}", stale.string(), ec.message()));
  // One demsa holds a study at a time (study::StudyLock): a clock reading and a count make the name unique.
  const auto clock = std::chrono::steady_clock::now().time_since_epoch().count();
  fs::path aside;
  for (int k = 0; aside.empty() || fs::exists(fs::symlink_status(aside, ec)); ++k)
    aside = stale / fmt::format("{}-{}-{}", folder.filename().string(), clock, k);
  fs::rename(folder, aside, ec);
  if (ec)
    throw util::IoError(fmt::format("{}: cannot move aside for a new attempt: {}", folder.string(), ec.message()));
  // This folder and what earlier attempts left: whatever is still being written to stays for a later call.
  for (fs::directory_iterator it(stale, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code ignored;
    fs::remove_all(it->path(), ignored);
  }
}

CaseRequest request_from_unit_point(const StudyConfig& config, int sample, const std::vector<double>& unit_point) {
  assert(unit_point.size() == config.parameters.size());
  CaseRequest r;
  r.sample = sample;
  r.unit_point = unit_point;
  for (std::size_t i = 0; i < unit_point.size(); ++i)
    r.physical.push_back(sobol::to_physical(unit_point[i], config.parameters[i].bounds));
  return r;
}

CaseRequest request_from_values(const StudyConfig& config, const std::vector<std::pair<std::string, double>>& values) {
  std::vector<double> unit(config.parameters.size(), 0.5);
  for (const auto& [name, value] : values) {
    const auto& names = contact_parameter_names();
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      std::string valid;
      for (const std::string& n : names) valid += (valid.empty() ? "" : ", ") + n;
      throw UserError(fmt::format("unknown parameter '{}' (valid: {})", name, valid));
    }
    bool varied = false;
    for (std::size_t i = 0; i < config.parameters.size(); ++i) {
      const ParameterRange& p = config.parameters[i];
      if (p.name != name) continue;
      varied = true;
      if (value < p.bounds.low || value > p.bounds.high)
        throw UserError(fmt::format("{} = {} lies outside its range [{}, {}] in {}", name, value, p.bounds.low,
                                    p.bounds.high, config.file.filename().string()));
      unit[i] = sobol::to_unit(value, p.bounds);
    }
    if (const ParameterTie* tie = find_tie(config.ties, name); !varied && tie)
      throw UserError(fmt::format("{} is tied to {} in {} (same_as): set {}", name, tie->partner,
                                  config.file.filename().string(), tie->partner));
    if (!varied)
      throw UserError(
          fmt::format("{} is not varied in {}; set it in [material] instead", name, config.file.filename().string()));
  }
  CaseRequest r = request_from_unit_point(config, -1, unit);
  // Exact values as typed (to_unit/to_physical round trip may differ in the last bit).
  for (const auto& [name, value] : values)
    for (std::size_t i = 0; i < config.parameters.size(); ++i)
      if (config.parameters[i].name == name) r.physical[i] = value;
  return r;
}

std::uint64_t replicate_assembly_seed(std::uint64_t study_seed, int point, int repeat) {
  // SplitMix64's output function (Steele, Lea, Flood 2014), applied to the study seed advanced by the golden gamma
  // once per (point, repeat) pair.
  const auto mix = [](std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  };
  constexpr std::uint64_t gamma = 0x9e3779b97f4a7c15ULL;
  std::uint64_t seed = mix(mix(study_seed + gamma) + static_cast<std::uint64_t>(point) * gamma +
                           static_cast<std::uint64_t>(repeat) * 0xd1b54a32d192ed03ULL);
  // GSL's MT19937 takes an unsigned long; keep the seed in 63 bits for TOML and SQLite readers.
  seed &= 0x7fffffffffffffffULL;
  return seed == study_seed ? seed ^ 1ULL : seed;
}

CaseSummary write_case(const StudyConfig& config, const CaseRequest& request, const fs::path& dir,
                       ExistingCaseFiles existing) {
  assert(request.physical.size() == config.parameters.size());
  const Experiment& experiment = experiments::of(config);
  const Material material = material_for(config, request.physical);
  const std::string study_file = config.file.filename().string();

  // The assembly first: its smallest radius sets the Rayleigh time.
  const std::uint64_t assembly_seed = request.replicate_point >= 0 ? request.assembly_seed : config.seed;
  const std::unique_ptr<CaseDraft> draft = experiment.draft(config, assembly_seed);
  const TimestepChoice ts = choose_timestep(config.timestep, material, draft->smallest_radius());
  std::vector<std::string> problems = liggghts_limit_violations(material, ts);
  if (experiment.limit_violations)
    for (std::string& p : experiment.limit_violations(config, material, ts)) problems.push_back(std::move(p));
  if (!problems.empty()) {
    std::string what = request.sample >= 0 ? fmt::format("sample {}", request.sample) : std::string("the case");
    std::string message = fmt::format("{} cannot run in LIGGGHTS: ", what);
    for (std::size_t i = 0; i < problems.size(); ++i) message += (i ? "; " : "") + problems[i];
    throw UserError(study_file, 0, message);
  }

  const bool existed = fs::exists(dir);
  prepare_folder(config, dir, existing);
  fs::create_directories(dir);
  PartialCase partial(dir, existed, existing);
  Params params;
  CaseWritten w;
  try {
    add_common_params(params, material, ts, config);
    w = draft->write(material, ts, params, dir);
  } catch (const UserError& e) {
    // A step count beyond what LIGGGHTS can run (experiments/physics.hpp: steps_for).
    const std::string what = request.sample >= 0 ? fmt::format("sample {}", request.sample) : std::string("the case");
    const std::string dt = ts.mode == TimestepMode::rayleigh
                               ? fmt::format("[timestep] fraction = {} of the Rayleigh time {:.4g} s",
                                             config.timestep.fraction, ts.rayleigh_time)
                               : fmt::format("[timestep] value = {} s", config.timestep.value);
    throw UserError(study_file, 0, fmt::format("{} cannot run: {} (the time step is {})", what, e.what(), dt));
  }
  write_text(dir / k_case_params, params.text());
  for (const char* include : {"system.liggghts", "contact.liggghts"})
    write_text(dir / include, with_rolling_model(template_text(include), config.contact));

  const fs::path script = dir / k_case_run_script;
  write_text(script, run_script(config, request));
  fs::permissions(script,
                  fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec | fs::perms::others_read |
                      fs::perms::others_exec,
                  fs::perm_options::replace);

  nlohmann::ordered_json parameters = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < config.parameters.size(); ++i)
    parameters[config.parameters[i].name] = request.physical[i];
  for (const ParameterTie& t : config.ties) parameters[t.name] = material.*material_member(t.name);  // = partner
  // A case of values set by hand has no design row: "sample": null.
  const nlohmann::ordered_json sample =
      request.sample >= 0 ? nlohmann::ordered_json(request.sample) : nlohmann::ordered_json(nullptr);
  nlohmann::ordered_json doc{{"study", config.name},
                             {"experiment", experiment.name},
                             {"sample", sample},
                             {"unit_point", request.unit_point},
                             {"parameters", parameters},
                             {"material", material_json(material)},
                             {"seed", config.seed},
                             {"dt", ts.dt},
                             {"dt_source", ts.mode == TimestepMode::rayleigh ? "rayleigh" : "fixed"},
                             {"dt_fraction_of_rayleigh", ts.fraction_of_rayleigh()},
                             {"rayleigh_time", ts.rayleigh_time},
                             {"ranks", config.run.ranks},
                             {"design_hash", design_hash(config)},
                             {"demsa_version", k_version},
                             {"liggghts_version", request.liggghts_version},
                             {"final_dump", experiment.final_dump},
                             {"assembly", w.assembly},
                             {std::string(experiment.name), w.experiment}};
  if (request.replicate_point >= 0)
    doc["replicate"] = {{"point", request.replicate_point},
                        {"repeat", request.replicate_repeat},
                        {"assembly_seed", request.assembly_seed}};
  write_text(dir / k_case_json, doc.dump(2) + "\n");

  partial.done();
  CaseSummary summary;
  summary.dir = dir;
  summary.material = material;
  summary.dt = ts.dt;
  summary.rayleigh_time = ts.rayleigh_time;
  summary.dt_source = ts.mode == TimestepMode::rayleigh ? "rayleigh" : "fixed";
  summary.particles = w.particles;
  summary.final_dump = std::string(experiment.final_dump);
  return summary;
}

}  // namespace demsa::cases
