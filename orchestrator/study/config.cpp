#include "orchestrator/study/config.hpp"

#include "orchestrator/util/errors.hpp"
#include "sobol/error.hpp"
#include "sobol/metamodel.hpp"

#include <fmt/core.h>

#include <toml++/toml.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <set>
#include <sstream>

namespace demsa::study {

using namespace demsa::util;

namespace {

template <typename Range>
std::string join(const Range& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + std::string(item);
  return out;
}

/// Reads one TOML table key by key: every key must be known, every value of the right type and range. Messages
/// are "study.toml:LINE: [section] key: ...".
class TableReader {
 public:
  TableReader(const toml::table& table, std::string file, std::string section)
      : m_table(table), m_file(std::move(file)), m_section(std::move(section)) {}

  /// Calls `handle(key, node)` for every key; `handle` returns false for an unknown key.
  void each(const std::function<bool(const std::string&, const toml::node&)>& handle) const {
    for (const auto& [key, node] : m_table) {
      const std::string name(key.str());
      if (!handle(name, node)) {
        throw UserError(m_file, line_of(node), fmt::format("unknown key '{}' in [{}]{}", name, m_section, hint()));
      }
    }
  }

  int line_of(const toml::node& node) const { return static_cast<int>(node.source().begin.line); }

  [[noreturn]] void fail(const toml::node& node, const std::string& key, const std::string& message) const {
    throw UserError(m_file, line_of(node), fmt::format("[{}] {}: {}", m_section, key, message));
  }

  double number(const std::string& key, const toml::node& node) const {
    if (const auto v = node.value<double>(); v && (node.is_floating_point() || node.is_integer())) {
      if (!std::isfinite(*v)) fail(node, key, fmt::format("must be a finite number, got {}", *v));
      return *v;
    }
    fail(node, key, fmt::format("expected a number, got {}", describe(node)));
  }
  double positive(const std::string& key, const toml::node& node) const {
    const double v = number(key, node);
    if (!(v > 0)) fail(node, key, fmt::format("must be > 0, got {}", v));
    return v;
  }
  double non_negative(const std::string& key, const toml::node& node) const {
    const double v = number(key, node);
    if (v < 0) fail(node, key, fmt::format("must be >= 0, got {}", v));
    return v;
  }
  long integer(const std::string& key, const toml::node& node, long min_value) const {
    if (!node.is_integer()) fail(node, key, fmt::format("expected an integer, got {}", describe(node)));
    const long v = static_cast<long>(*node.value<std::int64_t>());
    if (v < min_value) fail(node, key, fmt::format("must be >= {}, got {}", min_value, v));
    return v;
  }
  std::string string(const std::string& key, const toml::node& node) const {
    if (!node.is_string()) fail(node, key, fmt::format("expected a string, got {}", describe(node)));
    return *node.value<std::string>();
  }
  bool boolean(const std::string& key, const toml::node& node) const {
    if (!node.is_boolean()) fail(node, key, fmt::format("expected true or false, got {}", describe(node)));
    return *node.value<bool>();
  }
  std::vector<double> numbers(const std::string& key, const toml::node& node) const {
    const toml::array* array = node.as_array();
    if (!array) fail(node, key, fmt::format("expected an array of numbers, got {}", describe(node)));
    std::vector<double> out;
    for (const toml::node& element : *array) out.push_back(number(key, element));
    return out;
  }
  std::vector<std::string> strings(const std::string& key, const toml::node& node) const {
    const toml::array* array = node.as_array();
    if (!array) fail(node, key, fmt::format("expected an array of strings, got {}", describe(node)));
    std::vector<std::string> out;
    for (const toml::node& element : *array) out.push_back(string(key, element));
    return out;
  }
  const toml::table& table(const std::string& key, const toml::node& node) const {
    const toml::table* t = node.as_table();
    if (!t) fail(node, key, fmt::format("expected a table, got {}", describe(node)));
    return *t;
  }

  const std::string& file() const { return m_file; }
  const std::string& section() const { return m_section; }

  static std::string describe(const toml::node& node) {
    switch (node.type()) {
      case toml::node_type::string:
        return "the string \"" + *node.value<std::string>() + "\"";
      case toml::node_type::table:
        return "a table";
      case toml::node_type::array:
        return "an array";
      case toml::node_type::integer:
        return "the integer " + std::to_string(*node.value<std::int64_t>());
      case toml::node_type::floating_point:
        return fmt::format("the number {}", *node.value<double>());
      case toml::node_type::boolean:
        return *node.value<bool>() ? "true" : "false";
      default:
        return "a date or time";
    }
  }

