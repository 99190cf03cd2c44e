#include "orchestrator/experiments/pile/pile.hpp"

#include "orchestrator/experiments/geometry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/signals.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

// The pile's case (paper §3.1–3.2): its assembly of discs and the files of its folder.
namespace demsa::experiments::pile {

using namespace demsa::study;

namespace fs = std::filesystem;

Disc fill_disc(const std::vector<double>& radii, std::size_t& next, double r_upper, double disc_radius, double gap) {
  Disc disc;
  const double two_pi = 2.0 * std::numbers::pi;
  for (int k = 0;; ++k) {
    const double ring = 2.0 * r_upper * k;
    if (ring + r_upper > disc_radius * (1.0 + 1e-12)) break;
    if (next >= radii.size()) break;
    if (k == 0) {
      disc.push_back({0.0, 0.0, 0.0, radii[next++]});
      continue;
    }
    // Angle subtended by a chord of length c on the ring.
    const auto angle = [ring](double chord) { return 2.0 * std::asin(std::min(1.0, chord / (2.0 * ring))); };
    const double first_r = radii[next];
    double theta = 0.0;
    disc.push_back({ring, 0.0, 0.0, radii[next++]});
    double prev_r = first_r;
    while (next < radii.size()) {
      const double r = radii[next];
      const double t = theta + angle(prev_r + r + gap);
      if (t + angle(first_r + r + gap) > two_pi) break;  // would touch the ring's first particle
      theta = t;
      disc.push_back({ring * std::cos(theta), ring * std::sin(theta), 0.0, r});
      ++next;
      prev_r = r;
    }
  }
  return disc;
}

int PileAssembly::particles() const {
  int n = 0;
  for (const Disc& d : discs) n += static_cast<int>(d.size());
  return n;
}

int PileAssembly::column_particles() const {
  int n = 0;
  for (int i = 0; i < column_discs; ++i) n += static_cast<int>(discs[static_cast<std::size_t>(i)].size());
  return n;
}

PileAssembly build_assembly(const PileSettings& s, std::uint64_t seed) {
  PileAssembly a;
  a.r_upper = s.radii.r_max;
  a.radii = truncated_normal_radii(s.radii, s.particles, seed);
  // Placement gap along a ring: 1 % of the smallest radius keeps neighbours apart without loosening the disc.
  const double gap = 0.01 * s.radii.r_min;
  // Heights from the pedestal top, or from the top of a base layer (its particles reach 2 r_max above the top).
  const double base = s.pedestal_height + (s.base == PileBase::particles ? 2.0 * s.radii.r_max : 0.0);
  a.append_height = base + s.fill_height;
  std::size_t next = 0;
  bool in_column = true;
  for (int k = 0; next < a.radii.size(); ++k) {
    util::throw_if_stop_raised();
    Disc disc = fill_disc(a.radii, next, a.r_upper, s.disc_radius, gap);
    assert(!disc.empty());
    const double z_column = base + a.r_upper + 2.0 * a.r_upper * k;
    in_column = in_column && z_column <= a.append_height * (1.0 + 1e-12);
    const double z = in_column ? z_column : a.append_height;
    for (Particle& p : disc) p.z = z;
    if (in_column) ++a.column_discs;
    a.discs.push_back(std::move(disc));
  }
  return a;
}

double disc_append_interval(double r_upper, double gravity) { return std::sqrt(4.0 * r_upper / gravity); }

std::vector<Particle> build_base_layer(const PileSettings& s, std::uint64_t seed) {
  // The layer's radii have a seed of their own, SplitMix64's output function (Steele, Lea, Flood, OOPSLA 2014) of the
  // assembly seed, so that the pile's own radii and positions are those of the same pile on a wall.
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  const std::uint64_t base_seed = (z ^ (z >> 31)) & 0x7fffffffffffffffULL;
  // Hexagonal lattice sites over the pedestal top, row by row from -R to R.
  const double pitch = k_base_pitch * s.radii.mean;
  const double row = pitch * std::sqrt(3.0) / 2.0;
  const double R = s.pedestal_radius;
  std::vector<std::pair<double, double>> sites;
  const long rows = static_cast<long>(std::floor(R / row));
  const long columns = static_cast<long>(std::floor(R / pitch)) + 1;
  for (long j = -rows; j <= rows; ++j) {
    util::throw_if_stop_raised();
    for (long i = -columns; i <= columns; ++i) {
      const double x = (static_cast<double>(i) + (j % 2 != 0 ? 0.5 : 0.0)) * pitch;
      const double y = static_cast<double>(j) * row;
      // Every site whose centre lies on the top: a particle may overhang the rim, so that no gap down to the top is
      // left there (with only the sites whose particle fits inside, 6 % of the top's area near the rim was within
      // reach of the smallest pile particle, against 0.5 % this way: docs/explanation/experiments.md).
      if (std::hypot(x, y) <= R) sites.emplace_back(x, y);
    }
  }
  const std::vector<double> radii = truncated_normal_radii(s.radii, static_cast<int>(sites.size()), base_seed);
  std::vector<Particle> layer;
  for (std::size_t k = 0; k < sites.size(); ++k)
    layer.push_back({sites[k].first, sites[k].second, s.pedestal_height + radii[k], radii[k]});
  return layer;
}

namespace {

/// A pile case between its assembly and its files.
class PileDraft final : public CaseDraft {
 public:
  PileDraft(const StudyConfig& config, std::uint64_t seed)
      : m_config(config),
        m_assembly(build_assembly(settings(config), seed)),
        m_base(settings(config).base == PileBase::particles ? build_base_layer(settings(config), seed)
                                                            : std::vector<Particle>{}) {}
  /// The pile's smallest radius (the base layer's particles are in contact too: they count for the time step).
  double smallest_radius() const override {
    double r = pile_smallest_radius();
    for (const Particle& p : m_base) r = std::min(r, p.radius);
    return r;
  }
  CaseWritten write(const Material& m, const TimestepChoice& ts, Params& params, const fs::path& dir) const override;

