// The core sections of the study file (those every experiment has): their rows and their prose for
// docs/reference/study-file.md (settings.hpp's core_settings() and core_sections()). The table's machinery (lookup,
// hints, hash, markdown) is settings.cpp's; each experiment's rows are in its folder.
#include "orchestrator/study/settings.hpp"

#include "orchestrator/study/setting_row.hpp"

#include "orchestrator/study/parameters.hpp"
#include "orchestrator/util/log.hpp"
#include "sobol/design.hpp"
#include "sobol/enum_names.hpp"
#include "sobol/error.hpp"
#include "sobol/metamodel.hpp"
#include "sobol/metamodel_sobol.hpp"
#include "sobol/saltelli.hpp"
#include "sobol/scaling.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>
#include <utility>

namespace demsa::study {

namespace {

// Upper bounds of the settings that size what demsa holds in memory (setting_row.hpp has the shared ones).
constexpr double k_max_samples = 100000;
constexpr double k_max_base_samples = sobol::k_max_base_samples;
constexpr double k_max_bootstrap = 100000;
// Coulomb and rolling coefficients: far above any measured value (rolling coefficients of `viscous` in mm·ms reach a
// few units), so that a value that is a typo of its exponent is refused at its line.
const SettingBounds k_friction_bounds = between(0, true, 10, true);
const SettingBounds k_rolling_bounds = between(0, true, 1000, true);

#define FIELD(path) \
  [](auto& c) -> auto& { return c.path; }

const Setting& material_row(const std::vector<Setting>& rows, const std::string& key) {
  for (const Setting& s : rows)
    if (s.section == "material" && s.key == key) return s;
  assert(false && "no [material] row for a contact parameter");
  return rows.front();
}

std::vector<Setting> build_core_settings() {
  using E = SettingEffect;
  std::vector<Row> rows;
  const auto add = [&](Row& row) { rows.push_back(std::move(row)); };

  // [study]
  add(Row("study", "name")
          .string(FIELD(name))
          .non_empty()
          .check([](const SettingValue& v) {
            // `calibrate --target STUDY:NAME=V±E` and `plan --sd STUDY:NAME=SD` split at the first ':' and the
            // last '=': a study named with either could not be named there.
            const std::string& text = std::get<std::string>(v);
            if (const std::size_t at = text.find_first_of(":="); at != std::string::npos)
              throw SettingError(fmt::format("'{}' holds '{}': a STUDY:NAME target could not name it", text, text[at]));
          })
          .range("non-empty, without ':' or '='")
          .required()
          .default_text("— (required)")
          .doc("study name (the STUDY of `calibrate`'s and `plan`'s STUDY:NAME)"));
  // The experiments' names are the table's (SettingsTable's constructor makes this row an enumeration of them).
  add(Row("study", "experiment")
          .string(FIELD(experiment))
          .required()
          .default_text("— (required)")
          .cases("experiment")
          .doc("the experiment the cases simulate"));
  add(Row("study", "seed")
          .integer(FIELD(seed), between(0, true, static_cast<double>(std::numeric_limits<std::int64_t>::max()), true,
                                        "a TOML integer"))
          .range(">= 0")
          .cases("seed")
          .doc("one seed for the design, the radii (GSL MT19937) and the initial positions"));

  // [design]: the names are sobol's (design_kind_from_string, which also accepts "lhs-centered"), every kind of which
  // a study can use; the study keeps the canonical name, so that both spellings give the same design hash.
  add(Row("design", "method")
          .string(FIELD(design))
          .assign([](StudyConfig& c, const SettingValue& v) {
            try {
              c.design = sobol::to_string(sobol::design_kind_from_string(std::get<std::string>(v)));
            } catch (const sobol::InputError& e) {
              throw SettingError(e.what());
            }
          })
          .names(sobol::design_kind_names())
          .cases("design")
          .doc("the design of experiments on the parameter ranges: Latin hypercubes (plain, centred, optimised for "
               "maximin distance or centred L2 discrepancy) or a scrambled Sobol' sequence"));
  add(Row("design", "samples")
          .integer(FIELD(samples),
                   between(2, true, k_max_samples, true,
                           "the analysis needs at least 2 samples, one case alone is `demsa case`; each sample is "
                           "a case folder"))
          .range(fmt::format("[2, {}]; at most {} for `lhs-maximin` and `lhs-cl2`", k_max_samples,
                             k_max_optimised_lhs_samples))
          .cases("samples")
          .doc("number of samples (the paper: 160 pile, 200 oedometer); the optimised Latin hypercubes keep an "
               "N × N matrix of the sample pairs. Raising it in an existing study extends the design (the finished "
               "cases are kept, docs/how-to/refine.md); lowering it is refused"));

  // DEM noise: replicate cases at the first P design points (cases/case_writer.hpp: CaseRequest::assembly_seed). The
  // replicates are case rows of their own (study/store.hpp), so a design that grows keeps them.
  add(Row("design", "replicates")
          .table(
              {"points", "repeats"},
              [](const StudyConfig& c) {
                if (!c.replicates.enabled()) return std::string("none");
                return fmt::format("{{ points = {}, repeats = {} }}", c.replicates.points, c.replicates.repeats);
              },
              [](const StudyConfig& c) {
                Lines lines;  // none when off: a study without replicates keeps its design hash
                if (c.replicates.enabled()) {
                  lines.emplace_back("replicates.points", std::to_string(c.replicates.points));
                  lines.emplace_back("replicates.repeats", std::to_string(c.replicates.repeats));
                }
                return lines;
              })
          .effect(E::cases)
          .default_text("none")
          .range("points in [1, samples], repeats in [2, 1000]")
          .doc("DEM noise: `{ points = P, repeats = R }` runs, at the first P design points, R cases each whose "
               "particle packing (radii and positions) is drawn with another assembly seed, everything else equal (a "
               "Rayleigh time step follows the packing's smallest radius, as in any case); "
               "the design point's own case is the first of the R, so the study runs P (R − 1) cases more. The "
               "analysis measures each observable's noise variance from them (pooled within-point variance), sets "
               "the GP nugget from it and reports the noise share; the replicates do not enter the metamodels' "
               "training. Raising P or R in an existing study adds the missing replicate cases (those run are "
               "kept); lowering either, or removing the setting, is refused"));

  // [parameters]: one table row per contact parameter; the admissible values are those of its [material] row.
  for (const ContactParameter& p : contact_parameters()) {
    const std::string key(p.key);
    Row row("parameters", key);
    row.table(
           {"low", "high", "scale", "same_as"},
           [key](const StudyConfig& c) {
             for (const ParameterRange& r : c.parameters)
               if (r.name == key)
                 return fmt::format("{{ low = {}, high = {}, scale = \"{}\" }}", shortest(r.bounds.low),
                                    shortest(r.bounds.high), sobol::to_string(r.bounds.scale));
             if (const ParameterTie* t = find_tie(c.ties, key))
               return fmt::format("{{ same_as = \"{}\" }}", t->partner);
             return std::string("not varied");
           },
           [key](const StudyConfig& c) {
             Lines lines;
             for (const ParameterRange& r : c.parameters) {
               if (r.name != key) continue;
               lines.emplace_back("p." + key + ".low", canonical_number(r.bounds.low));
               lines.emplace_back("p." + key + ".high", canonical_number(r.bounds.high));
               lines.emplace_back("p." + key + ".scale", sobol::to_string(r.bounds.scale));
             }
             // A tie changes every case of the tied parameter (its [material] value no longer counts).
             if (const ParameterTie* t = find_tie(c.ties, key)) lines.emplace_back("p." + key + ".same_as", t->partner);
             return lines;
           })
        .effect(E::cases)
        .unit(p.unit == "-" ? "" : std::string(p.unit))
        .default_text("not varied")
        .doc(fmt::format("range of {} ({}): `{{ low, high, scale }}`; or `{{ same_as = \"KEY\" }}`, tied to the varied "
                         "parameter KEY: no range and no design column of its own, every case gives it KEY's value",
                         p.label, p.symbol));
    add(row);
  }

  // [material]
  add(Row("material", "E")
          .number(FIELD(material.E), between(1e3, true, 1e13, true, "from a gel to ten times diamond's 1.2e12 Pa"))
          .unit("Pa")
          .cases("m.E")
          .doc("Young's modulus; LIGGGHTS accepts [5e6, 1e9] Pa only (see `soft_particles`, `hard_particles`)"));
  add(Row("material", "nu")
          .number(FIELD(material.nu), between(0, false, 0.5, false))
          .cases("m.nu")
          .doc("Poisson ratio"));
  add(Row("material", "mu_pp")
          .number(FIELD(material.mu_pp), k_friction_bounds)
          .cases("m.mu_pp")
          .doc("particle–particle Coulomb friction"));
  add(Row("material", "mu_pw")
          .number(FIELD(material.mu_pw), k_friction_bounds)
          .cases("m.mu_pw")
          .doc("particle–wall Coulomb friction"));
  add(Row("material", "e_r")
          .number(FIELD(material.e_r), between(0, false, 1, true))
          .cases("m.e_r")
          .doc("coefficient of restitution"));
  add(Row("material", "mu_r_pp")
          .number(FIELD(material.mu_r_pp), k_rolling_bounds)
          .cases("m.mu_r_pp")
          .doc("particle–particle rolling coefficient of `[contact] rolling_model` (μ_r of `cdt`, dimensionless; μ_R "
               "of `viscous` in `viscous_unit`)"));
  add(Row("material", "mu_r_pw")
          .number(FIELD(material.mu_r_pw), k_rolling_bounds)
          .cases("m.mu_r_pw")
          .doc("particle–wall rolling coefficient of `[contact] rolling_model`"));
  add(Row("material", "density")
          .number(FIELD(material.density), between(1, true, 1e5, true, "from an aerogel to four times osmium's"))
          .unit("kg/m³")
          .cases("m.density")
          .doc("particle density (not in the paper)"));
  add(Row("material", "gravity")
          .number(FIELD(material.gravity), between(1e-3, true, 1e4, true, "from microgravity to a centrifuge"))
          .unit("m/s²")
          .cases("m.gravity")
          .doc("\\|g\\|"));
  add(Row("material", "soft_particles")
          .boolean(FIELD(material.soft_particles))
          .cases("m.soft")
          .doc("allow E < 5e6 Pa (LIGGGHTS `soft_particles yes`)"));
  add(Row("material", "hard_particles")
          .boolean(FIELD(material.hard_particles))
          .cases("m.hard")
          .doc("allow E > 1e9 Pa (LIGGGHTS `hard_particles yes`)"));

  // [timestep]
  add(Row("timestep", "mode")
          .choice(FIELD(timestep.mode),
                  std::vector<std::pair<std::string, TimestepMode>>{{"rayleigh", TimestepMode::rayleigh},
                                                                    {"fixed", TimestepMode::fixed}})
          .cases("dt.mode")
          .doc("`rayleigh`: dt = `fraction` × T_R of the smallest particle of the sample; `fixed`: dt = `value`"));
  add(Row("timestep", "fraction")
          .number(FIELD(timestep.fraction),
                  between(1e-6, true, 0.3, true,
                          "a time step above 0.3 Rayleigh times is unstable for Hertz contacts; below 1e-6 it "
                          "underflows for the smallest particles"))
          .cases("dt.fraction")
          .doc("dt as a fraction of the Rayleigh time T_R"));
  add(Row("timestep", "value")
          .number(FIELD(timestep.value), between(0, false, 1, true))
          .unit("s")
          .default_text("— (required with `mode = \"fixed\"`)")
          .cases("dt.value")
          .doc("fixed time step"));
  add(Row("timestep", "skin")
          .number(FIELD(timestep.skin), between(0, false, 1, true))
          .unit("m")
          .cases("dt.skin")
          .doc("neighbor list skin; a moving mesh may travel at most skin/2 per step"));

  // [run]
  add(Row("run", "executor")
          .choice(FIELD(run.executor),
                  std::vector<std::pair<std::string, ExecutorKind>>{{"local", ExecutorKind::local},
                                                                    {"slurm", ExecutorKind::slurm}})
          .doc("where cases run: this machine or a SLURM cluster"));
  add(Row("run", "ranks")
          .integer(FIELD(run.ranks), between(1, true, 1e6, true))
          .cases("ranks")
          .doc("MPI ranks per case; results depend on it, so every case of a study uses the same count"));
  add(Row("run", "parallel")
          .integer(FIELD(run.parallel), between(0, true, 1e6, true))
          .doc("cases at once (local); 0 = cores / ranks"));
  add(Row("run", "oversubscribe").boolean(FIELD(run.oversubscribe)).doc("allow parallel × ranks > cores"));
  add(Row("run", "timeout")
          .number(FIELD(run.timeout), between(0, true, 1e7, true))
          .unit("s")
          .doc("per case; 0 = none"));
  add(Row("run", "retries")
          .integer(FIELD(run.retries), between(0, true, 1000, true))
          .doc("extra attempts after a failure"));
  add(Row("run", "lost_fraction")
          .number(FIELD(run.lost_fraction), between(0, true, 1, true))
          .doc("a case that loses more than this fraction of its particles fails"));
  add(Row("run", "liggghts").string(FIELD(run.liggghts)).non_empty().doc("LIGGGHTS executable (name on PATH or path)"));
  add(Row("run", "mpirun").string(FIELD(run.mpirun)).non_empty().doc("MPI launcher"));

  // [run.slurm]
  add(Row("run.slurm", "mode")
          .choice(FIELD(run.slurm.mode), std::vector<std::pair<std::string, SlurmMode>>{{"array", SlurmMode::array},
                                                                                        {"pack", SlurmMode::pack}})
          .doc("`array`: one job array per batch of cases; `pack`: one allocation of `throttle` cases × `ranks` "
               "CPUs that runs the cases as `srun --exclusive` job steps (for clusters that cap jobs per user)"));
  add(Row("run.slurm", "partition")
          .string(FIELD(run.slurm.partition))
          .doc("sbatch `--partition` (empty: the cluster's default)"));
  add(Row("run.slurm", "account")
          .string(FIELD(run.slurm.account))
          .doc("sbatch `--account` (empty: the cluster's default)"));
  add(Row("run.slurm", "time_limit").string(FIELD(run.slurm.time_limit)).doc("sbatch `--time` per case"));
  add(Row("run.slurm", "throttle")
          .integer(FIELD(run.slurm.throttle), between(0, true, 1e6, true))
          .doc("`%N` array throttle, 0 = none"));
  add(Row("run.slurm", "sbatch_options")
          .strings(FIELD(run.slurm.sbatch_options))
          .doc("extra sbatch options, verbatim"));
  add(Row("run.slurm", "prologue")
          .string(FIELD(run.slurm.prologue))
          .doc("shell lines before mpirun (e.g. `module load ...`)"));
  add(Row("run.slurm", "poll_interval")
          .number(FIELD(run.slurm.poll_interval), between(0, false, 86400, true))
          .unit("s")
          .doc("time between squeue polls"));

  // [analysis]
  add(Row("analysis", "metamodels")
          .strings(FIELD(analysis.metamodels))
          .check([](const SettingValue& v) {
            // The metamodels sobol/ builds: one list, so the study file accepts exactly what the analysis can fit.
            const std::vector<std::string> models = sobol::metamodel_names();
            for (const std::string& m : std::get<std::vector<std::string>>(v))
              if (std::find(models.begin(), models.end(), m) == models.end())
                throw SettingError(fmt::format("unknown metamodel '{}' (valid: {})", m, util::join(models)));
          })
          .range(fmt::format("any of {}", code_list(sobol::metamodel_names())))
          .doc("metamodels to fit: `rsm1`–`rsm3` are polynomials of total degree 1–3"));
  add(Row("analysis", "second_order").boolean(FIELD(analysis.second_order)).doc("also S2"));
  add(Row("analysis", "bootstrap")
          .integer(FIELD(analysis.bootstrap), between(0, true, k_max_bootstrap, true,
                                                      "each resample refits every metamodel and computes its indices"))
          .doc("bootstrap resamples for confidence intervals (for the `gp` metamodel with `interval = "
               "\"gp-posterior\"`: posterior draws)"));
  add(Row("analysis", "interval")
          .choice(FIELD(analysis.interval),
                  std::vector<sobol::MetamodelInterval>{sobol::MetamodelInterval::gp_posterior,
                                                        sobol::MetamodelInterval::design_bootstrap},
                  sobol::metamodel_interval_from_string, [](sobol::MetamodelInterval i) { return sobol::to_string(i); })
          .doc(
              "interval of metamodel indices: `design-bootstrap` refits every metamodel on resampled samples; "
              "`gp-posterior` takes the `gp` metamodel's from draws of its posterior (Le Gratiet et al. 2014; it "
              "narrows where points are added, but at the fitted hyperparameters it covered the true indices less "
              "often than its level, docs/explanation/benchmarks.md; the other metamodels keep the design bootstrap)"));
  add(Row("analysis", "confidence")
          .number(FIELD(analysis.confidence), between(0, false, 1, false))
          .doc("confidence level"));
  add(Row("analysis", "base_samples")
          .integer(FIELD(analysis.base_samples),
                   between(16, true, k_max_base_samples, true,
                           "the indices' QMC design holds N (2d + 2) points in memory, about 1 GB at 2^20 for 7 "
                           "parameters"))
          .assign([](StudyConfig& c, const SettingValue& v) {
            // Sobol' points are balanced in blocks of 2^m (Owen 2020, "On dropping the first Sobol' point"; Saltelli
            // et al. 2010 use N = 2^m): another N loses accuracy, so the analysis uses the next power of two.
            const long given = std::get<long>(v);
            long used = 1;
            while (used < given) used *= 2;
            if (used != given)
              util::log::warn("[analysis] base_samples = {} is not a power of two; the analysis uses {}", given, used);
            c.analysis.base_samples = static_cast<int>(used);
          })
          .doc("QMC base N for metamodel-based indices; rounded up to a power of two (Sobol' points are balanced in "
               "blocks of 2^m)"));
  add(Row("analysis", "gp_kernel")
          .choice(FIELD(analysis.gp_kernel),
                  std::vector<sobol::GpKernel>{sobol::GpKernel::squared_exponential, sobol::GpKernel::matern52},
                  sobol::gp_kernel_from_string, [](sobol::GpKernel k) { return sobol::to_string(k); })
          .doc("correlation of the `gp` metamodel"));
  add(Row("analysis", "gp_trend")
          .choice(FIELD(analysis.gp_trend),
                  std::vector<sobol::GpTrend>{sobol::GpTrend::constant, sobol::GpTrend::linear},
                  sobol::gp_trend_from_string, [](sobol::GpTrend t) { return sobol::to_string(t); })
          .doc("trend of the `gp` metamodel: `linear` is universal Kriging"));
  add(Row("analysis", "gp_nugget")
          .boolean(FIELD(analysis.gp_nugget))
          .doc("estimate a nugget: the GP smooths the noise of DEM responses instead of interpolating it"));

  // [contact]: the rolling model; at their defaults (`cdt`) the rows add nothing to the hash, so the studies made
  // before the section existed keep their hash.
  add(Row("contact", "rolling_model")
          .choice(FIELD(contact.rolling_model),
                  std::vector<std::pair<std::string, RollingModel>>{{"cdt", RollingModel::cdt},
                                                                    {"epsd", RollingModel::epsd},
                                                                    {"epsd2", RollingModel::epsd2},
                                                                    {"epsd3", RollingModel::epsd3},
                                                                    {"viscous", RollingModel::viscous}})
          .cases("contact.rolling_model")
          .canonical([](const StudyConfig& c) -> Lines {
            if (c.contact.rolling_model == RollingModel::cdt) return {};
            return {{"contact.rolling_model", std::string(rolling_model_name(c.contact.rolling_model))}};
          })
          .doc("rolling resistance of every pair and wall contact (LIGGGHTS `rolling_friction`); `viscous` is the "
               "paper's model B and needs the LIGGGHTS of `scripts/build-liggghts.sh`; `mu_r_pp`/`mu_r_pw` are "
               "its coefficients (see below)"));
  add(Row("contact", "rolling_damping")
          .number(FIELD(contact.rolling_damping), between(0, true, 1, true))
          .cases("contact.rolling_damping")
          .canonical(unless_default("contact.rolling_damping", FIELD(contact.rolling_damping)))
          .doc("`epsd`, `epsd3`: viscous damping ratio η_r of the rolling dashpot "
               "(`coefficientRollingViscousDamping`, dimensionless; Ai et al. 2011 use 0.3)"));
  add(Row("contact", "rolling_stiffness")
          .number(FIELD(contact.rolling_stiffness), between(1, true, 1e6, true))
          .cases("contact.rolling_stiffness")
          .canonical(unless_default("contact.rolling_stiffness", FIELD(contact.rolling_stiffness)))
          .doc("`epsd3`: prefactor of the rolling stiffness k_r = factor × k_n μ_r² R*² (`rollingStiffness`, "
               "dimensionless, >= 1 in SI; `epsd` fixes it at 2.25, Ai et al. 2011)"));
  add(Row("contact", "viscous_unit")
          .choice(FIELD(contact.viscous_unit),
                  std::vector<std::pair<std::string, ViscousUnit>>{{"s*m", ViscousUnit::s_m},
                                                                   {"mm*ms", ViscousUnit::mm_ms}})
          .cases("contact.viscous_unit")
          .canonical([](const StudyConfig& c) -> Lines {
            if (c.contact.viscous_unit == ViscousUnit::s_m) return {};
            return {{"contact.viscous_unit", "mm*ms"}};
          })
          .doc("`viscous`: the unit of `mu_r_pp`, `mu_r_pw` and their `[parameters]` ranges: SI `s*m`, or the "
               "paper's `mm*ms` (Table 3; 1 mm·ms = 1e-6 s·m, converted when the case is written)"));

  std::vector<Setting> settings;
  for (Row& row : rows) settings.push_back(std::move(row).finish());
  // The parameter ranges obey the rules of their [material] values.
  for (Setting& s : settings) {
    if (s.section != "parameters") continue;
    const Setting& m = material_row(settings, s.key);
    s.bounds = m.bounds;
    s.range_text = fmt::format(
        "`low` < `high`, both {}{}; `scale` is `uniform` (default) or `log` (`low` > 0); `same_as`: another varied "
        "key, itself not tied, whose range lies within these values",
        m.bounds.low && m.bounds.high ? "in " : "", m.range_text);
  }
  return settings;
}

#undef FIELD

}  // namespace

/// [contact]: one paragraph per rolling model (docs/reference/study-file.md).
const char* const k_contact_intro =
    "Every pair and wall contact is Hertz normal (`model hertz`, damping from `e_r`) with Mindlin tangential "
    "(`tangential history`, capped by Coulomb friction) and one rolling model, written into `pair_style gran` "
    "and every `fix wall/gran` of both experiments. The coefficients `mu_r_pp` and `mu_r_pw` (`[material]` and "
    "`[parameters]`) are the chosen model's rolling coefficient; its meaning and unit depend on the model.";
const char* const k_contact_notes =
    "- `cdt` (default; LIGGGHTS `src/rolling_model_cdt.h`, doc `gran_rolling_friction_cdt`; Ai et al. 2011 "
    "model A): a constant torque μ_r k_n δ_n R* against the tangential relative rotation. `mu_r_*` is the "
    "dimensionless coefficientRollingFriction μ_r (a lever arm of μ_r R*). Stock LIGGGHTS.\n"
    "- `epsd` (`src/rolling_model_epsd.h`; Ai et al. 2011 model C, elastic-plastic spring-dashpot): a rolling "
    "spring k_r = 2.25 k_n μ_r² R*² capped at μ_r \\|F_n\\| R*, plus a dashpot of damping ratio `rolling_damping` "
    "(coefficientRollingViscousDamping η_r, dimensionless) while the spring is not at its cap. `mu_r_*`: μ_r, "
    "dimensionless. Stock LIGGGHTS.\n"
    "- `epsd2` (`src/rolling_model_epsd2.h`; Iwashita and Oda 1998): the spring of `epsd` with k_r = k_t R*² "
    "(k_t the tangential stiffness), capped at μ_r \\|F_n\\| R*, no dashpot. `mu_r_*`: μ_r, dimensionless. Stock "
    "LIGGGHTS.\n"
    "- `epsd3` (`src/rolling_model_epsd3.h`): `epsd` with k_r = `rolling_stiffness` × k_n μ_r² R*² "
    "(rollingStiffness, dimensionless, >= 1 in SI) and the dashpot ratio `rolling_damping`. `mu_r_*`: μ_r, "
    "dimensionless. Stock LIGGGHTS.\n"
    "- `viscous` (the paper's eq. 8: Ai et al. 2011 model B; `liggghts/rolling_model_viscous.h` of this "
    "repository, doc `liggghts/rolling_model_viscous.md`): the torque μ_R \\|F_n\\| ω_t against the tangential "
    "relative angular velocity ω_t, so that `mu_r_*` is μ_R with units of length × time "
    "(coefficientRollingViscosity in s·m). Give it in SI (`viscous_unit = \"s*m\"`) or in the paper's mm·ms "
    "(`viscous_unit = \"mm*ms\"`: Table 3's μ_R,PP ∈ [0.45, 4.5] and μ_R,PW ∈ [0.8, 5] mm·ms are [0.45e-6, "
    "4.5e-6] and [0.8e-6, 5e-6] s·m; 1 mm·ms = 1e-6 s·m); the case writer converts to s·m. Explicitly "
    "integrated the torque is stiff (unstable once μ_R \\|F_n\\| dt / I* > 2); each contact therefore applies "
    "over one step the exact exponential decay of ω_t that its torque causes, its one-step fraction capped at "
    "1/8 (the header's comment gives the derivation), which equals model B whenever the rolling relaxes over "
    "more than about 8 steps. A purely viscous torque gives no static rolling resistance (ω = 0, no torque). Not "
    "in stock LIGGGHTS: build it with `scripts/build-liggghts.sh` (docs/how-to/viscous-liggghts.md); demsa refuses a "
    "`viscous` study "
    "before any case runs when the LIGGGHTS it found lacks the model.";

std::vector<SettingSection> core_sections(const std::vector<SettingSection>& experiment_sections) {
  std::vector<SettingSection> sections{
      {"study", "", ""},
      {"design", "", ""},
      {"parameters",
       "Keys are the paper's tuple P (eq. 1). Each is a table `{ low, high, scale }`. The ranges must be physical, "
       "by the rules of the `[material]` values. An `E` range (or a fixed `[material]` `E`) that reaches above 1e9 "
       "Pa needs `[material] hard_particles = true`, and one below 5e6 Pa needs `soft_particles = true`: LIGGGHTS "
       "refuses such moduli in SI units otherwise, so the study file is refused when it is read. Parameters not "
       "listed take their `[material]` value. Whatever the order in the file, the parameters are kept in the "
       "paper's order; at least one is required. A parameter can be tied to another instead of varied: `mu_pw = "
       "{ same_as = \"mu_pp\" }` (or `mu_r_pw = { same_as = \"mu_r_pp\" }`) for a wall whose material is not known "
       "apart from the particles'. The pair is one parameter of the design, the metamodels, the Sobol' indices, "
       "`demsa calibrate` and `demsa plan` (named \"μ_PP = μ_PW\" in the report); each case gives the tied one its "
       "partner's value. Calibrated together with a study that varies both, the tied parameter maps onto its "
       "partner there too (docs/explanation/method.md, \"The report and the calibration\").",
       ""},
      {"material", "",
       "The rolling coefficients `mu_r_pp` and `mu_r_pw` are those of `[contact] rolling_model`: dimensionless "
       "for `cdt` (the default), `epsd`, `epsd2` and `epsd3`, length × time for the paper's `viscous` model B "
       "(in the unit of `[contact] viscous_unit`)."},
      {"contact", k_contact_intro, k_contact_notes},
  };
  // The experiments' sections sit between [contact] and [timestep] (the order of the design hash's text).
  sections.insert(sections.end(), experiment_sections.begin(), experiment_sections.end());
  const std::vector<SettingSection> after{
      {"timestep", "",
       "T_R = π r_min sqrt(ρ/G) / (0.1631 ν + 0.8766), G = E / (2 (1 + ν)). A case is refused (with the reason) "
       "when dt > 0.3 T_R, when E lies outside [5e6, 1e9] Pa without the matching `[material]` flag, or when a "
       "servo plate's `servo_vel_max` ≥ skin / (2 dt)."},
      {"run", "", ""},
      {"run.slurm", "", ""},
      {"analysis", "", ""},
  };
  sections.insert(sections.end(), after.begin(), after.end());
  return sections;
}

std::vector<Setting> core_settings() { return build_core_settings(); }

}  // namespace demsa::study
