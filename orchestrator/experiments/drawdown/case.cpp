#include "orchestrator/experiments/drawdown/drawdown.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/geometry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>
#include <gsl/gsl_rng.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <tuple>

// The draw-down's case: its floor layer and loose fill, its meshes and the files of its folder.
namespace demsa::experiments::drawdown {

using namespace demsa::study;

namespace fs = std::filesystem;

namespace {

/// SplitMix64's output function (Steele, Lea, Flood, OOPSLA 2014) of the assembly seed and a stream number: the seeds
/// of the fill's radii, its positions and the floor layer's radii, each its own.
std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t z = seed + (stream + 1) * 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return (z ^ (z >> 31)) & 0x7fffffffffffffffULL;
}

double width(const DrawdownSettings& s) { return s.slot_width + 2 * s.side_width; }

/// A horizontal rectangle at z = 0 as two triangles (normal up).
std::vector<Triangle> rectangle(double x0, double x1, double y0, double y1) {
  return {Triangle{Vertex{x0, y0, 0.0}, Vertex{x1, y0, 0.0}, Vertex{x1, y1, 0.0}},
          Triangle{Vertex{x0, y0, 0.0}, Vertex{x1, y1, 0.0}, Vertex{x0, y1, 0.0}}};
}

}  // namespace

std::vector<Particle> build_floor_layer(const DrawdownSettings& s, std::uint64_t seed) {
  // Rows along y at a pitch that divides the periodic depth, rows sqrt(3)/2 of it apart in x, every other row shifted
  // by half a pitch: a hexagonal lattice that repeats across the periodic boundary.
  const int per_row = std::max(1, static_cast<int>(std::lround(s.depth / (k_floor_pitch * s.radii.mean))));
  const double py = s.depth / per_row;
  const double px = py * std::sqrt(3.0) / 2.0;
  const double half = width(s) / 2.0;
  const int rows = static_cast<int>(std::ceil(half / px)) + 1;
  std::vector<std::pair<double, double>> sites;
  for (int i = -rows; i <= rows; ++i)
    for (int j = 0; j < per_row; ++j) sites.emplace_back(i * px, (j + 0.5 * ((i % 2 + 2) % 2)) * py);
  const std::vector<double> radii =
      truncated_normal_radii(s.radii, static_cast<int>(sites.size()), stream_seed(seed, 2));
  std::vector<Particle> layer;
  for (std::size_t k = 0; k < sites.size(); ++k) {
    const double r = radii[k];
    const double x = sites[k].first;
    // On the floor: not over the slot, not into a wall.
    if (std::abs(x) - r < s.slot_width / 2 || std::abs(x) + r > half) continue;
    layer.push_back({x, sites[k].second, r, r});
  }
  return layer;
}

std::vector<double> fill_radii(const DrawdownSettings& s, std::uint64_t seed) {
  return truncated_normal_radii(s.radii, s.particles, stream_seed(seed, 0));
}

std::vector<Particle> build_fill(const DrawdownSettings& s, std::uint64_t seed, double floor_top) {
  std::vector<double> radii = fill_radii(s, seed);
  std::sort(radii.begin(), radii.end(), std::greater<>());  // larger first: random sequential addition fills denser
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), &gsl_rng_free);
  gsl_rng_set(rng.get(), static_cast<unsigned long>(stream_seed(seed, 1)));
  const double gap = 0.02 * s.radii.r_min;
  const double cell = 2 * s.radii.r_max + gap;
  const double half = width(s) / 2.0;
  const double z_low = floor_top, z_high = floor_top + s.fill_height;
  const long ny = std::max(1L, static_cast<long>(std::floor(s.depth / cell)));
  const double cell_y = s.depth / static_cast<double>(ny);
  std::map<std::tuple<long, long, long>, std::vector<std::size_t>> grid;
  std::vector<Particle> fill;
  // Random sequential addition (Widom 1966): a particle is tried at uniform random positions until it overlaps none
  // placed before; a bounded number of tries, so that a fill that cannot fit is refused rather than tried for ever.
  constexpr int k_tries = 100000;
  for (const double r : radii) {
    bool placed = false;
    for (int t = 0; t < k_tries && !placed; ++t) {
      const double x = -half + r + gap + gsl_rng_uniform(rng.get()) * (2 * half - 2 * r - 2 * gap);
      const double y = gsl_rng_uniform(rng.get()) * s.depth;
      const double z = z_low + r + gap + gsl_rng_uniform(rng.get()) * (s.fill_height - 2 * r - gap);
      const long cx = std::lround(std::floor((x + half) / cell)), cz = std::lround(std::floor((z - z_low) / cell));
      const long cy = static_cast<long>(std::floor(y / cell_y));
      bool free = true;
      for (long ix = cx - 1; ix <= cx + 1 && free; ++ix)
        for (long iy = cy - 1; iy <= cy + 1 && free; ++iy)
          for (long iz = cz - 1; iz <= cz + 1 && free; ++iz) {
            const auto it = grid.find({ix, (iy % ny + ny) % ny, iz});
            if (it == grid.end()) continue;
            for (const std::size_t j : it->second) {
              const Particle& q = fill[j];
              double dy = std::abs(y - q.y);
              dy = std::min(dy, s.depth - dy);  // periodic along the slot
              const double d2 = (x - q.x) * (x - q.x) + dy * dy + (z - q.z) * (z - q.z);
              if (d2 < (r + q.radius + gap) * (r + q.radius + gap)) {
                free = false;
                break;
              }
            }
          }
      if (!free) continue;
      grid[{cx, cy, cz}].push_back(fill.size());
      fill.push_back({x, y, z, r});
      placed = true;
    }
    if (!placed) {
      double volume = 0;
      for (const Particle& p : fill) volume += 4.0 / 3.0 * std::numbers::pi * p.radius * p.radius * p.radius;
      throw util::UserError(fmt::format(
          "[drawdown] fill_height = {} m, particles = {}: after {} particles were placed (a solid fraction of {:.2f} "
          "of the {} × {} × {} m box), particle {} (radius {:.3g} m, placed larger first) found no free place in {} "
          "random tries: raise fill_height or lower particles",
          s.fill_height, s.particles, fill.size(), volume / (width(s) * s.depth * s.fill_height), width(s), s.depth,
          s.fill_height, fill.size() + 1, r, k_tries));
    }
    (void)z_high;
  }
  return fill;
}

