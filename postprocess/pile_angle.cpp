#include "postprocess/pile_angle.hpp"

#include "postprocess/measures.hpp"

#include <fmt/core.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace demsa::postprocess {

BoundaryPointKind boundary_point_kind_from_string(const std::string& name) {
  if (name == "surface") return BoundaryPointKind::surface;
  if (name == "centre" || name == "center") return BoundaryPointKind::centre;
  throw std::invalid_argument(fmt::format("unknown boundary point '{}' (valid: surface, centre)", name));
}

std::string to_string(BoundaryPointKind kind) {
  switch (kind) {
    case BoundaryPointKind::surface:
      return "surface";
    case BoundaryPointKind::centre:
      return "centre";
  }
  assert(false && "unhandled BoundaryPointKind");
  return {};
}

AngleEstimator angle_estimator_from_string(const std::string& name) {
  if (name == "paper") return AngleEstimator::paper;
  if (name == "robust") return AngleEstimator::robust;
  throw std::invalid_argument(fmt::format("unknown angle estimator '{}' (valid: paper, robust)", name));
}

std::string to_string(AngleEstimator estimator) {
  switch (estimator) {
    case AngleEstimator::paper:
      return "paper";
    case AngleEstimator::robust:
      return "robust";
  }
  assert(false && "unhandled AngleEstimator");
  return {};
}

std::vector<std::string> angle_estimator_names() { return {"paper", "robust"}; }

double PileAngleOptions::low_level() const {
  if (level_low) return *level_low;
  return estimator == AngleEstimator::robust ? k_robust_level_low : k_paper_level_low;
}

double PileAngleOptions::high_level() const {
  if (level_high) return *level_high;
  return estimator == AngleEstimator::robust ? k_robust_level_high : k_paper_level_high;
}

void PileAngleOptions::validate() const {
  auto bad = [](const char* field, double value, const char* rule) {
    return std::invalid_argument(fmt::format("PileAngleOptions.{} = {}: {}", field, value, rule));
  };
  if (!(pedestal_radius > 0.0) || !std::isfinite(pedestal_radius))
    throw bad("pedestal_radius", pedestal_radius, "must be a positive length [m]");
  if (!std::isfinite(pedestal_top)) throw bad("pedestal_top", pedestal_top, "must be finite [m]");
  if (!std::isfinite(axis_x)) throw bad("axis_x", axis_x, "must be finite [m]");
  if (!std::isfinite(axis_y)) throw bad("axis_y", axis_y, "must be finite [m]");
  if (particle_type < 0) throw bad("particle_type", particle_type, "must be 0 (all atoms) or an atom type >= 1");
  if (directions < 1) throw bad("directions", directions, "must be at least 1");
  if (levels < 2) throw bad("levels", levels, "must be at least 2");
  const double low = low_level();
  const double high = high_level();
  if (!(low > 0.0 && low < 1.0)) throw bad("level_low", low, "must be in (0, 1)");
  if (!(high > low && high < 1.0))
    throw bad("level_high", high, fmt::format("must be in (level_low = {}, 1)", low).c_str());
  if (min_points < 2) throw bad("min_points", min_points, "must be at least 2 (a line needs two points)");
  if (!std::isfinite(target_angle)) throw bad("target_angle", target_angle, "must be finite [deg]");
}

std::vector<std::size_t> pedestal_particles(const Particles& particles, const PileAngleOptions& options) {
  // Paper §3.2: particles off the pedestal or below its upper edge are removed before measuring.
  std::vector<std::size_t> kept;
  for (std::size_t j = 0; j < particles.size(); ++j) {
    if (options.particle_type > 0 && particles.type[j] != options.particle_type) continue;
    const double rho = std::hypot(particles.x[j] - options.axis_x, particles.y[j] - options.axis_y);
    if (rho <= options.pedestal_radius && particles.z[j] >= options.pedestal_top) kept.push_back(j);
  }
  return kept;
}