 private:
  double pile_smallest_radius() const { return *std::min_element(m_assembly.radii.begin(), m_assembly.radii.end()); }

  const StudyConfig& m_config;
  PileAssembly m_assembly;
  std::vector<Particle> m_base;  ///< the frozen base layer ([pile] base = "particles"); empty on a wall
};

/// Replaces the one occurrence of `from` in `text` (a line of pile.liggghts that a case variant rewrites).
void replace_once(std::string& text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  assert(at != std::string::npos && "pile.liggghts lacks a line a pile variant replaces");
  text.replace(at, from.size(), to);
}

/// The LIGGGHTS text of `base = "particles"` in pile.liggghts: the base layer (atoms 1..base_particles) is glued —
/// `fix freeze` zeroes its forces and torques after every other force (so the integration leaves it at rest) and its
/// pairs among themselves are not computed — and the particles on the pedestal are counted without it. The wall
/// case's script is the template unchanged.
std::string with_base_layer(std::string text) {
  replace_once(
      text, "fix integr      all nve/sphere\n",
      "fix integr      all nve/sphere\n"
      "# [pile] base = \"particles\": atoms 1..base_particles are a layer of the material's particles glued to "
      "the\n# pedestal top. Their force and torque are zeroed after every other force (fix freeze, defined "
      "after\n# gravity and the walls), so they stay at rest; their pairs among themselves are not computed.\n"
      "group           base id <= ${base_particles}\n"
      "fix             glue base freeze\n"
      "neigh_modify    exclude group base base\n");
  replace_once(text, "variable        n_on_pedestal equal count(all,on_pedestal)\n",
               "variable        n_on_pedestal equal count(all,on_pedestal)-${base_particles}\n");
  return text;
}

/// The LIGGGHTS text of a plane pedestal top (plane_pedestal) in pile.liggghts: the pedestal's mesh wall becomes a
/// primitive plane at the top's height, and `fallen` every particle whose centre lies past the rim, at any height (on
/// an infinite plane a particle past the rim does not fall; it is deleted at the next check, after every disc and
/// every settling check, where on the mesh it would tip over the rim and fall past the side band). The mesh wall was
/// a third of a quickstart pile's time (docs/explanation/benchmarks.md, "Where the time goes").
std::string with_plane_pedestal(std::string text) {
  replace_once(
      text,
      "# The pedestal is a closed-top cylinder mesh (primitive cylinders are infinite and have no cap).\n"
      "fix pedm        all mesh/surface file pedestal.stl type 2\n"
      "fix pedw        all wall/gran model hertz tangential history rolling_friction cdt mesh n_meshes 1 meshes "
      "pedm\n",
      "# [pile] pedestal_top = \"plane\": the pedestal's top is a primitive plane at its height (pedestal.stl is its\n"
      "# drawing only); particles past its rim are deleted at every check (region fallen below).\n"
      "fix pedw        all wall/gran model hertz tangential history rolling_friction cdt primitive type 2 zplane "
      "${pedestal_height}\n");
  replace_once(text, "region          fallen intersect 2 below_top off_radius\n",
               "# The plane pedestal: a particle past the rim has left the pedestal, at any height.\n"
               "region          fallen cylinder z 0.0 0.0 ${pedestal_radius} INF INF units box side out\n");
  return text;
}

CaseWritten PileDraft::write(const Material& m, const TimestepChoice& ts, Params& params, const fs::path& dir) const {
  const StudyConfig& c = m_config;
  const PileSettings& s = settings(c);
  const PileAssembly& a = m_assembly;
  const double t_append = disc_append_interval(a.r_upper, m.gravity);
  const long append_steps =
      steps_for(t_append, ts.dt, "the interval between discs, sqrt(4 r_max / [material] gravity),");
  const long settle_steps = steps_for(s.settle_time, ts.dt, "[pile] settle_time");
  const long check_steps =
      std::max(1L, std::min(settle_steps, steps_for(s.settle_check_time, ts.dt, "[pile] settle_check_time")));
  const long checks = (settle_steps + check_steps - 1) / check_steps;
  check_run_count(checks, check_steps, "[pile] settle_check_time");
  const int appended = static_cast<int>(a.discs.size()) - a.column_discs;
  const double r_min = pile_smallest_radius();
  // The settling criterion: a speed scale of the smallest particle, sqrt(|g| r_min) (the speed it gains falling
  // half its radius), times settle_speed; held at every check over settle_window.
  const double speed_limit = s.settle_speed * std::sqrt(m.gravity * r_min);
  const long window_checks =
      s.settle_speed > 0 ? std::max(1L, static_cast<long>(std::ceil(s.settle_window / s.settle_check_time - 1e-9))) : 0;

  params.comment("pile schedule (paper §3.2)");
  params.integer("particles", a.particles(), "particles in all discs");
  params.integer("column_discs", a.column_discs, "discs present at the start");
  params.integer("appended_discs", appended, "discs appended later");
  params.number("append_time", t_append, "sqrt(4 r_U/|g|) [s]");
  params.integer("append_steps", append_steps, "steps between appended discs");
  params.integer("settle_steps", settle_steps, "settling after the last disc: the cap");
  params.integer("settle_check_steps", check_steps, "settling checked and fallen particles removed every this often");
  params.integer("settle_checks", checks, "checks that cover settle_steps");
  params.number("settle_speed_limit", speed_limit,
                "settled: particles on the pedestal slower than this [m/s] = settle_speed x sqrt(|g| r_min)");
  params.number("settle_fast_share", 1.0 - s.settle_quantile,
                "... except at most this share of the particles on the pedestal (1 - settle_quantile)");
  params.integer("settle_window_checks", window_checks, "... at this many checks in a row; 0 = criterion off");
  const SnapshotPlan history = snapshot_plan(s, checks, check_steps, ts.dt);
  params.integer("settle_min_checks", history.min_checks,
                 "... and not before this check (the last of [pile] measure_times)");
  params.number("pedestal_radius", s.pedestal_radius, "r_cy [m]");
  params.number("pedestal_height", s.pedestal_height, "h_cy, the pedestal top [m]");

  const double hw = s.domain_half_width;
  const double zhi = a.append_height + 0.05;
  const long base_particles = static_cast<long>(m_base.size());
  double base_top = 0.0;  // the mean top of the base layer's particles
  for (const Particle& p : m_base) base_top += (p.z + p.radius) / static_cast<double>(base_particles);
  if (!m_base.empty()) {
    params.comment("rough base ([pile] base = \"particles\")");
    params.integer("base_particles", base_particles, "atoms 1..base_particles: the frozen base layer");
  }
  std::string data = data_header(
      m_base.empty() ? "demsa pile: initial column" : "demsa pile: the frozen base layer, then the initial column",
      base_particles + a.column_particles(), hw, -0.001, zhi);
  long id = 0;
  for (const Particle& p : m_base) data += atom_line(++id, p, m.density);
  for (int k = 0; k < a.column_discs; ++k)
    for (const Particle& p : a.discs[static_cast<std::size_t>(k)]) data += atom_line(++id, p, m.density);
  write_text(dir / "pile_particles.data", data);

  // A new atom is found by its position, not by a predicted id: LIGGGHTS gives a created atom the highest id in
  // use plus one, so a predicted id goes wrong once the highest-numbered particle has left the domain. Before
  // each disc, no particle centre may lie in the disc's layer (above append_height - r_U): a falling disc has
  // dropped 2 r_U by then, so a centre there means the pile has grown into the insertion height, and the new
  // disc would overlap it. The case then stops with an error instead of inserting into the pile.
  const double r_smallest = *std::min_element(a.radii.begin(), a.radii.end());
  const double zone_bottom = a.append_height - a.r_upper;
  std::string discs = fmt::format(
      "# Generated by demsa: {} discs appended at z = {:.10g} m, one every append_steps steps ({:.6g} s).\n"
      "# Each new atom is picked by a small sphere region around its centre to give it its radius.\n"
      "region          insertion_zone block -1e3 1e3 -1e3 1e3 {:.10g} 1e3 units box\n"
      "variable        in_insertion_zone equal count(all,insertion_zone)\n",
      appended, a.append_height, t_append, zone_bottom);
  for (std::size_t k = static_cast<std::size_t>(a.column_discs); k < a.discs.size(); ++k) {
    util::throw_if_stop_raised();
    discs += fmt::format("# disc {} of {}: {} particles\nrun {}\ninclude pile_remove.liggghts\n", k + 1, a.discs.size(),
                         a.discs[k].size(), "${append_steps}");
    discs += fmt::format(
        "if \"${{in_insertion_zone}} > 0\" then \"print 'demsa: before disc {} of {}, ${{in_insertion_zone}} "
        "particle centres lie above z = {:.10g} m: the pile has reached the insertion height (raise [pile] "
        "fill_height)'\" \"demsa:_the_pile_has_reached_the_insertion_height_(raise_fill_height)\"\n",
        k + 1, a.discs.size(), zone_bottom);
    for (const Particle& p : a.discs[k]) {
      ++id;
      discs += fmt::format("create_atoms 1 single {:.10g} {:.10g} {:.10g} units box\n", p.x + 0.0, p.y + 0.0, p.z);
      discs += fmt::format("region new_atom sphere {:.10g} {:.10g} {:.10g} {:.10g} units box\n", p.x + 0.0, p.y + 0.0,
                           p.z, 0.5 * r_smallest);
      discs += fmt::format("set region new_atom diameter {:.10g} density ${{density}}\nregion new_atom delete\n",
                           2.0 * p.radius);
    }
  }
  write_text(dir / "pile_discs.liggghts", discs);
  // The snapshots of the settling (pile.liggghts includes this after every check, with history_check its number).
  std::string snapshots = fmt::format(
      "# Generated by demsa: a snapshot of the particles at {} of the {} settling checks ([pile] history_interval, "
      "measure_times);\n# check 0 is the end of the last disc.\n",
      history.checks.size(), checks);
  for (const long k : history.checks)
    snapshots += fmt::format(
        "if \"${{history_check}} == {}\" then \"write_dump all custom {} id type x y z radius vx vy vz modify sort "
        "id\"\n",
        k, snapshot_file(k));
  write_text(dir / "pile_history.liggghts", snapshots);
  // The pedestal: its rim (the circle's polygon), side band and flat top of 5 mm elements (with a plane top, the
  // pedestal's drawing for export-vtk; LIGGGHTS does not read it). A top of 12.5 mm rings halves the mesh wall's
  // particle-triangle pairs, but with RECIPE 5's exact rejection it runs the quickstart's piles only 1.13 times as
  // fast, and it lowers the angle by about 1 degree at three of six design points on every packing
  // (docs/explanation/benchmarks.md, "The lean top with RECIPE 5"): not adopted.
  write_text(
      dir / k_pedestal_stl,
      to_ascii_stl(pedestal_mesh(s.pedestal_radius, s.pedestal_height, 0.005, 0.005, m_base.empty()), "pedestal"));
  // Particles off the pedestal (region `fallen` of pile.liggghts) are deleted after every disc and settling check,
  // counted in removed_total; `compress no` keeps the ids of the others.
  write_text(dir / "pile_remove.liggghts",
             s.remove_fallen
                 ? "# Generated by demsa: particles below the pedestal top and outside its radius are deleted.\n"
                   "variable n_fallen equal count(all,fallen)\n"
                   "variable removed_total equal ${removed_total}+${n_fallen}\n"
                   "delete_atoms region fallen compress no\n"
                 : "# Generated by demsa: [pile] remove_fallen = false, particles off the pedestal stay.\n");
  const std::string script = with_rolling_model(
      plane_pedestal(s) ? with_plane_pedestal(template_text("pile.liggghts")) : template_text("pile.liggghts"),
      c.contact);
  write_text(dir / k_case_input, m_base.empty() ? script : with_base_layer(script));

  CaseWritten w;
  w.particles = a.particles() + base_particles;
  w.assembly = {{"particles", a.particles()},
                {"discs", a.discs.size()},
                {"column_discs", a.column_discs},
                {"column_particles", a.column_particles()},
                {"particles_per_full_disc", a.discs.front().size()},
                {"append_height_m", a.append_height},
                {"radius_min_m", r_min},
                {"radius_max_m", *std::max_element(a.radii.begin(), a.radii.end())}};
  w.experiment = {{"append_time_s", t_append},
                  {"append_steps", append_steps},
                  {"settle_steps", settle_steps},
                  {"settle_speed_limit_m_s", speed_limit},
                  {"settle_quantile", s.settle_quantile},
                  {"settle_window_checks", window_checks},
                  {"remove_fallen", s.remove_fallen},
                  {"pedestal_top", plane_pedestal(s) ? "plane" : "mesh"},
                  {"pedestal_radius_m", s.pedestal_radius},
                  {"pedestal_height_m", s.pedestal_height}};
  // How the finished pile is measured (exec/measure.cpp), so `demsa postprocess pile CASE` measures it the same way.
  w.experiment["angle_measurement"] = {{"directions", s.directions},
                                       {"levels", s.levels},
                                       {"estimator", s.angle_estimator},
                                       {"drift_window_s", s.drift_window},
                                       {"drift_limit_deg_s", s.drift_limit}};
  // The pile in time: which checks wrote a snapshot, and the check of each measure time.
  w.experiment["history"] = {{"check_steps", check_steps},
                             {"check_time_s", s.settle_check_time},
                             {"snapshot_checks", history.checks},
                             {"measure_times_s", s.measure_times},
                             {"measure_checks", history.measure_checks},
                             {"keep_snapshots", s.keep_snapshots}};
  if (!m_base.empty()) {
    // The base layer: left out of the measurement, whose heights start at its mean top.
    w.experiment["base"] = {{"particles", base_particles}, {"top_m", base_top}};
    w.assembly["base_particles"] = base_particles;
  }
  return w;
}

}  // namespace

std::unique_ptr<CaseDraft> draft_case(const StudyConfig& config, std::uint64_t assembly_seed) {
  return std::make_unique<PileDraft>(config, assembly_seed);
}

}  // namespace demsa::experiments::pile
