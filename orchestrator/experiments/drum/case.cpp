#include "orchestrator/experiments/drum/drum.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <numeric>
#include <tuple>

// The drum's case: its fill (a lattice inside the drum, radii from the size classes or the truncated normal, coarse
// grained), its wall mesh and the files of its folder.
namespace demsa::experiments::drum {

using namespace demsa::study;

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

namespace {

constexpr double k_pi = std::numbers::pi;

/// The gap between neighbouring lattice sites and between a site and the wall, as a fraction of the largest
/// diameter: particles start apart and settle.
constexpr double k_lattice_gap = 0.02;

/// The classes' fractions renormalised to sum 1.
std::vector<double> normalised_fractions(const DrumSettings& s) {
  const double sum = std::accumulate(s.fractions.begin(), s.fractions.end(), 0.0);
  std::vector<double> f;
  for (const double v : s.fractions) f.push_back(v / sum);
  return f;
}

/// The full-size largest radius.
double full_r_max(const DrumSettings& s) {
  if (s.diameters.empty()) return s.radii.r_max;
  return *std::max_element(s.diameters.begin(), s.diameters.end()) / 2;
}

/// The counts of the classes among `count` particles: ⌊f_i count⌋, and the rest one each to the largest remainders
/// (Hamilton's method), ties to the lower class: the closest integer counts to the fractions.
std::vector<long> class_counts(const std::vector<double>& fractions, long count) {
  std::vector<long> n;
  std::vector<std::pair<double, std::size_t>> remainders;
  long given = 0;
  for (std::size_t i = 0; i < fractions.size(); ++i) {
    const double exact = fractions[i] * static_cast<double>(count);
    n.push_back(static_cast<long>(std::floor(exact)));
    given += n.back();
    remainders.emplace_back(exact - std::floor(exact), i);
  }
  std::stable_sort(remainders.begin(), remainders.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t k = 0; given < count; ++k, ++given) ++n[remainders[k % remainders.size()].second];
  return n;
}

/// Triangles of a ring `inner` (ccw, at least 3 points, or one point: a fan) stitched to a ring `outer` (ccw) in the
/// plane, each ccw, by advancing along whichever ring is behind in angle (as pedestal_mesh).
using Point = std::array<double, 2>;
std::vector<std::array<Point, 3>> stitch(const std::vector<Point>& a, const std::vector<Point>& b) {
  std::vector<std::array<Point, 3>> tris;
  const std::size_t na = a.size(), nb = b.size();
  if (na == 1) {
    for (std::size_t j = 0; j < nb; ++j) tris.push_back({a[0], b[j], b[(j + 1) % nb]});
    return tris;
  }
  std::size_t i = 0, j = 0;
  while (i < na || j < nb) {
    const double ta = static_cast<double>(i + 1) / static_cast<double>(na);
    const double tb = static_cast<double>(j + 1) / static_cast<double>(nb);
    if (j < nb && (i >= na || tb <= ta)) {
      tris.push_back({a[i % na], b[j % nb], b[(j + 1) % nb]});
      ++j;
    } else {
      tris.push_back({a[i % na], b[j % nb], a[(i + 1) % na]});
      ++i;
    }
  }
  return tris;
}

std::vector<Point> polygon(double r, int n) {
  std::vector<Point> ring;
  for (int i = 0; i < n; ++i) ring.push_back({r * std::cos(2 * k_pi * i / n), r * std::sin(2 * k_pi * i / n)});
  return ring;
}

}  // namespace

double polygon_vertex_radius(double radius, int sides) {
  // A regular n-gon of circumradius ρ has the area n ρ² sin(2π/n) / 2; equal to π R² for this ρ.
  const double n = sides;
  return radius * std::sqrt(2 * k_pi / (n * std::sin(2 * k_pi / n)));
}

std::vector<Triangle> drum_mesh(double radius, double depth, int sides) {
  const double rv = polygon_vertex_radius(radius, sides);
  const std::vector<Point> outer = polygon(rv, sides);
  // Compact triangles on the end plates rather than a fan of long slivers from the centre: a triangle enters the
  // neighbour lists of every particle near its bounding box, and a sliver's box spans half the plate.
  std::vector<std::array<Point, 3>> plate = stitch({Point{0, 0}}, polygon(rv / 2, (sides + 1) / 2));
  for (const auto& t : stitch(polygon(rv / 2, (sides + 1) / 2), outer)) plate.push_back(t);
  std::vector<Triangle> tris;
  const auto at = [](const Point& p, double y) { return Vertex{p[0], y, p[1]}; };
  // The plane's ccw triangles have the normal −y in (x, z): as they are at y = depth (into the drum), reversed at
  // y = 0.
  for (const auto& t : plate) tris.push_back({at(t[0], 0.0), at(t[2], 0.0), at(t[1], 0.0)});
  for (std::size_t i = 0; i < outer.size(); ++i) {
    const Point& p = outer[i];
    const Point& q = outer[(i + 1) % outer.size()];
    tris.push_back({at(p, 0.0), at(q, 0.0), at(q, depth)});
    tris.push_back({at(p, 0.0), at(q, depth), at(p, depth)});
  }
  for (const auto& t : plate) tris.push_back({at(t[0], depth), at(t[1], depth), at(t[2], depth)});
  return tris;
}

double mean_particle_volume(const DrumSettings& s) {
  if (!s.diameters.empty()) {
    const std::vector<double> f = normalised_fractions(s);
    double v = 0;
    for (std::size_t i = 0; i < f.size(); ++i) v += f[i] * k_pi / 6 * std::pow(s.diameters[i], 3);
    return v;
  }
  // E[r³] of N(mean, sd) truncated to [r_min, r_max], by composite Simpson's rule (the density is smooth).
  const study::RadiusDistribution& d = s.radii;
  const int n = 2000;
  const double h = (d.r_max - d.r_min) / n;
  double mass = 0, third = 0;
  for (int i = 0; i <= n; ++i) {
    const double r = d.r_min + i * h;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    const double phi = std::exp(-0.5 * std::pow((r - d.mean) / d.sd, 2));
    mass += w * phi;
    third += w * phi * r * r * r;
  }
  return 4.0 / 3.0 * k_pi * third / mass;
}

double exact_fill_count(const DrumSettings& s) {
  const double full =
      s.particles > 0 ? static_cast<double>(s.particles) : s.bulk_volume * s.packing_fraction / mean_particle_volume(s);
  return full / std::pow(s.coarse_grain, 3);
}

long fill_count(const DrumSettings& s) {
  // Rounding is undefined beyond a long's range: a count that large is one no check lets through anyway.
  const double n = exact_fill_count(s);
  return n < 1e18 ? std::lround(n) : static_cast<long>(1e18);
}

namespace {

/// The face-centred cubic sites of the fill (nearest neighbours 2 r_max (1 + gap) apart, FCC holding 0.74 (d/a)³ of
/// its volume) inside the drum's flat sides less a radius and a gap, visited plane by plane of constant z from the
/// bottom, each plane's sites by x, then y. After each plane `enough(sites so far)` may stop the walk, so that a fill
/// at the bottom of a large drum never enumerates the whole drum.
template <class Visit, class Enough>
void walk_lattice(const DrumSettings& s, Visit visit, Enough enough) {
  const double r_max = full_r_max(s) * s.coarse_grain;
  const double gap = k_lattice_gap * 2 * r_max;
  const double c = (2 * r_max + gap) * std::sqrt(2.0);
  const double inner = polygon_vertex_radius(s.radius, s.wall_sides) * std::cos(k_pi / s.wall_sides) - r_max - gap;
  const double y_low = r_max + gap, y_high = s.depth - r_max - gap;
  if (!(inner > 0) || !(y_high >= y_low)) return;
  // Basis of the cubic cell (x, y, z in cell units), grouped by its z offset.
  const std::array<std::array<double, 2>, 2> at_z0{{{0, 0}, {0.5, 0.5}}};
  const std::array<std::array<double, 2>, 2> at_z1{{{0.5, 0}, {0, 0.5}}};
  const long cells_xz = static_cast<long>(std::ceil(inner / c)) + 1;
  const long cells_y = static_cast<long>(std::ceil((y_high - y_low) / c)) + 1;
  long visited = 0;
  for (long l = -cells_xz; l <= cells_xz; ++l)
    for (int half = 0; half < 2; ++half) {
      const double z = (static_cast<double>(l) + 0.5 * half) * c;
      if (std::abs(z) > inner) continue;
      const double chord = std::sqrt(inner * inner - z * z);
      const long i_low = static_cast<long>(std::floor(-chord / c)) - 1,
                 i_high = static_cast<long>(std::ceil(chord / c));
      std::vector<std::array<double, 3>> plane;
      for (long i = i_low; i <= i_high; ++i)
        for (long j = 0; j <= cells_y; ++j)
          for (const auto& b : half == 0 ? at_z0 : at_z1) {
            const double x = (static_cast<double>(i) + b[0]) * c;
            const double y = y_low + (static_cast<double>(j) + b[1]) * c;
            if (y > y_high + 1e-12 || x * x + z * z > inner * inner) continue;
            plane.push_back({x, y, z});
          }
      std::sort(plane.begin(), plane.end());
      for (const auto& p : plane) visit(p);
      visited += static_cast<long>(plane.size());
      if (enough(visited)) return;
    }
}

double lattice_spacing(const DrumSettings& s) { return 2 * full_r_max(s) * s.coarse_grain * (1 + k_lattice_gap); }

}  // namespace

long lattice_capacity(const DrumSettings& s, long wanted) {
  long sites = 0;
  walk_lattice(
      s, [&](const std::array<double, 3>&) { ++sites; }, [&](long n) { return n >= wanted; });
  return sites;
}

std::vector<Particle> build_fill(const DrumSettings& s, std::uint64_t seed) {
  const long count = fill_count(s);
  const double k = s.coarse_grain;
  // The lowest sites (then x, then y): the fill starts as a loose bed at the bottom of the drum.
  std::vector<std::array<double, 3>> sites;
  walk_lattice(
      s, [&](const std::array<double, 3>& p) { sites.push_back(p); }, [&](long n) { return n >= count; });
  if (static_cast<long>(sites.size()) < count)
    throw util::UserError(fmt::format(
        "[drum]: {} particles do not fit into the drum: it holds {} lattice sites {:.4g} m apart (lower bulk_volume "
        "or particles, or a smaller coarse_grain)",
        count, sites.size(), lattice_spacing(s)));
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), &gsl_rng_free);
  gsl_rng_set(rng.get(), static_cast<unsigned long>(seed));
  std::vector<double> radii;
  if (!s.diameters.empty()) {
    const std::vector<long> n = class_counts(normalised_fractions(s), count);
    for (std::size_t i = 0; i < n.size(); ++i)
      radii.insert(radii.end(), static_cast<std::size_t>(n[i]), s.diameters[i] / 2);
    gsl_ran_shuffle(rng.get(), radii.data(), radii.size(), sizeof(double));
  } else {
    radii = truncated_normal_radii(s.radii, static_cast<int>(count), gsl_rng_get(rng.get()));
  }
  for (double& r : radii) r *= k;
  std::vector<Particle> fill;
  for (long i = 0; i < count; ++i) {
    const auto& p = sites[static_cast<std::size_t>(i)];
    fill.push_back({p[0], p[1], p[2], radii[static_cast<std::size_t>(i)]});
  }
  return fill;
}