namespace {

class DrawdownDraft final : public CaseDraft {
 public:
  DrawdownDraft(const StudyConfig& config, std::uint64_t seed) : m_config(config) {
    const DrawdownSettings& s = settings(config);
    if (s.floor == DrawdownFloor::particles) m_floor = build_floor_layer(s, seed);
    double top = 0;
    for (const Particle& p : m_floor) top = std::max(top, p.z + p.radius);
    m_fill = build_fill(s, seed, top);
  }
  double smallest_radius() const override {
    double r = m_fill.front().radius;
    for (const Particle& p : m_fill) r = std::min(r, p.radius);
    for (const Particle& p : m_floor) r = std::min(r, p.radius);
    return r;
  }
  CaseWritten write(const Material& m, const TimestepChoice& ts, Params& params, const fs::path& dir) const override;

 private:
  const StudyConfig& m_config;
  std::vector<Particle> m_floor;  ///< the frozen floor layer (floor = "particles"); atoms 1..m_floor.size()
  std::vector<Particle> m_fill;
};

CaseWritten DrawdownDraft::write(const Material& m, const TimestepChoice& ts, Params& params,
                                 const fs::path& dir) const {
  const DrawdownSettings& s = settings(m_config);
  const double half = width(s) / 2.0;
  const long floor_particles = static_cast<long>(m_floor.size());
  const auto mass_of = [&](const std::vector<Particle>& ps) {
    double mass = 0;
    for (const Particle& p : ps) mass += m.density * 4.0 / 3.0 * std::numbers::pi * p.radius * p.radius * p.radius;
    return mass;
  };
  const long check_steps = steps_for(s.check_time, ts.dt, "[drawdown] check_time");
  const long window_checks = std::max(1L, std::lround(s.window / s.check_time));
  check_run_count(window_checks * std::max(1L, std::lround(std::ceil(s.time_cap / (window_checks * s.check_time)))),
                  check_steps, "[drawdown] check_time");
  const double fill_mass = mass_of(m_fill);
  params.comment("draw-down");
  params.number("half_width", half, "side walls at x = -half_width and half_width [m]");
  params.integer("fill_steps", steps_for(s.fill_time, ts.dt, "[drawdown] fill_time"),
                 "the fill settles on the closed floor");
  params.integer("check_steps", check_steps, "discharge recorded and fallen particles removed every this often");
  params.integer("window_checks", window_checks, "checks of a window");
  params.integer("min_windows", std::max(1L, std::lround(s.min_time / (window_checks * s.check_time))),
                 "the flow is judged stopped from this window on");
  params.integer("max_windows", std::max(1L, std::lround(std::ceil(s.time_cap / (window_checks * s.check_time)))),
                 "the cap");
  params.number("stop_mass", s.stop_share * fill_mass, "the flow has stopped below this discharge per window [kg]");
  params.number("removal_depth", s.removal_depth, "particles this far below the floor are discharged [m]");
  params.integer("floor_particles", floor_particles, "atoms 1..floor_particles: the frozen floor layer");
  params.number("floor_mass", mass_of(m_floor), "its mass [kg]");

  double top = 0;
  for (const Particle& p : m_fill) top = std::max(top, p.z + p.radius);
  std::string data = data_header(m_floor.empty() ? "demsa drawdown: the loose fill"
                                                 : "demsa drawdown: the frozen floor layer, then the loose fill",
                                 floor_particles + static_cast<long>(m_fill.size()), -half - 0.001, half + 0.001, 0.0,
                                 s.depth, -s.removal_depth - 0.02, top + 0.02);
  long id = 0;
  for (const Particle& p : m_floor) data += atom_line(++id, p, m.density);
  for (const Particle& p : m_fill) data += atom_line(++id, p, m.density);
  write_text(dir / "drawdown_particles.data", data);
  write_text(dir / "floor_left.stl", to_ascii_stl(rectangle(-half, -s.slot_width / 2, 0.0, s.depth), "floor_left"));
  write_text(dir / "floor_right.stl", to_ascii_stl(rectangle(s.slot_width / 2, half, 0.0, s.depth), "floor_right"));
  write_text(dir / "slot_plate.stl",
             to_ascii_stl(rectangle(-s.slot_width / 2, s.slot_width / 2, 0.0, s.depth), "slot_plate"));
  write_text(
      dir / "drawdown_floor.liggghts",
      m_floor.empty()
          ? "# Generated by demsa: [drawdown] floor = \"wall\", the floor is the wall material.\n"
          : "# Generated by demsa: [drawdown] floor = \"particles\": atoms 1..floor_particles are a layer of the\n"
            "# material's particles glued onto the floor. Their force and torque are zeroed after every other\n"
            "# force (fix freeze), so they stay at rest; their pairs among themselves are not computed.\n"
            "group           floor_layer id <= ${floor_particles}\n"
            "fix             glue floor_layer freeze\n"
            "neigh_modify    exclude group floor_layer floor_layer\n");
  write_text(dir / k_case_input, with_rolling_model(template_text("drawdown.liggghts"), m_config.contact));

  CaseWritten w;
  w.particles = floor_particles + static_cast<long>(m_fill.size());
  w.assembly = {{"particles", m_fill.size()}, {"floor_particles", floor_particles}, {"fill_top_m", top}};
  // Everything the measurement needs (drawdown.cpp), so that `demsa measure CASE` measures it the same way.
  w.experiment = {{"width_m", width(s)},
                  {"slot_width_m", s.slot_width},
                  {"depth_m", s.depth},
                  {"floor_particles", floor_particles},
                  {"fill_mass_kg", fill_mass},
                  {"density", m.density},
                  {"measurement",
                   {{"slices", s.slices},
                    {"bin_width_m", s.bin_width},
                    {"edge_skip_m", s.edge_skip},
                    {"wall_skip_m", s.wall_skip}}}};
  return w;
}

}  // namespace

