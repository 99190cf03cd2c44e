#include "postprocess/drawdown.hpp"

#include "postprocess/error.hpp"
#include "postprocess/pile_angle.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace demsa::postprocess {

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

void DrawdownSlopeOptions::validate() const {
  const auto positive = [](double v, const char* name) {
    if (!(v > 0) || !std::isfinite(v)) throw std::invalid_argument(fmt::format("{} = {}: must be > 0", name, v));
  };
  positive(width, "width");
  positive(slot_width, "slot_width");
  positive(depth, "depth");
  positive(bin_width, "bin_width");
  if (!(slot_width < width))
    throw std::invalid_argument(fmt::format("slot_width = {}: must be below width", slot_width));
  if (!(edge_skip >= 0) || !(wall_skip >= 0)) throw std::invalid_argument("edge_skip and wall_skip must be >= 0");
  if (slices < 1) throw std::invalid_argument(fmt::format("slices = {}: must be >= 1", slices));
  if (min_points < 2) throw std::invalid_argument(fmt::format("min_points = {}: must be >= 2", min_points));
}

DrawdownSlope measure_drawdown_slope(const Particles& p, const DrawdownSlopeOptions& o, double density) {
  o.validate();
  DrawdownSlope result;
  std::vector<std::size_t> left;  // the material in the box
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.id[i] <= o.skip_ids || p.z[i] < o.floor_z) continue;
    left.push_back(i);
    result.mass_left += density * 4.0 / 3.0 * std::numbers::pi * p.radius[i] * p.radius[i] * p.radius[i];
  }
  result.particles_left = static_cast<long>(left.size());
  struct Side {
    double x0, x1;
    std::vector<double>* slices;
  };
  const Side sides[] = {{-o.width / 2 + o.wall_skip, -o.slot_width / 2 - o.edge_skip, &result.slices_left},
                        {o.slot_width / 2 + o.edge_skip, o.width / 2 - o.wall_skip, &result.slices_right}};
  for (const Side& side : sides) {
    const int bins = static_cast<int>(std::floor((side.x1 - side.x0) / o.bin_width));
    for (int s = 0; s < o.slices; ++s) {
      const double y0 = o.y_low + o.depth * s / o.slices, y1 = o.y_low + o.depth * (s + 1) / o.slices;
      // The highest particle top in each bin of the slice: the surface across the slope.
      std::vector<double> top(static_cast<std::size_t>(std::max(bins, 0)), -INFINITY), at_x(top.size(), 0.0);
      for (const std::size_t i : left) {
        const double y = o.y_low + std::fmod(std::fmod(p.y[i] - o.y_low, o.depth) + o.depth, o.depth);
        if (y < y0 || y >= y1 || p.x[i] < side.x0) continue;
        const int b = static_cast<int>(std::floor((p.x[i] - side.x0) / o.bin_width));
        if (b < 0 || b >= bins) continue;
        const double z = p.z[i] + p.radius[i];
        if (z > top[static_cast<std::size_t>(b)]) {
          top[static_cast<std::size_t>(b)] = z;
          at_x[static_cast<std::size_t>(b)] = p.x[i];
        }
      }
      std::vector<double> xs, zs;
      for (std::size_t b = 0; b < top.size(); ++b)
        if (std::isfinite(top[b])) xs.push_back(at_x[b]), zs.push_back(top[b]);
      result.profile_x.insert(result.profile_x.end(), xs.begin(), xs.end());
      result.profile_z.insert(result.profile_z.end(), zs.begin(), zs.end());
      if (static_cast<int>(xs.size()) < o.min_points) continue;
      const TheilSenLine line = fit_theil_sen_line(zs, xs);
      side.slices->push_back(std::atan(std::abs(line.slope)) * 180.0 / std::numbers::pi);
    }
    if (side.slices->empty())
      throw InputError(
          fmt::format("no slice has {} surface points on the {} side of the slot ({} particles left in "
                      "the box): no slope to measure",
                      o.min_points, side.x0 < 0 ? "left" : "right", result.particles_left));
  }
  result.angle_left = median(result.slices_left);
  result.angle_right = median(result.slices_right);
  result.angle = 0.5 * (result.angle_left + result.angle_right);
  return result;
}

DischargeRecord read_discharge(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw ParseError(path.string(), 0, "cannot be read");
  DischargeRecord r;
  std::string line;
  for (long number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    double t = 0, m = 0, atoms = 0;
    if (!(words >> t >> m >> atoms) || !std::isfinite(t) || !std::isfinite(m))
      throw ParseError(path.string(), number, fmt::format("expected 't_open discharged_kg atoms', got '{}'", line));
    // LIGGGHTS's mass(all) before and after nothing left differs in its last bits: a microgram below zero is zero.
    if (m < 0 && m > -1e-9) m = 0;
    if (m < 0) throw ParseError(path.string(), number, fmt::format("discharged mass {} kg below zero", m));
    if (!r.time.empty() && t < r.time.back())
      throw ParseError(path.string(), number, fmt::format("time {} s goes back (after {} s)", t, r.time.back()));
    r.time.push_back(t);
    r.mass.push_back(m);
  }
  return r;
}

double discharge_rate(const DischargeRecord& r) {
  if (r.mass.empty()) throw InputError("no discharge recorded");
  const double final_mass = r.mass.back();
  if (!(final_mass > 0)) throw InputError("nothing was discharged: no rate to measure");
  std::vector<double> t, m;
  for (std::size_t i = 0; i < r.mass.size(); ++i)
    if (r.mass[i] >= 0.2 * final_mass && r.mass[i] <= 0.8 * final_mass) t.push_back(r.time[i]), m.push_back(r.mass[i]);
  if (t.size() < 2 || t.front() == t.back())
    throw InputError(fmt::format("{} record(s) between 20 % and 80 % of the discharged {} kg: no rate to measure",
                                 t.size(), final_mass));
  // Ordinary least squares of mass on time.
  double mt = 0, mm = 0;
  for (std::size_t i = 0; i < t.size(); ++i) mt += t[i] / t.size(), mm += m[i] / m.size();
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < t.size(); ++i) sxy += (t[i] - mt) * (m[i] - mm), sxx += (t[i] - mt) * (t[i] - mt);
  return sxy / sxx;
}

}  // namespace demsa::postprocess