namespace {

/// The steps of the schedule (DrumDraft::write, case_cost).
struct Schedule {
  long settle = 0, spin_up = 0, window = 0, snapshot = 0;
  double period = 0;  ///< one turn [s]
  long snapshots() const { return window / snapshot; }
};

Schedule schedule(const DrumSettings& s, double dt) {
  Schedule t;
  t.settle = steps_for(s.settle_time, dt, "[drum] settle_time");
  t.spin_up = steps_for(s.spin_up, dt, "[drum] spin_up");
  t.snapshot = steps_for(s.snapshot_interval, dt, "[drum] snapshot_interval");
  // Whole snapshot intervals of the steps the window asks for, so that the window ends on a snapshot and lasts about
  // `window` even where the interval rounds to another number of steps (an interval below the time step is one step;
  // counting the intervals in seconds made its window a hundred times longer, or, beyond a long, one step).
  const long window = steps_for(s.window, dt, "[drum] window");
  t.window = std::max(1L, std::lround(static_cast<double>(window) / static_cast<double>(t.snapshot))) * t.snapshot;
  t.period = 60.0 / s.rpm;
  return t;
}

class DrumDraft final : public CaseDraft {
 public:
  DrumDraft(const StudyConfig& config, std::uint64_t seed)
      : m_config(config), m_fill(build_fill(settings(config), seed)) {}
  double smallest_radius() const override {
    double r = std::numeric_limits<double>::infinity();
    for (const Particle& p : m_fill) r = std::min(r, p.radius);
    return r;
  }
  CaseWritten write(const Material& m, const TimestepChoice& ts, Params& params, const fs::path& dir) const override;