 private:
  std::string hint() const {
    static const std::map<std::string, std::string> keys{
        {"study", "name, experiment, seed"},
        {"design", "method, samples"},
        {"parameters", "E, nu, mu_pp, mu_pw, e_r, mu_r_pp, mu_r_pw"},
        {"material", "E, nu, mu_pp, mu_pw, e_r, mu_r_pp, mu_r_pw, density, gravity, soft_particles, hard_particles"},
        {"pile",
         "preset, particles, r_min, r_max, r_mean, r_sd, disc_radius, fill_height, pedestal_radius, "
         "pedestal_height, settle_time, ke_stop, settle_check_time, domain_half_width, target_angle, directions, "
         "levels"},
        {"oedometer",
         "preset, particles, r_min, r_max, r_mean, r_sd, box_side, box_height, fill_time, loads, "
         "measured_settlements, plate_mode, plate_gap, load_tolerance, servo_vel_max, servo_kp, servo_ki, "
         "servo_kd, servo_max_steps, servo_check_steps, rest_velocity, trial_steps, relax_steps, "
         "trial_reduction, trial_step0, trial_floor, max_trials"},
        {"timestep", "mode, fraction, value, skin"},
        {"run", "executor, ranks, parallel, oversubscribe, timeout, retries, lost_fraction, liggghts, mpirun, slurm"},
        {"run.slurm", "partition, account, time_limit, throttle, sbatch_options, prologue, poll_interval"},
        {"analysis", "metamodels, second_order, bootstrap, confidence, base_samples, gp_kernel, gp_trend, gp_nugget"},
    };
    const auto it = keys.find(m_section);
    return it == keys.end() ? std::string() : " (valid: " + it->second + ")";
  }