std::unique_ptr<CaseDraft> draft_case(const StudyConfig& config, std::uint64_t assembly_seed) {
  return std::make_unique<DrawdownDraft>(config, assembly_seed);
}

}  // namespace demsa::experiments::drawdown

namespace demsa::experiments::drawdown {

// The schedule of drawdown.liggghts: fill_steps on the closed floor, then up to max_windows windows of window_checks
// checks of check_steps with every atom present (the cap: the flow stops earlier and the discharged atoms are
// removed), as DrawdownDraft::write counts them above.
CaseCost case_cost(const StudyConfig& config, const nlohmann::json& case_json, const fs::path& file,
                   const nlohmann::json& /*probed*/) {
  const DrawdownSettings& s = settings(config);
  const std::optional<double> dt = case_number(case_json, file, "dt", 0.0, 1.0);
  if (!dt || *dt <= 0.0) throw util::UserError(fmt::format("{}: no time step (dt)", file.string()));
  constexpr long k_big = std::numeric_limits<int>::max();
  const long fill = case_integer(case_json, file, "assembly.particles", 0, k_big).value_or(0);
  const long floor = case_integer(case_json, file, "assembly.floor_particles", 0, k_big).value_or(0);
  const long fill_steps = steps_for(s.fill_time, *dt, "[drawdown] fill_time");
  const long check_steps = steps_for(s.check_time, *dt, "[drawdown] check_time");
  const long window_checks = std::max(1L, std::lround(s.window / s.check_time));
  const long max_windows = std::max(1L, std::lround(std::ceil(s.time_cap / (window_checks * s.check_time))));
  CaseCost cost;
  cost.steps = fill_steps + max_windows * window_checks * check_steps;
  cost.particles = fill + floor;
  cost.atom_steps = static_cast<double>(cost.steps) * static_cast<double>(cost.particles);
  cost.may_end_early = true;
  cost.schedule = fmt::format(
      "{} atoms for {} fill steps and up to {} discharge steps (the cap: the flow stops "
      "earlier and discharged particles are removed)",
      cost.particles, fill_steps, max_windows * window_checks * check_steps);
  return cost;
}

}  // namespace demsa::experiments::drawdown