TlsLine fit_tls_line(const std::vector<double>& u, const std::vector<double>& v) {
  assert(u.size() == v.size() && u.size() >= 2);
  const Eigen::Index n = static_cast<Eigen::Index>(u.size());
  TlsLine line;
  for (Eigen::Index j = 0; j < n; ++j) {
    line.u0 += u[static_cast<std::size_t>(j)];
    line.v0 += v[static_cast<std::size_t>(j)];
  }
  line.u0 /= static_cast<double>(n);
  line.v0 /= static_cast<double>(n);
  Eigen::MatrixX2d centred(n, 2);
  for (Eigen::Index j = 0; j < n; ++j) {
    centred(j, 0) = u[static_cast<std::size_t>(j)] - line.u0;
    centred(j, 1) = v[static_cast<std::size_t>(j)] - line.v0;
  }
  // Total least squares: the line minimising the sum of squared orthogonal distances passes through the centroid
  // along the first right singular vector of the centred points; the second singular value is the residual norm
  // (Golub & Van Loan, Matrix Computations, §12.3).
  const Eigen::JacobiSVD<Eigen::MatrixX2d> svd(centred, Eigen::ComputeFullV);
  const Eigen::Vector2d dir = svd.matrixV().col(0);
  line.du = dir(0);
  line.dv = dir(1);
  if (line.du < 0.0 || (line.du == 0.0 && line.dv < 0.0)) {
    line.du = -line.du;
    line.dv = -line.dv;
  }
  line.rms_distance = svd.singularValues()(1) / std::sqrt(static_cast<double>(n));
  return line;
}

namespace {

double median_of(std::vector<double>& values) {
  assert(!values.empty());
  const std::size_t n = values.size();
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(values.begin(), mid, values.end());
  if (n % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(values.begin(), mid));
}

}  // namespace

TheilSenLine fit_theil_sen_line(const std::vector<double>& u, const std::vector<double>& v) {
  assert(u.size() == v.size() && u.size() >= 2);
  // Theil (1950), Sen (1968): the median of the slopes of all pairs of points, then the median intercept.
  std::vector<double> slopes;
  slopes.reserve(u.size() * (u.size() - 1) / 2);
  for (std::size_t j = 0; j < u.size(); ++j)
    for (std::size_t k = j + 1; k < u.size(); ++k)
      if (v[k] != v[j]) slopes.push_back((u[k] - u[j]) / (v[k] - v[j]));
  assert(!slopes.empty() && "Theil-Sen needs two distinct v");
  TheilSenLine line;
  line.slope = median_of(slopes);
  std::vector<double> intercepts(u.size());
  for (std::size_t j = 0; j < u.size(); ++j) intercepts[j] = u[j] - line.slope * v[j];
  line.intercept = median_of(intercepts);
  return line;
}