 private:
  const StudyConfig& m_config;
  std::vector<Particle> m_fill;
};

CaseWritten DrumDraft::write(const Material& m, const TimestepChoice& ts, Params& params, const fs::path& dir) const {
  const DrumSettings& s = settings(m_config);
  const Schedule t = schedule(s, ts.dt);
  const bool clockwise = s.rotation == pp::DrumRotation::clockwise;
  params.comment("rotating drum: axis y, gravity -z, the camera looks along +y through the end plate at y = 0");
  params.integer("settle_steps", t.settle, "the fill settles in the drum at rest");
  params.integer("spin_up_steps", t.spin_up, "the drum turns before the first snapshot");
  params.integer("snapshot_steps", t.snapshot, "one snapshot every this many steps");
  params.integer("window_steps", t.window, "snapshots over this many steps");
  params.number("period", t.period, "one turn [s] = 60 / rpm");
  // A turn about +y by the right-hand rule carries +z towards +x: clockwise for the camera looking along +y.
  params.number("axis_y", clockwise ? 1.0 : -1.0,
                fmt::format("rotation axis (0, axis_y, 0): {} as the camera sees it", pp::to_string(s.rotation)));

  const double rv = polygon_vertex_radius(s.radius, s.wall_sides);
  const double margin = 0.05 * s.radius + 0.001;
  std::string data = data_header("demsa drum: the fill", static_cast<long>(m_fill.size()), -rv - margin, rv + margin,
                                 -margin, s.depth + margin, -rv - margin, rv + margin);
  long id = 0;
  for (const Particle& p : m_fill) data += atom_line(++id, p, m.density);
  write_text(dir / "drum_particles.data", data);
  const std::vector<Triangle> mesh = drum_mesh(s.radius, s.depth, s.wall_sides);
  write_text(dir / k_mesh_file, to_ascii_stl(mesh, "drum_wall"));
  write_text(dir / k_case_input, with_rolling_model(template_text("drum.liggghts"), m_config.contact));

  double r_min = std::numeric_limits<double>::infinity(), r_max = 0;
  for (const Particle& p : m_fill) r_min = std::min(r_min, p.radius), r_max = std::max(r_max, p.radius);
  CaseWritten w;
  w.particles = static_cast<long>(m_fill.size());
  w.assembly = {{"particles", m_fill.size()},
                {"coarse_grain", s.coarse_grain},
                {"radius_min_m", r_min},
                {"radius_max_m", r_max},
                {"placement", "face-centred cubic sites inside the drum, lowest first; radii shuffled by the seed"}};
  // Everything the measurement needs (drum.cpp), so that `demsa measure CASE` measures it the same way.
  w.experiment = {{"radius_m", s.radius},
                  {"depth_m", s.depth},
                  {"rpm", s.rpm},
                  {"rotation", pp::to_string(s.rotation)},
                  {"period_s", t.period},
                  {"wall_sides", s.wall_sides},
                  {"wall_vertex_radius_m", rv},
                  {"wall_triangles", mesh.size()},
                  {"coarse_grain", s.coarse_grain},
                  {"settle_steps", t.settle},
                  {"spin_up_steps", t.spin_up},
                  {"snapshot_steps", t.snapshot},
                  {"window_steps", t.window},
                  {"snapshots", t.snapshots()},
                  {"camera",
                   {{"looks_along", "+y"},
                    {"end_plate_y_m", 0.0},
                    {"image_x", "x"},
                    {"image_up", "z"},
                    {"drum_centre_xz_m", {0.0, 0.0}}}},
                  {"measurement",
                   {{"image_size", s.image_size},
                    {"judged_radius", s.judged_radius},
                    {"angle_half_width", s.angle_half_width},
                    {"stations", s.stations},
                    {"threshold", s.threshold}}}};
  w.experiment["analysed"] = observable_names(m_config);
  return w;
}

}  // namespace

