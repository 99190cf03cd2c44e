#include "postprocess/dump_compare.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace demsa::postprocess {

namespace {

/// Row indices of `p` sorted by id; throws InputError on a duplicate id.
std::vector<std::size_t> order_by_id(const Particles& p, const std::string& name) {
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&p](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  for (std::size_t k = 1; k < order.size(); ++k)
    if (p.id[order[k]] == p.id[order[k - 1]])
      throw InputError(fmt::format("{}: atom id {} appears twice", name, p.id[order[k]]));
  return order;
}

}  // namespace

void CompareOptions::validate() const {
  auto check = [](const char* field, double value) {
    if (!(value >= 0.0) || !std::isfinite(value))
      throw std::invalid_argument(fmt::format("CompareOptions.{} = {}: must be finite and >= 0", field, value));
  };
  check("position_tolerance", position_tolerance);
  check("radius_tolerance", radius_tolerance);
  check("angle_tolerance", angle_tolerance);
  if (pile) pile_options.validate();
  if (pile && pile_options_b) pile_options_b->validate();
}

DumpComparison compare_particles(const Particles& a, const Particles& b, const CompareOptions& options,
                                 const std::string& name_a, const std::string& name_b) {
  options.validate();
  DumpComparison out;
  out.options = options;
  out.particles_a = a.size();
  out.particles_b = b.size();
  const std::vector<std::size_t> oa = order_by_id(a, name_a);
  const std::vector<std::size_t> ob = order_by_id(b, name_b);

  // Merge the two id-sorted lists.
  double sum_sq = 0.0;
  std::size_t i = 0, j = 0;
  auto list = [&options](std::vector<std::int64_t>& ids, std::int64_t id) {
    if (ids.size() < options.max_listed) ids.push_back(id);
  };
  while (i < oa.size() || j < ob.size()) {
    if (j == ob.size() || (i < oa.size() && a.id[oa[i]] < b.id[ob[j]])) {
      ++out.missing;
      list(out.missing_ids, a.id[oa[i]]);
      ++i;
    } else if (i == oa.size() || b.id[ob[j]] < a.id[oa[i]]) {
      ++out.extra;
      list(out.extra_ids, b.id[ob[j]]);
      ++j;
    } else {
      const std::size_t ka = oa[i], kb = ob[j];
      const double dx = b.x[kb] - a.x[ka], dy = b.y[kb] - a.y[ka], dz = b.z[kb] - a.z[ka];
      const double d2 = dx * dx + dy * dy + dz * dz;
      sum_sq += d2;
      const double d = std::sqrt(d2);
      if (out.common == 0 || d > out.max_displacement) {
        out.max_displacement = d;
        out.max_displacement_id = a.id[ka];
      }
      const double dr = std::fabs(b.radius[kb] - a.radius[ka]);
      out.max_radius_difference = std::max(out.max_radius_difference, dr);
      if (dr > options.radius_tolerance) {
        ++out.radius_mismatches;
        list(out.radius_mismatch_ids, a.id[ka]);
      }
      ++out.common;
      ++i;
      ++j;
    }
  }
  if (out.common > 0) out.rms_displacement = std::sqrt(sum_sq / static_cast<double>(out.common));

  if (out.missing > 0)
    out.violations.push_back(fmt::format("{} ids of {} are missing in {}", out.missing, name_a, name_b));
  if (out.extra > 0) out.violations.push_back(fmt::format("{} ids of {} are not in {}", out.extra, name_b, name_a));
  if (out.max_displacement > options.position_tolerance)
    out.violations.push_back(fmt::format("maximum displacement {:.6g} m (id {}) exceeds the tolerance {:.6g} m",
                                         out.max_displacement, out.max_displacement_id, options.position_tolerance));
  if (out.radius_mismatches > 0)
    out.violations.push_back(fmt::format("{} radii differ by more than {:.6g} m (largest difference {:.6g} m)",
                                         out.radius_mismatches, options.radius_tolerance, out.max_radius_difference));

  if (options.pile) {
    // The pile measure knows particles, not files: say which of the two it failed on.
    auto measure = [](const Particles& p, const PileAngleOptions& pile_options, const std::string& name) {
      try {
        return measure_pile_angle(p, pile_options);
      } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", name, e.what()));
      }
    };
    const PileAngleResult pa = measure(a, options.pile_options, name_a);
    const PileAngleResult pb = measure(b, options.pile_options_b.value_or(options.pile_options), name_b);
    PileDifference d;
    d.angle_a = pa.angle;
    d.angle_b = pb.angle;
    d.angle_difference = pb.angle - pa.angle;
    d.height_a = pa.pile_height;
    d.height_b = pb.pile_height;
    d.height_difference = pb.pile_height - pa.pile_height;
    if (std::fabs(d.angle_difference) > options.angle_tolerance)
      out.violations.push_back(fmt::format("angle of repose differs by {:.4g} deg ({:.4g} vs {:.4g}), tolerance {:.4g}",
                                           d.angle_difference, d.angle_a, d.angle_b, options.angle_tolerance));
    if (std::fabs(d.height_difference) > options.position_tolerance)
      out.violations.push_back(fmt::format("pile height h_P differs by {:.6g} m ({:.6g} vs {:.6g}), tolerance {:.6g} m",
                                           d.height_difference, d.height_a, d.height_b, options.position_tolerance));
    out.pile = d;
  }
  return out;
}

DumpComparison compare_dumps(const std::filesystem::path& a, const std::filesystem::path& b,
                             const CompareOptions& options) {
  options.validate();
  const Particles pa = read_particles(a);
  const Particles pb = read_particles(b);
  return compare_particles(pa, pb, options, a.string(), b.string());
}

}  // namespace demsa::postprocess