PileAngleResult measure_pile_angle(const Particles& particles, const PileAngleOptions& requested) {
  requested.validate();
  PileAngleOptions options = requested;
  const bool robust = options.estimator == AngleEstimator::robust;
  if (robust) options.point = BoundaryPointKind::surface;  // exact heights: the roughness is all radial
  options.level_low = options.low_level();                 // the band measured, echoed in the result
  options.level_high = options.high_level();
  PileAngleResult result;
  result.options = options;
  for (std::size_t j = 0; j < particles.size(); ++j)
    if (options.particle_type == 0 || particles.type[j] == options.particle_type) ++result.particles_total;

  const std::vector<std::size_t> kept = pedestal_particles(particles, options);
  result.particles_on_pedestal = kept.size();
  if (kept.empty())
    throw InputError(fmt::format(
        "no particle{} on the pedestal (centre within {} m of the axis at ({}, {}) and at or above z = {} m) among "
        "{} atoms",
        options.particle_type > 0 ? fmt::format(" of type {}", options.particle_type) : std::string(),
        options.pedestal_radius, options.axis_x, options.axis_y, options.pedestal_top, particles.size()));

  // h_P: the top of the highest particle above the pedestal top (paper §3.2, determined during the filter).
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t j : kept) top = std::max(top, particles.z[j] + particles.radius[j]);
  result.pile_height = top - options.pedestal_top;
  if (!(result.pile_height > 0.0))
    throw InputError(
        fmt::format("pile height h_P = {} m: the particles on the pedestal have no extent", result.pile_height));

  // The robust estimator's default band starts no lower than k_robust_floor_radii largest radii above the pedestal
  // top: below that the cross-section meets the particles resting on the pedestal's edge, which crowd the foot of a
  // shallow flank (see k_robust_floor_radii).
  if (robust && !requested.level_low) {
    double r_max = 0.0;
    for (std::size_t j : kept) r_max = std::max(r_max, particles.radius[j]);
    const double floor = k_robust_floor_radii * r_max / result.pile_height;
    if (floor > *options.level_low && floor < *options.level_high) options.level_low = floor;
    result.options.level_low = options.level_low;
  }
  // Equidistant levels between level_low h_P and level_high h_P (paper §3.3: 0.2 h_P and 0.75 h_P).
  const int nl = options.levels;
  const int nd = options.directions;
  result.level_heights.resize(static_cast<std::size_t>(nl));
  for (int k = 0; k < nl; ++k)
    result.level_heights[static_cast<std::size_t>(k)] =
        result.pile_height *
        (*options.level_low + (*options.level_high - *options.level_low) * static_cast<double>(k) / (nl - 1));

  // Directions e_i = (cos φ_i, −sin φ_i), φ_i = 360° i / φ_N (paper eq. 9); n_i is the horizontal normal of the
  // vertical half-plane spanned by e_i and the z axis.
  std::vector<double> ex(static_cast<std::size_t>(nd)), ey(ex.size()), nx(ex.size()), ny(ex.size());
  for (int i = 0; i < nd; ++i) {
    const double phi = 2.0 * std::numbers::pi * static_cast<double>(i) / nd;
    ex[static_cast<std::size_t>(i)] = std::cos(phi);
    ey[static_cast<std::size_t>(i)] = -std::sin(phi);
    nx[static_cast<std::size_t>(i)] = std::sin(phi);
    ny[static_cast<std::size_t>(i)] = std::cos(phi);
  }

  // For every (direction, level) cell the particle reaching furthest out (paper §3.3: "the particle with the
  // largest radial distance"). A particle is in the cell when its sphere meets the direction's half-plane and the
  // level's horizontal plane; in that cross-section its outline is a circle of radius r' = sqrt(r² − d²), d being
  // the distance of its centre from the half-plane.
  const std::size_t cells = static_cast<std::size_t>(nd) * static_cast<std::size_t>(nl);
  const double none = -std::numeric_limits<double>::infinity();
  std::vector<double> best_value(cells, none);
  std::vector<double> best_radial(cells, 0.0), best_height(cells, 0.0);
  std::vector<std::size_t> best_index(cells, 0);
  const bool surface = options.point == BoundaryPointKind::surface;
  const auto offer = [&](std::size_t cell, std::size_t j, double value, double radial, double height) {
    if (value > best_value[cell]) {
      best_value[cell] = value;
      best_index[cell] = j;
      best_radial[cell] = radial;
      best_height[cell] = height;
    }
  };
  if (robust) {
    // The pile's horizontal section at each level, its outermost radius in a sector about each direction: a particle
    // counts for direction i when its outer arc (radius ρ_c + r) lies within its own radius r of the direction,
    // |Δφ| (ρ_c + r) ≤ r, and it reaches ρ_c + sqrt(r² − dz²) at the level, measured in its own azimuth. The
    // half-plane cross-section the paper uses lets a particle count over |Δφ| ≤ asin(r/ρ_c), a window that widens
    // towards the top of a cone, where ρ_c is smallest and falls fastest with r sin θ; the outermost of more
    // candidates reaches further out, most on a steep rough flank, whose upper levels then read further out than its
    // lower ones (synthetic cones with Gaussian normal jitter of 1.5 mm: the mean surface point rose by 0.4–0.5 mm from
    // the lowest to the highest level at 37–45°, +0.2° to +0.55° on the angle; docs/explanation/benchmarks.md). The
    // sector's width at the surface is constant over the height, and so is the number of particles competing for a
    // cell.
    for (std::size_t j : kept) {
      const double px = particles.x[j] - options.axis_x;
      const double py = particles.y[j] - options.axis_y;
      const double pz = particles.z[j] - options.pedestal_top;
      const double r = particles.radius[j];
      const double rho = std::hypot(px, py);
      const double az = std::atan2(-py, px);  // φ of e = (cos φ, −sin φ)
      const double half_width = r / (rho + r);
      for (int i = 0; i < nd; ++i) {
        const double phi = 2.0 * std::numbers::pi * static_cast<double>(i) / nd;
        if (std::fabs(std::remainder(az - phi, 2.0 * std::numbers::pi)) > half_width) continue;
        for (int k = 0; k < nl; ++k) {
          const double zk = result.level_heights[static_cast<std::size_t>(k)];
          const double dz = pz - zk;
          if (std::fabs(dz) > r) continue;
          const double reach = rho + std::sqrt(r * r - dz * dz);
          offer(static_cast<std::size_t>(i) * static_cast<std::size_t>(nl) + static_cast<std::size_t>(k), j, reach,
                reach, zk);
        }
      }
    }
  } else {
    for (std::size_t j : kept) {
      const double px = particles.x[j] - options.axis_x;
      const double py = particles.y[j] - options.axis_y;
      const double pz = particles.z[j] - options.pedestal_top;
      const double r = particles.radius[j];
      for (int i = 0; i < nd; ++i) {
        const std::size_t ui = static_cast<std::size_t>(i);
        const double d = px * nx[ui] + py * ny[ui];
        if (std::fabs(d) > r) continue;
        const double s = px * ex[ui] + py * ey[ui];
        const double rs = std::sqrt(r * r - d * d);
        if (s + rs < 0.0) continue;  // lies on the opposite half-plane
        for (int k = 0; k < nl; ++k) {
          const double zk = result.level_heights[static_cast<std::size_t>(k)];
          const double dz = pz - zk;
          if (std::fabs(dz) > rs) continue;
          const double reach = s + std::sqrt(rs * rs - dz * dz);
          const double value = surface ? reach : s;
          offer(ui * static_cast<std::size_t>(nl) + static_cast<std::size_t>(k), j, value, surface ? reach : s,
                surface ? zk : pz);
        }
      }
    }
  }

  // One orthogonal line per direction in the (radial distance, height) plane; its angle (paper §3.3, Fig. 4b).
  std::vector<double> angles;
  result.lines.reserve(static_cast<std::size_t>(nd));
  std::vector<double> u, v;
  for (int i = 0; i < nd; ++i) {
    const std::size_t ui = static_cast<std::size_t>(i);
    DirectionLine line;
    line.direction = i;
    line.phi = 360.0 * static_cast<double>(i) / nd;
    line.ex = ex[ui];
    line.ey = ey[ui];
    u.clear();
    v.clear();
    for (int k = 0; k < nl; ++k) {
      const std::size_t cell = ui * static_cast<std::size_t>(nl) + static_cast<std::size_t>(k);
      if (best_value[cell] == none) continue;
      const std::size_t j = best_index[cell];
      BoundaryParticle b;
      b.direction = i;
      b.level = k;
      b.index = j;
      b.id = particles.id[j];
      b.x = particles.x[j];
      b.y = particles.y[j];
      b.z = particles.z[j];
      b.radius = particles.radius[j];
      b.radial = best_radial[cell];
      b.height = best_height[cell];
      result.boundary.push_back(b);
      u.push_back(b.radial);
      v.push_back(b.height);
    }
    line.points = static_cast<int>(u.size());
    // A line needs points that differ (one particle may be the boundary at every level).
    const bool distinct =
        !u.empty() &&
        (*std::max_element(u.begin(), u.end()) - *std::min_element(u.begin(), u.end()) > 1e-9 * result.pile_height ||
         *std::max_element(v.begin(), v.end()) - *std::min_element(v.begin(), v.end()) > 1e-9 * result.pile_height);
    const bool two_heights =
        !v.empty() && *std::max_element(v.begin(), v.end()) > *std::min_element(v.begin(), v.end());
    if (robust && line.points >= options.min_points && two_heights) {
      // Radial distance on height: the heights are the exact level heights, so ordinary (not orthogonal)
      // regression of u on v is the right model, made robust by Theil-Sen.
      const TheilSenLine fit = fit_theil_sen_line(u, v);
      line.used = true;
      // u = a + b v falls outwards when b < 0: angle atan(1/|b|); a flank leaning inwards gives a negative angle.
      line.angle =
          (fit.slope <= 0.0 ? std::atan2(1.0, -fit.slope) : -std::atan2(1.0, fit.slope)) * 180.0 / std::numbers::pi;
      const double norm = std::sqrt(1.0 + fit.slope * fit.slope);
      double ss = 0.0;
      for (std::size_t p = 0; p < u.size(); ++p) {
        const double d = (u[p] - fit.intercept - fit.slope * v[p]) / norm;
        ss += d * d;
      }
      line.rms_distance = std::sqrt(ss / static_cast<double>(u.size()));
      line.height_low = *std::min_element(v.begin(), v.end());
      line.height_high = *std::max_element(v.begin(), v.end());
      line.radial_low = fit.intercept + fit.slope * line.height_low;
      line.radial_high = fit.intercept + fit.slope * line.height_high;
      angles.push_back(line.angle);
    } else if (!robust && line.points >= options.min_points && distinct) {
      const TlsLine fit = fit_tls_line(u, v);
      line.used = true;
      line.angle = std::atan2(-fit.dv, fit.du) * 180.0 / std::numbers::pi;
      line.rms_distance = fit.rms_distance;
      double t_min = std::numeric_limits<double>::infinity();
      double t_max = -t_min;
      for (std::size_t p = 0; p < u.size(); ++p) {
        const double t = (u[p] - fit.u0) * fit.du + (v[p] - fit.v0) * fit.dv;
        t_min = std::min(t_min, t);
        t_max = std::max(t_max, t);
      }
      // Segment ends ordered by height: "low" is the end nearer the pedestal.
      double ua = fit.u0 + t_min * fit.du, va = fit.v0 + t_min * fit.dv;
      double ub = fit.u0 + t_max * fit.du, vb = fit.v0 + t_max * fit.dv;
      if (va > vb) {
        std::swap(ua, ub);
        std::swap(va, vb);
      }
      line.radial_low = ua;
      line.height_low = va;
      line.radial_high = ub;
      line.height_high = vb;
      angles.push_back(line.angle);
    }
    result.lines.push_back(line);
  }
  result.directions_used = static_cast<int>(angles.size());
  if (angles.empty())
    throw InputError(fmt::format(
        "no direction has {} boundary points between {} h_P and {} h_P (h_P = {} m, {} particles on the pedestal): "
        "not a pile",
        options.min_points, *options.level_low, *options.level_high, result.pile_height, kept.size()));

  // The angle of repose is the mean over the directions (paper §3.3), or for the robust estimator their median (a
  // mound or a hole on one side of the flank tilts the lines of the directions that cross it, the median of the
  // directions not); also their spread about the mean.
  double sum = 0.0;
  for (double a : angles) sum += a;
  const double mean = sum / static_cast<double>(angles.size());
  result.angle = mean;
  if (robust) {
    std::vector<double> sorted = angles;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t n = sorted.size();
    result.angle = n % 2 == 1 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  }
  // A pile's flank falls outward: its angle lies in (0°, 90°). Outside it the particles on the pedestal are a bowl, a
  // ring or a scattering (a snapshot before the pile formed, a pile that slid off), and no angle of repose exists.
  if (!(result.angle > 0.0 && result.angle < 90.0))
    throw InputError(fmt::format(
        "angle {:.3g}° over {} directions (h_P = {} m, {} particles on the pedestal): their outer edge does not fall "
        "outward, no pile to measure",
        result.angle, angles.size(), result.pile_height, kept.size()));
  double ss = 0.0;
  for (double a : angles) ss += (a - mean) * (a - mean);
  result.angle_sd = angles.size() > 1 ? std::sqrt(ss / static_cast<double>(angles.size() - 1)) : 0.0;
  result.angle_min = *std::min_element(angles.begin(), angles.end());
  result.angle_max = *std::max_element(angles.begin(), angles.end());
  result.angle_error = angle_error(result.angle, options.target_angle);
  return result;
}

}  // namespace demsa::postprocess