std::unique_ptr<CaseDraft> draft_case(const StudyConfig& config, std::uint64_t assembly_seed) {
  return std::make_unique<DrumDraft>(config, assembly_seed);
}

// The schedule of drum.liggghts: settle_steps at rest, spin_up_steps and window_steps turning, every atom present
// throughout (none leaves a closed drum), as DrumDraft::write counts them above.
CaseCost case_cost(const StudyConfig& config, const nlohmann::json& case_json, const fs::path& file,
                   const nlohmann::json& /*probed*/) {
  const DrumSettings& s = settings(config);
  const std::optional<double> dt = case_number(case_json, file, "dt", 0.0, 1.0);
  if (!dt || *dt <= 0.0) throw util::UserError(fmt::format("{}: no time step (dt)", file.string()));
  const long atoms =
      case_integer(case_json, file, "assembly.particles", 0, std::numeric_limits<int>::max()).value_or(fill_count(s));
  const Schedule t = schedule(s, *dt);
  CaseCost cost;
  cost.steps = t.settle + t.spin_up + t.window;
  cost.particles = atoms;
  cost.atom_steps = static_cast<double>(cost.steps) * static_cast<double>(atoms);
  cost.may_end_early = false;
  cost.schedule = fmt::format("{} atoms for {} settling, {} spin-up and {} window steps ({} snapshots)", atoms,
                              t.settle, t.spin_up, t.window, t.snapshots());
  // A turning drum runs slower than the standard run (docs/how-to/cost.md, "The drum's rate"): its moving mesh wall
  // takes 35 % of its loop time (`Other` in its log) against 13 % of the standard run's, and its flowing bed rebuilds
  // the neighbour lists every ~90 steps (1453 builds in a 130,500-step window) against 16 builds in the standard run's
  // 4000 steps. Measured: the 8 cases of the coarse 45 rpm study ran 4.65e9 atom-steps
  // in 910.6 CPU-s (wait4's rusage), 5.11e6 a CPU-second, against the standard run's 8.68e6 with the same LIGGGHTS on
  // the same machine the same day (8.64e6-9.00e6 measured again three times).
  constexpr double k_drum_rate_factor = 0.588;
  cost.rate_factor = k_drum_rate_factor;
  cost.rate_factor_source = fmt::format(
      "x {:.3f}, the drum's atom-steps per CPU-second over the standard run's (the coarse 45 rpm study, 5.11e6 "
      "against 8.68e6, 2026-12-04; docs/how-to/cost.md)",
      k_drum_rate_factor);
  return cost;
}

}  // namespace demsa::experiments::drum