  const toml::table& m_table;
  std::string m_file;
  std::string m_section;
};

template <typename Enum>
Enum choose(const TableReader& reader, const std::string& key, const toml::node& node,
            const std::vector<std::pair<std::string, Enum>>& options) {
  const std::string value = reader.string(key, node);
  std::vector<std::string> names;
  for (const auto& [name, e] : options) {
    if (name == value) return e;
    names.push_back(name);
  }
  reader.fail(node, key, fmt::format("unknown value '{}' (valid: {})", value, join(names)));
}

bool read_radius(const TableReader& r, const std::string& key, const toml::node& node, RadiusDistribution& radii) {
  if (key == "r_min")
    radii.r_min = r.positive(key, node);
  else if (key == "r_max")
    radii.r_max = r.positive(key, node);
  else if (key == "r_mean")
    radii.mean = r.positive(key, node);
  else if (key == "r_sd")
    radii.sd = r.positive(key, node);
  else
    return false;
  return true;
}

/// The paper's particle sets (Table 2) and oedometer assembly one (§4).
void apply_pile_preset(const TableReader& r, const toml::node& node, PileSettings& pile) {
  const std::string preset = r.string("preset", node);
  if (preset == "set1") {
    pile.particles = 6000;
    pile.radii = RadiusDistribution{1.0e-3, 3.5e-3, 2.0e-3, 0.5e-3};
  } else if (preset == "set2") {
    pile.particles = 8000;
    pile.radii = RadiusDistribution{0.8e-3, 2.5e-3, 1.5e-3, 0.35e-3};
  } else {
    r.fail(node, "preset", fmt::format("unknown preset '{}' (valid: set1, set2)", preset));
  }
  pile.preset = preset;
}

void apply_oedometer_preset(const TableReader& r, const toml::node& node, OedometerSettings& oedometer) {
  const std::string preset = r.string("preset", node);
  if (preset != "paper") r.fail(node, "preset", fmt::format("unknown preset '{}' (valid: paper)", preset));
  oedometer.preset = preset;
  // Paper §4: assembly one has 4642 particles and the void ratio 0.66, with the pore volume computed on a
  // 10 x 10 x 5 cm^3 sample: V_P = 500 cm^3 - V_S. (The paper's formula reads e_1 = V_S / V_P, but a solid
  // fraction of 1/1.66 = 0.60 is a sphere packing under load and 0.40 is not, so e = V_P / V_S as usual.) The
  // paper gives no radii; these give that solid volume in expectation:
  //   V_S = 500 cm^3 / (1 + 0.66) = 301.2 cm^3, so E[r^3] = V_S / (4642 * 4/3 pi) = 15.49 mm^3.
  // Radii are N(mu, sd) truncated to [a, b] = [2.0, 3.0] mm with sd = 0.25 mm, i.e. density proportional to
  // phi((r - mu)/sd) on [a, b]; E[r^3] = int_a^b r^3 phi dr / int_a^b phi dr (trapezoid rule, 2e5 intervals).
  // mu = 2.466 mm gives E[r] = 2.4737 mm and E[r^3] = 15.496 mm^3: V_S = 301.30 cm^3 and e = 500 / 301.30 - 1 =
  // 0.6595 (mu = 2.47 mm would give 0.653). The former radii, 2.5 to 3.5 mm around 3 mm (E[r^3] = 27.4 mm^3),
  // put V_S = 533 cm^3 above the 500 cm^3 of the sample.
  oedometer.particles = 4642;
  oedometer.radii = k_paper_oedometer_radii;
}

void check_radii(const TableReader& r, const toml::table& table, const RadiusDistribution& radii) {
  const toml::node* at = table.get("r_min");
  if (!at) at = table.get("r_max");
  const int line = at ? r.line_of(*at) : static_cast<int>(table.source().begin.line);
  if (!(radii.r_min < radii.r_max)) {
    throw UserError(r.file(), line,
                    fmt::format("[{}] r_min ({}) must be less than r_max ({})", r.section(), radii.r_min, radii.r_max));
  }
  if (radii.mean < radii.r_min || radii.mean > radii.r_max) {
    throw UserError(r.file(), line,
                    fmt::format("[{}] r_mean ({}) must lie in [r_min, r_max] = [{}, {}]", r.section(), radii.mean,
                                radii.r_min, radii.r_max));
  }
}

void read_material_value(const TableReader& r, const std::string& key, const toml::node& node, Material& m) {
  if (key == "E")
    m.E = r.positive(key, node);
  else if (key == "nu") {
    m.nu = r.number(key, node);
    if (!(m.nu > 0 && m.nu < 0.5)) r.fail(node, key, fmt::format("must lie in (0, 0.5), got {}", m.nu));
  } else if (key == "mu_pp")
    m.mu_pp = r.non_negative(key, node);
  else if (key == "mu_pw")
    m.mu_pw = r.non_negative(key, node);
  else if (key == "e_r") {
    m.e_r = r.number(key, node);
    if (!(m.e_r > 0 && m.e_r <= 1)) r.fail(node, key, fmt::format("must lie in (0, 1], got {}", m.e_r));
  } else if (key == "mu_r_pp")
    m.mu_r_pp = r.non_negative(key, node);
  else if (key == "mu_r_pw")
    m.mu_r_pw = r.non_negative(key, node);
  else
    assert(false && "read_material_value called with a non-parameter key");
}

bool is_parameter(const std::string& key) {
  const auto& names = contact_parameter_names();
  return std::find(names.begin(), names.end(), key) != names.end();
}

/// Physical admissibility of a parameter's range (the same rules as [material]).
void check_parameter_range(const TableReader& r, const toml::node& node, const ParameterRange& p) {
  const auto bad = [&](const std::string& rule) {
    r.fail(node, p.name, fmt::format("range [{}, {}] {}", p.bounds.low, p.bounds.high, rule));
  };
  if (p.name == "E" && p.bounds.low <= 0) bad("must be > 0");
  if (p.name == "nu" && (p.bounds.low <= 0 || p.bounds.high >= 0.5)) bad("must lie in (0, 0.5)");
  if (p.name == "e_r" && (p.bounds.low <= 0 || p.bounds.high > 1)) bad("must lie in (0, 1]");
  if ((p.name == "mu_pp" || p.name == "mu_pw" || p.name == "mu_r_pp" || p.name == "mu_r_pw") && p.bounds.low < 0)
    bad("must be >= 0");
}

/// LIGGGHTS's SI check on Young's modulus (physics.hpp: k_liggghts_min_E, k_liggghts_max_E), applied to the whole
/// range of a varied E and to a fixed [material] E once every table is read (the flags may follow [parameters]):
/// otherwise the study is accepted and its samples fail one by one when their cases are written.
void check_young_modulus_limits(const StudyConfig& c, const std::string& file, int material_E_line) {
  const auto it =
      std::find_if(c.parameters.begin(), c.parameters.end(), [](const ParameterRange& p) { return p.name == "E"; });
  const bool varied = it != c.parameters.end();
  const double low = varied ? it->bounds.low : c.material.E;
  const double high = varied ? it->bounds.high : c.material.E;
  const int line = varied ? it->line : material_E_line;
  const std::string what = varied ? fmt::format("[parameters] E: range [{:.4g}, {:.4g}] Pa", low, high)
                                  : fmt::format("[material] E: {:.4g} Pa", low);
  if (high > k_liggghts_max_E && !c.material.hard_particles)
    throw UserError(file, line,
                    fmt::format("{} reaches above {:.0e} Pa, which LIGGGHTS refuses in SI units: set [material] "
                                "hard_particles = true to allow it, or keep E <= {:.0e} Pa",
                                what, k_liggghts_max_E, k_liggghts_max_E));
  if (low < k_liggghts_min_E && !c.material.soft_particles)
    throw UserError(file, line,
                    fmt::format("{} reaches below {:.0e} Pa, which LIGGGHTS refuses in SI units: set [material] "
                                "soft_particles = true to allow it, or keep E >= {:.0e} Pa",
                                what, k_liggghts_min_E, k_liggghts_min_E));
}

}  // namespace

StudyConfig parse_study(const std::string& text, const std::filesystem::path& file) {
  const std::string name = file.filename().string();
  toml::table root;
  try {
    root = toml::parse(text, file.string());
  } catch (const toml::parse_error& e) {
    throw UserError(name, static_cast<int>(e.source().begin.line), std::string(e.description()));
  }
  StudyConfig c;
  c.file = file;
  bool have_name = false, have_experiment = false;
  int material_E_line = 0;  // line of [material] E, 0 when not given
  const TableReader top(root, name, "");

  for (const auto& [key, node] : root) {
    const std::string section(key.str());
    static const std::set<std::string> sections{"study",     "design",   "parameters", "material", "pile",
                                                "oedometer", "timestep", "run",        "analysis"};
    if (!sections.count(section)) {
      throw UserError(name, top.line_of(node),
                      fmt::format("unknown section [{}] (valid: {})", section, join(sections)));
    }
    const toml::table& table = top.table(section, node);
    const TableReader r(table, name, section);

    if (section == "study") {
      r.each([&](const std::string& k, const toml::node& n) {
        if (k == "name") {
          c.name = r.string(k, n);
          if (c.name.empty()) r.fail(n, k, "must not be empty");
          have_name = true;
        } else if (k == "experiment") {
          c.experiment =
              choose<Experiment>(r, k, n, {{"pile", Experiment::pile}, {"oedometer", Experiment::oedometer}});
          have_experiment = true;
        } else if (k == "seed") {
          c.seed = static_cast<std::uint64_t>(r.integer(k, n, 0));
        } else {
          return false;
        }
        return true;
      });
    } else if (section == "design") {
      r.each([&](const std::string& k, const toml::node& n) {
        if (k == "method") {
          c.design = r.string(k, n);
          static const std::vector<std::string> methods{"lhs", "lhs-centred", "lhs-maximin", "lhs-cl2", "sobol"};
          if (std::find(methods.begin(), methods.end(), c.design) == methods.end())
            r.fail(n, k, fmt::format("unknown method '{}' (valid: {})", c.design, join(methods)));
        } else if (k == "samples") {
          c.samples = static_cast<int>(r.integer(k, n, 1));
        } else {
          return false;
        }
        return true;
      });
    } else if (section == "parameters") {
      r.each([&](const std::string& k, const toml::node& n) {
        if (!is_parameter(k)) return false;
        const toml::table& pt = r.table(k, n);
        const TableReader pr(pt, name, "parameters." + k);
        ParameterRange p;
        p.name = k;
        p.line = r.line_of(n);
        bool low = false, high = false;
        pr.each([&](const std::string& pk, const toml::node& pn) {
          if (pk == "low") {
            p.bounds.low = pr.number(pk, pn);
            low = true;
          } else if (pk == "high") {
            p.bounds.high = pr.number(pk, pn);
            high = true;
          } else if (pk == "scale") {
            try {
              p.bounds.scale = sobol::scale_from_string(pr.string(pk, pn));
            } catch (const sobol::InputError& e) {
              pr.fail(pn, pk, e.what());
            }
          } else {
            return false;
          }
          return true;
        });
        if (!low || !high) r.fail(n, k, "needs both 'low' and 'high'");
        try {
          sobol::validate_bounds({p.bounds}, {k});
        } catch (const sobol::InputError& e) {
          r.fail(n, k, e.what());
        }
        check_parameter_range(r, n, p);
        c.parameters.push_back(p);
        return true;
      });
    } else if (section == "material") {
      r.each([&](const std::string& k, const toml::node& n) {
        if (is_parameter(k)) {
          read_material_value(r, k, n, c.material);
          if (k == "E") material_E_line = r.line_of(n);
        } else if (k == "density")
          c.material.density = r.positive(k, n);
        else if (k == "gravity")
          c.material.gravity = r.positive(k, n);
        else if (k == "soft_particles")
          c.material.soft_particles = r.boolean(k, n);
        else if (k == "hard_particles")
          c.material.hard_particles = r.boolean(k, n);
        else
          return false;
        return true;
      });
    } else if (section == "pile") {
      PileSettings& p = c.pile;
      if (const toml::node* preset = table.get("preset")) apply_pile_preset(r, *preset, p);
      r.each([&](const std::string& k, const toml::node& n) {
        if (k == "preset") return true;
        if (read_radius(r, k, n, p.radii)) return true;
        if (k == "particles")
          p.particles = static_cast<int>(r.integer(k, n, 1));
        else if (k == "disc_radius")
          p.disc_radius = r.positive(k, n);
        else if (k == "fill_height")
          p.fill_height = r.positive(k, n);
        else if (k == "pedestal_radius")
          p.pedestal_radius = r.positive(k, n);
        else if (k == "pedestal_height")
          p.pedestal_height = r.positive(k, n);
        else if (k == "settle_time")
          p.settle_time = r.non_negative(k, n);
        else if (k == "ke_stop")
          p.ke_stop = r.non_negative(k, n);
        else if (k == "settle_check_time")
          p.settle_check_time = r.positive(k, n);
        else if (k == "domain_half_width")
          p.domain_half_width = r.positive(k, n);
        else if (k == "target_angle") {
          p.target_angle = r.number(k, n);
          if (!(p.target_angle > 0 && p.target_angle < 90))
            r.fail(n, k, fmt::format("must lie in (0, 90) degrees, got {}", p.target_angle));
        } else if (k == "directions")
          p.directions = static_cast<int>(r.integer(k, n, 1));
        else if (k == "levels")
          p.levels = static_cast<int>(r.integer(k, n, 2));
        else
          return false;
        return true;
      });
      check_radii(r, table, p.radii);
      if (2 * p.radii.r_max > 2 * p.disc_radius)
        r.fail(table, "disc_radius",
               fmt::format("{} m cannot hold a particle of radius r_max = {} m", p.disc_radius, p.radii.r_max));
      if (p.disc_radius + p.radii.r_max > p.domain_half_width || p.pedestal_radius >= p.domain_half_width)
        r.fail(table, "domain_half_width",
               fmt::format("{} m must exceed the disc radius + r_max and the pedestal radius", p.domain_half_width));
    } else if (section == "oedometer") {
      OedometerSettings& o = c.oedometer;
      if (const toml::node* preset = table.get("preset")) apply_oedometer_preset(r, *preset, o);
      r.each([&](const std::string& k, const toml::node& n) {
        if (k == "preset") return true;
        if (read_radius(r, k, n, o.radii)) return true;
        if (k == "particles")
          o.particles = static_cast<int>(r.integer(k, n, 1));
        else if (k == "box_side")
          o.box_side = r.positive(k, n);
        else if (k == "box_height")
          o.box_height = r.positive(k, n);
        else if (k == "fill_time")
          o.fill_time = r.positive(k, n);
        else if (k == "loads") {
          o.loads = r.numbers(k, n);
          if (o.loads.empty()) r.fail(n, k, "needs at least one load");
          for (std::size_t i = 0; i < o.loads.size(); ++i) {
            if (!(o.loads[i] > 0)) r.fail(n, k, fmt::format("load {} is {} N; loads must be > 0", i + 1, o.loads[i]));
            if (i > 0 && !(o.loads[i] > o.loads[i - 1]))
              r.fail(n, k, fmt::format("loads must increase: {} N follows {} N", o.loads[i], o.loads[i - 1]));
          }
        } else if (k == "measured_settlements") {
          o.measured_settlements = r.numbers(k, n);
        } else if (k == "plate_mode") {
          o.plate_mode =
              choose<PlateMode>(r, k, n, {{"servo", PlateMode::servo}, {"trial-step", PlateMode::trial_step}});
        } else if (k == "plate_gap")
          o.plate_gap = r.non_negative(k, n);
        else if (k == "load_tolerance")
          o.load_tolerance = r.positive(k, n);
        else if (k == "servo_vel_max")
          o.servo_vel_max = r.positive(k, n);
        else if (k == "servo_kp")
          o.servo_kp = r.non_negative(k, n);
        else if (k == "servo_ki")
          o.servo_ki = r.non_negative(k, n);
        else if (k == "servo_kd")
          o.servo_kd = r.non_negative(k, n);
        else if (k == "servo_max_steps")
          o.servo_max_steps = r.integer(k, n, 1);
        else if (k == "servo_check_steps")
          o.servo_check_steps = r.integer(k, n, 1);
        else if (k == "rest_velocity")
          o.rest_velocity = r.positive(k, n);
        else if (k == "trial_steps")
          o.trial_steps = r.integer(k, n, 1);
        else if (k == "relax_steps")
          o.relax_steps = r.integer(k, n, 1);
        else if (k == "trial_reduction") {
          o.trial_reduction = r.number(k, n);
          if (!(o.trial_reduction > 0 && o.trial_reduction < 1))
            r.fail(n, k, fmt::format("must lie in (0, 1), got {}", o.trial_reduction));
        } else if (k == "trial_step0")
          o.trial_step0 = r.positive(k, n);
        else if (k == "trial_floor") {
          o.trial_floor = r.number(k, n);
          if (!(o.trial_floor > 0 && o.trial_floor <= 1))
            r.fail(n, k, fmt::format("must lie in (0, 1], got {}", o.trial_floor));
        } else if (k == "max_trials")
          o.max_trials = static_cast<int>(r.integer(k, n, 1));
        else
          return false;
        return true;
      });
      check_radii(r, table, o.radii);
      if (!o.measured_settlements.empty() && o.measured_settlements.size() + 1 != o.loads.size()) {
        const toml::node* at = table.get("measured_settlements");
        r.fail(*at, "measured_settlements",
               fmt::format("has {} values; it needs one per load after the first ({} loads -> {} values)",
                           o.measured_settlements.size(), o.loads.size(), o.loads.size() - 1));
      }
      if (2 * o.radii.r_max >= o.box_side)
        r.fail(table, "box_side",
               fmt::format("{} m is too small for particles of radius {} m", o.box_side, o.radii.r_max));
    } else if (section == "timestep") {
      r.each([&](const std::string& k, const toml::node& n) {
        if (k == "mode") {
          c.timestep.mode =
              choose<TimestepMode>(r, k, n, {{"rayleigh", TimestepMode::rayleigh}, {"fixed", TimestepMode::fixed}});
        } else if (k == "fraction") {
          c.timestep.fraction = r.number(k, n);
          if (!(c.timestep.fraction > 0 && c.timestep.fraction <= 0.3))
            r.fail(n, k,
                   fmt::format("must lie in (0, 0.3], got {}: a time step above 0.3 Rayleigh times is unstable "
                               "for Hertz contacts",
                               c.timestep.fraction));
        } else if (k == "value")
          c.timestep.value = r.positive(k, n);
        else if (k == "skin")
          c.timestep.skin = r.positive(k, n);
        else
          return false;
        return true;
      });
      if (c.timestep.mode == TimestepMode::fixed && !(c.timestep.value > 0))
        r.fail(table, "value", "mode = \"fixed\" needs value = the time step in seconds");
    } else if (section == "run") {
      RunSettings& run = c.run;
      r.each([&](const std::string& k, const toml::node& n) {
        if (k == "executor")
          run.executor =
              choose<ExecutorKind>(r, k, n, {{"local", ExecutorKind::local}, {"slurm", ExecutorKind::slurm}});
        else if (k == "ranks")
          run.ranks = static_cast<int>(r.integer(k, n, 1));
        else if (k == "parallel")
          run.parallel = static_cast<int>(r.integer(k, n, 0));
        else if (k == "oversubscribe")
          run.oversubscribe = r.boolean(k, n);
        else if (k == "timeout")
          run.timeout = r.non_negative(k, n);
        else if (k == "retries")
          run.retries = static_cast<int>(r.integer(k, n, 0));
        else if (k == "lost_fraction") {
          run.lost_fraction = r.number(k, n);
          if (!(run.lost_fraction >= 0 && run.lost_fraction <= 1))
            r.fail(n, k, fmt::format("must lie in [0, 1], got {}", run.lost_fraction));
        } else if (k == "liggghts")
          run.liggghts = r.string(k, n);
        else if (k == "mpirun")
          run.mpirun = r.string(k, n);
        else if (k == "slurm") {
          const TableReader sr(r.table(k, n), name, "run.slurm");
          SlurmSettings& s = run.slurm;
          sr.each([&](const std::string& sk, const toml::node& sn) {
            if (sk == "partition")
              s.partition = sr.string(sk, sn);
            else if (sk == "account")
              s.account = sr.string(sk, sn);
            else if (sk == "time_limit")
              s.time_limit = sr.string(sk, sn);
            else if (sk == "throttle")
              s.throttle = static_cast<int>(sr.integer(sk, sn, 0));
            else if (sk == "sbatch_options")
              s.sbatch_options = sr.strings(sk, sn);
            else if (sk == "prologue")
              s.prologue = sr.string(sk, sn);
            else if (sk == "poll_interval")
              s.poll_interval = sr.positive(sk, sn);
            else
              return false;
            return true;
          });
        } else
          return false;
        return true;
      });
    } else if (section == "analysis") {
      AnalysisSettings& a = c.analysis;
      r.each([&](const std::string& k, const toml::node& n) {
        if (k == "metamodels") {
          a.metamodels = r.strings(k, n);
          // The metamodels sobol/ builds: one list, so the study file accepts exactly what the analysis can fit.
          const std::vector<std::string> models = sobol::metamodel_names();
          for (const std::string& m : a.metamodels)
            if (std::find(models.begin(), models.end(), m) == models.end())
              r.fail(n, k, fmt::format("unknown metamodel '{}' (valid: {})", m, join(models)));
        } else if (k == "second_order")
          a.second_order = r.boolean(k, n);
        else if (k == "bootstrap")
          a.bootstrap = static_cast<int>(r.integer(k, n, 0));
        else if (k == "confidence") {
          a.confidence = r.number(k, n);
          if (!(a.confidence > 0 && a.confidence < 1))
            r.fail(n, k, fmt::format("must lie in (0, 1), got {}", a.confidence));
        } else if (k == "base_samples")
          a.base_samples = static_cast<int>(r.integer(k, n, 16));
        else if (k == "gp_kernel") {
          try {
            a.gp_kernel = sobol::gp_kernel_from_string(r.string(k, n));
          } catch (const sobol::InputError& e) {
            r.fail(n, k, e.what());
          }
        } else if (k == "gp_trend") {
          try {
            a.gp_trend = sobol::gp_trend_from_string(r.string(k, n));
          } catch (const sobol::InputError& e) {
            r.fail(n, k, e.what());
          }
        } else if (k == "gp_nugget")
          a.gp_nugget = r.boolean(k, n);
        else
          return false;
        return true;
      });
    }
  }

  if (!have_name) throw UserError(name, 0, "[study] name is required");
  if (!have_experiment) throw UserError(name, 0, "[study] experiment is required (pile or oedometer)");
  if (c.parameters.empty()) throw UserError(name, 0, "[parameters] must vary at least one parameter");
  // Keep the paper's order (eq. 1) whatever order the file lists them in.
  const auto& order = contact_parameter_names();
  std::sort(c.parameters.begin(), c.parameters.end(), [&](const ParameterRange& a, const ParameterRange& b) {
    return std::find(order.begin(), order.end(), a.name) < std::find(order.begin(), order.end(), b.name);
  });
  check_young_modulus_limits(c, name, material_E_line);
  return c;
}

StudyConfig load_study(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw UserError(file.string() + ": cannot read the study file");
  std::ostringstream text;
  text << in.rdbuf();
  StudyConfig c = parse_study(text.str(), file);
  c.file = file;
  return c;
}

namespace {

std::string canonical_number(double v) { return fmt::format("{:.17g}", v); }

}  // namespace

std::string design_hash(const StudyConfig& c) {
  // FNV-1a 64 over a canonical text of everything that defines the design and the cases ([run] and [analysis]
  // excluded): reordering keys or changing comments in the file does not change it.
  std::string s;
  const auto add = [&](const std::string& key, const std::string& value) { s += key + "=" + value + "\n"; };
  const auto num = [&](const std::string& key, double v) { add(key, canonical_number(v)); };
  add("experiment", c.experiment == Experiment::pile ? "pile" : "oedometer");
  add("seed", std::to_string(c.seed));
  add("design", c.design);
  add("samples", std::to_string(c.samples));
  for (const ParameterRange& p : c.parameters) {
    num("p." + p.name + ".low", p.bounds.low);
    num("p." + p.name + ".high", p.bounds.high);
    add("p." + p.name + ".scale", sobol::to_string(p.bounds.scale));
  }
  const Material& m = c.material;
  for (const auto& [k, v] : std::vector<std::pair<std::string, double>>{{"E", m.E},
                                                                        {"nu", m.nu},
                                                                        {"mu_pp", m.mu_pp},
                                                                        {"mu_pw", m.mu_pw},
                                                                        {"e_r", m.e_r},
                                                                        {"mu_r_pp", m.mu_r_pp},
                                                                        {"mu_r_pw", m.mu_r_pw},
                                                                        {"density", m.density},
                                                                        {"gravity", m.gravity}})
    num("m." + k, v);
  add("m.soft", m.soft_particles ? "1" : "0");
  add("m.hard", m.hard_particles ? "1" : "0");
  const auto radii = [&](const std::string& prefix, const RadiusDistribution& r) {
    num(prefix + "r_min", r.r_min);
    num(prefix + "r_max", r.r_max);
    num(prefix + "mean", r.mean);
    num(prefix + "sd", r.sd);
  };
  if (c.experiment == Experiment::pile) {
    const PileSettings& p = c.pile;
    add("pile.particles", std::to_string(p.particles));
    radii("pile.", p.radii);
    for (const auto& [k, v] : std::vector<std::pair<std::string, double>>{{"disc_radius", p.disc_radius},
                                                                          {"fill_height", p.fill_height},
                                                                          {"pedestal_radius", p.pedestal_radius},
                                                                          {"pedestal_height", p.pedestal_height},
                                                                          {"settle_time", p.settle_time},
                                                                          {"ke_stop", p.ke_stop},
                                                                          {"settle_check_time", p.settle_check_time},
                                                                          {"domain_half_width", p.domain_half_width}})
      num("pile." + k, v);
  } else {
    const OedometerSettings& o = c.oedometer;
    add("oed.particles", std::to_string(o.particles));
    radii("oed.", o.radii);
    num("oed.box_side", o.box_side);
    num("oed.box_height", o.box_height);
    num("oed.fill_time", o.fill_time);
    for (double l : o.loads) num("oed.load", l);
    add("oed.mode", o.plate_mode == PlateMode::servo ? "servo" : "trial-step");
    num("oed.plate_gap", o.plate_gap);
    num("oed.tol", o.load_tolerance);
    num("oed.vmax", o.servo_vel_max);
    num("oed.kp", o.servo_kp);
    num("oed.ki", o.servo_ki);
    num("oed.kd", o.servo_kd);
    add("oed.smax", std::to_string(o.servo_max_steps));
    add("oed.scheck", std::to_string(o.servo_check_steps));
    num("oed.vrest", o.rest_velocity);
    add("oed.ns", std::to_string(o.trial_steps));
    add("oed.nl", std::to_string(o.relax_steps));
    num("oed.mt", o.trial_reduction);
    num("oed.d0", o.trial_step0);
    num("oed.floor", o.trial_floor);
    add("oed.maxtrials", std::to_string(o.max_trials));
  }
  add("dt.mode", c.timestep.mode == TimestepMode::rayleigh ? "rayleigh" : "fixed");
  num("dt.fraction", c.timestep.fraction);
  num("dt.value", c.timestep.value);
  num("dt.skin", c.timestep.skin);
  add("ranks", std::to_string(c.run.ranks));  // results depend on the rank count (reference notes)
  std::uint64_t h = 1469598103934665603ULL;
  for (const unsigned char ch : s) {
    h ^= ch;
    h *= 1099511628211ULL;
  }
  return fmt::format("{:016x}", h);
}

Material material_for(const StudyConfig& config, const std::vector<double>& physical) {
  assert(physical.size() == config.parameters.size());
  Material m = config.material;
  for (std::size_t i = 0; i < physical.size(); ++i) {
    const std::string& n = config.parameters[i].name;
    const double v = physical[i];
    if (n == "E")
      m.E = v;
    else if (n == "nu")
      m.nu = v;
    else if (n == "mu_pp")
      m.mu_pp = v;
    else if (n == "mu_pw")
      m.mu_pw = v;
    else if (n == "e_r")
      m.e_r = v;
    else if (n == "mu_r_pp")
      m.mu_r_pp = v;
    else if (n == "mu_r_pw")
      m.mu_r_pw = v;
    else
      assert(false && "unknown parameter name in config.parameters");
  }
  return m;
}

sobol::MetamodelOptions AnalysisSettings::metamodel_options() const {
  sobol::MetamodelOptions o;
  o.gp.kernel = gp_kernel;
  o.gp.trend = gp_trend;
  o.gp.nugget = gp_nugget;
  return o;
}

}  // namespace demsa::study
