#include "sobol/design.hpp"

#include "sobol/enum_names.hpp"

#include "sobol/error.hpp"
#include "sobol/random.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

namespace demsa::sobol {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// ---------------------------------------------------------------- criteria with O(n) updates for a column swap
//
// Both criteria are updated incrementally when the values of rows r1 and r2 in column k are exchanged, which is the
// move of every LHS optimiser (it keeps the Latin property).

/// φ_p = (Σ_{i<j} d_ij^-p)^(1/p) (Morris & Mitchell 1995, eq. 2.3). Stores the squared distances and their terms
/// d^-p (symmetric matrices, read by columns).
class PhiPCriterion {
 public:
  PhiPCriterion(const Eigen::MatrixXd& x, double p)
      : m_x(x),
        m_p(p),
        m_half_power(std::floor(0.5 * p) == 0.5 * p && p <= 400 ? static_cast<int>(0.5 * p) : 0),
        m_d2(x.rows(), x.rows()),
        m_t(x.rows(), x.rows()) {
    const Eigen::Index n = x.rows();
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = 0; j < n; ++j) m_d2(i, j) = (x.row(i) - x.row(j)).squaredNorm();
    recompute();
  }
  double value() const { return std::pow(m_sum, 1.0 / m_p); }
  /// Criterion after swapping column k of rows r1, r2 (state unchanged).
  double trial(Eigen::Index r1, Eigen::Index r2, Eigen::Index k) const {
    return std::pow(sum_after(r1, r2, k).value, 1.0 / m_p);
  }
  void apply(Eigen::Index r1, Eigen::Index r2, Eigen::Index k) {
    const Sum after = sum_after(r1, r2, k);
    m_sum = after.value;
    m_scale = after.exact ? m_sum : std::max(m_scale, m_sum);
    const double a = m_x(r1, k), b = m_x(r2, k);
    for (Eigen::Index j = 0; j < m_x.rows(); ++j) {
      if (j == r1 || j == r2) continue;
      const double c = m_x(j, k);
      m_d2(j, r1) = moved(m_d2(j, r1), a, b, c);
      m_d2(j, r2) = moved(m_d2(j, r2), b, a, c);
      m_d2(r1, j) = m_d2(j, r1);
      m_d2(r2, j) = m_d2(j, r2);
      m_t(j, r1) = m_t(r1, j) = term(m_d2(j, r1));
      m_t(j, r2) = m_t(r2, j) = term(m_d2(j, r2));
    }
    std::swap(m_x(r1, k), m_x(r2, k));
    if (++m_updates % 1000 == 0) recompute();  // bound the drift of the running sum
  }
  const Eigen::MatrixXd& points() const { return m_x; }

 private:
  /// Squared distance after one coordinate moves from `from` to `to` (the other point's coordinate is c). Every
  /// update goes through this one expression, so a term added to the running sum is removed later bit for bit.
  static double moved(double d2, double from, double to, double c) {
    return d2 + ((to - c) * (to - c) - (from - c) * (from - c));
  }
  /// d^-p from d²: repeated squaring when p/2 is a whole number (p = 50: 6 multiplications), else pow.
  double term(double d2) const {
    if (m_half_power <= 0) return std::pow(d2, -0.5 * m_p);
    double base = 1.0 / d2, out = 1.0;
    for (int e = m_half_power; e > 0; e >>= 1, base *= base)
      if (e & 1) out *= base;
    return out;
  }
  void recompute() {
    m_sum = 0.0;
    for (Eigen::Index j = 0; j < m_x.rows(); ++j)
      for (Eigen::Index i = 0; i < m_x.rows(); ++i) {
        m_t(i, j) = term(m_d2(i, j));
        if (i < j) m_sum += m_t(i, j);
      }
    m_scale = m_sum;
  }
  struct Sum {
    double value;
    bool exact;  ///< summed afresh
  };
  /// Σ d^-p after the swap. The terms span many decades (d^-50): the running sum carries an absolute rounding error
  /// of a few ulps of the largest value it has held since it was last summed afresh (m_scale), so once it falls
  /// below 1e-6 of that scale it is summed afresh. (Comparing with the previous value only, one step at a time,
  /// lets a sum that shrinks by 10^2 per step keep the error of its largest value: φ_p off by 30 %.)
  Sum sum_after(Eigen::Index r1, Eigen::Index r2, Eigen::Index k) const {
    const double updated = m_sum + delta(r1, r2, k);
    if (updated > 1e-6 * m_scale) return {updated, false};
    const double a = m_x(r1, k), b = m_x(r2, k);
    double sum = 0.0;
    for (Eigen::Index i = 0; i < m_x.rows(); ++i)
      for (Eigen::Index j = i + 1; j < m_x.rows(); ++j) {
        double d2 = m_d2(i, j);
        const bool touches1 = i == r1 || j == r1, touches2 = i == r2 || j == r2;
        if (touches1 != touches2) {  // a pair with exactly one swapped row changes
          const Eigen::Index other = (i == r1 || i == r2) ? j : i;
          const double c = m_x(other, k);
          d2 = touches1 ? moved(d2, a, b, c) : moved(d2, b, a, c);
        }
        sum += term(d2);
      }
    return {sum, true};
  }
  double delta(Eigen::Index r1, Eigen::Index r2, Eigen::Index k) const {
    const double a = m_x(r1, k), b = m_x(r2, k);
    double change = 0.0;
    for (Eigen::Index j = 0; j < m_x.rows(); ++j) {
      if (j == r1 || j == r2) continue;
      const double c = m_x(j, k);
      const double n1 = moved(m_d2(j, r1), a, b, c);
      const double n2 = moved(m_d2(j, r2), b, a, c);
      change += term(n1) + term(n2) - m_t(j, r1) - m_t(j, r2);
    }
    return change;  // d(r1, r2) is unchanged by the swap
  }

  Eigen::MatrixXd m_x;
  double m_p;
  int m_half_power;  ///< p/2 when it is a whole number, else 0
  Eigen::MatrixXd m_d2;
  Eigen::MatrixXd m_t;  ///< term(m_d2)
  double m_sum = 0.0;
  double m_scale = 0.0;  ///< largest running sum since the last exact sum
  long m_updates = 0;
};

/// Centred L2 discrepancy (Hickernell 1998, eq. 5.1c), squared, with the pair products c_ij and row products g_i
/// kept for O(n) updates (Fang, Ma, Winker 2002, "Centered L2-discrepancy of random sampling and Latin hypercube
/// design", for the update idea).
class Cl2Criterion {
 public:
  explicit Cl2Criterion(const Eigen::MatrixXd& x) : m_x(x), m_c(x.rows(), x.rows()), m_g(x.rows()) {
    const Eigen::Index n = x.rows();
    for (Eigen::Index i = 0; i < n; ++i) {
      m_g(i) = row_factor(i);
      for (Eigen::Index j = 0; j < n; ++j) m_c(i, j) = pair_factor(i, j);
    }
    recompute();
  }
  double value() const { return std::sqrt(std::max(m_value2, 0.0)); }
  double trial(Eigen::Index r1, Eigen::Index r2, Eigen::Index k) const {
    return std::sqrt(std::max(m_value2 + delta(r1, r2, k), 0.0));
  }
  void apply(Eigen::Index r1, Eigen::Index r2, Eigen::Index k) {
    m_value2 += delta(r1, r2, k);
    std::swap(m_x(r1, k), m_x(r2, k));
    for (const Eigen::Index r : {r1, r2}) {
      m_g(r) = row_factor(r);
      for (Eigen::Index j = 0; j < m_x.rows(); ++j) {
        m_c(r, j) = pair_factor(r, j);
        m_c(j, r) = m_c(r, j);
      }
    }
    if (++m_updates % 1000 == 0) recompute();  // bound the drift of the running value
  }
  const Eigen::MatrixXd& points() const { return m_x; }

 private:
  static double g1(double u) {
    const double z = std::abs(u - 0.5);
    return 1.0 + 0.5 * z - 0.5 * z * z;
  }
  static double c1(double u, double v) {
    return 1.0 + 0.5 * std::abs(u - 0.5) + 0.5 * std::abs(v - 0.5) - 0.5 * std::abs(u - v);
  }
  double row_factor(Eigen::Index i) const {
    double g = 1.0;
    for (Eigen::Index k = 0; k < m_x.cols(); ++k) g *= g1(m_x(i, k));
    return g;
  }
  double pair_factor(Eigen::Index i, Eigen::Index j) const {
    double c = 1.0;
    for (Eigen::Index k = 0; k < m_x.cols(); ++k) c *= c1(m_x(i, k), m_x(j, k));
    return c;
  }
  void recompute() {
    const double n = static_cast<double>(m_x.rows());
    m_value2 = std::pow(13.0 / 12.0, static_cast<double>(m_x.cols())) - 2.0 / n * m_g.sum() + m_c.sum() / (n * n);
  }
  double delta(Eigen::Index r1, Eigen::Index r2, Eigen::Index k) const {
    const double n = static_cast<double>(m_x.rows());
    const double a = m_x(r1, k), b = m_x(r2, k);
    // Row terms: factor of column k changes from g1(a) to g1(b) for r1 and the reverse for r2.
    const double dg = m_g(r1) * (g1(b) / g1(a) - 1.0) + m_g(r2) * (g1(a) / g1(b) - 1.0);
    // Pair terms: every c_{r1 j}, c_{r2 j} (j != r1, r2) counted twice; the diagonal c_rr; c_{r1 r2} unchanged.
    double dc = 0.0;
    for (Eigen::Index j = 0; j < m_x.rows(); ++j) {
      if (j == r1 || j == r2) continue;
      const double c = m_x(j, k);
      dc += 2.0 * (m_c(r1, j) * (c1(b, c) / c1(a, c) - 1.0) + m_c(r2, j) * (c1(a, c) / c1(b, c) - 1.0));
    }
    dc += m_c(r1, r1) * (c1(b, b) / c1(a, a) - 1.0) + m_c(r2, r2) * (c1(a, a) / c1(b, b) - 1.0);
    return -2.0 / n * dg + dc / (n * n);
  }

  Eigen::MatrixXd m_x;
  Eigen::MatrixXd m_c;
  Eigen::VectorXd m_g;
  double m_value2 = 0.0;
  long m_updates = 0;
};

/// Enhanced stochastic evolutionary algorithm (Jin, Chen, Sudjianto 2005, J. Stat. Plan. Inference 134, §3): inner
/// loops of M steps, each trying J random swaps in one column and keeping the best one under a threshold-accepting
/// rule; the threshold adapts between improvement and exploration phases. The budget is counted in outer iterations
/// (DesignOptions::iterations, stall_iterations, stall_tolerance), so that a seed pins the design down whatever the
/// machine's load; the wall-clock time_limit is only a safety stop, reported in result.stop.
template <class Criterion>
Eigen::MatrixXd optimise_lhs(Criterion criterion, const DesignOptions& options, DesignResult& result,
                             Clock::time_point start) {
  Random rng(options.seed ^ 0x9E3779B97F4A7C15ULL);
  const Eigen::Index n = criterion.points().rows();
  const Eigen::Index d = criterion.points().cols();
  const double pairs = 0.5 * static_cast<double>(n) * static_cast<double>(n - 1);
  const int j_tries = static_cast<int>(std::clamp(pairs / 5.0, 1.0, 50.0));
  const int m_inner = static_cast<int>(std::clamp(2.0 * pairs * static_cast<double>(d) / j_tries, 1.0, 100.0));

  Eigen::MatrixXd best = criterion.points();
  double best_value = criterion.value();
  double threshold = 0.005 * best_value;
  // best_value at the end of each outer iteration, for the no-improvement stop.
  std::vector<double> history{best_value};
  result.iterations = 0;
  result.stop = DesignStop::iterations;
  for (int outer = 0; outer < options.iterations; ++outer) {
    if (seconds_since(start) > options.time_limit) {
      result.stop = DesignStop::time_limit;
      break;
    }
    const double old_best = best_value;
    int accepted = 0, improved = 0;
    for (int inner = 0; inner < m_inner; ++inner) {
      const Eigen::Index k = static_cast<Eigen::Index>(rng.below(static_cast<std::uint64_t>(d)));
      Eigen::Index best_r1 = 0, best_r2 = 1;
      double best_trial = std::numeric_limits<double>::infinity();
      for (int t = 0; t < j_tries; ++t) {
        const Eigen::Index r1 = static_cast<Eigen::Index>(rng.below(static_cast<std::uint64_t>(n)));
        Eigen::Index r2 = static_cast<Eigen::Index>(rng.below(static_cast<std::uint64_t>(n - 1)));
        if (r2 >= r1) ++r2;
        const double v = criterion.trial(r1, r2, k);
        if (v < best_trial) {
          best_trial = v;
          best_r1 = r1;
          best_r2 = r2;
        }
      }
      if (best_trial - criterion.value() <= threshold * rng.uniform()) {
        criterion.apply(best_r1, best_r2, k);
        ++accepted;
        if (criterion.value() < best_value) {
          best_value = criterion.value();
          best = criterion.points();
          ++improved;
        }
      }
    }
    ++result.iterations;
    const double acceptance = static_cast<double>(accepted) / m_inner;
    if (best_value < old_best - 1e-12 * std::abs(old_best)) {  // improvement phase
      if (acceptance > 0.1 && improved < accepted) {
        threshold *= 0.8;
      } else if (acceptance <= 0.1) {
        threshold /= 0.8;
      }
    } else {  // exploration phase
      if (acceptance < 0.1) {
        threshold /= 0.7;
      } else if (acceptance > 0.8) {
        threshold *= 0.9;
      }
    }
    history.push_back(best_value);
    const std::size_t window = static_cast<std::size_t>(options.stall_iterations);
    if (history.size() > window &&
        best_value >= (1.0 - options.stall_tolerance) * history[history.size() - 1 - window]) {
      result.stop = DesignStop::no_improvement;
      break;
    }
  }
  return best;
}

}  // namespace

namespace {

const EnumNames<DesignKind>& design_kind_table() {
  static const EnumNames<DesignKind> names{"design",
                                           {{DesignKind::lhs, "lhs"},
                                            {DesignKind::lhs_centred, "lhs-centred"},
                                            {DesignKind::lhs_maximin, "lhs-maximin"},
                                            {DesignKind::lhs_cl2, "lhs-cl2"},
                                            {DesignKind::sobol, "sobol"}},
                                           {{"lhs-centered", DesignKind::lhs_centred}}};
  return names;
}

const EnumNames<DesignKind>& lhs_criterion_table() {
  static const EnumNames<DesignKind> names{"LHS criterion",
                                           {{DesignKind::lhs_maximin, "maximin"}, {DesignKind::lhs_cl2, "cl2"}}};
  return names;
}

}  // namespace

DesignKind design_kind_from_string(const std::string& name) { return design_kind_table().from_string(name); }
std::string to_string(DesignKind kind) { return design_kind_table().to_string(kind); }
std::vector<std::string> design_kind_names() { return design_kind_table().names(); }

DesignKind lhs_criterion_from_string(const std::string& name) { return lhs_criterion_table().from_string(name); }
void DesignOptions::validate() const {
  const int min_samples = kind == DesignKind::sobol ? 1 : 2;
  if (samples < min_samples)
    throw InputError(fmt::format("design samples = {}: must be at least {}", samples, min_samples));
  if (dimension < 1) throw InputError(fmt::format("design dimension = {}: must be at least 1", dimension));
  if (kind == DesignKind::sobol && dimension > k_max_sobol_dimension)
    throw InputError(fmt::format("design dimension = {}: the Sobol' sequence supports at most {} dimensions", dimension,
                                 k_max_sobol_dimension));
  if (!(phi_p_power >= 1.0) || !std::isfinite(phi_p_power))
    throw InputError(fmt::format("design phi_p_power = {}: must be a finite number >= 1", phi_p_power));
  const bool optimised = kind == DesignKind::lhs_maximin || kind == DesignKind::lhs_cl2;
  if (optimised && samples > k_max_optimised_lhs_samples)
    throw InputError(
        fmt::format("design samples = {}: an optimised LHS keeps n x n tables of pairs; at most {} samples", samples,
                    k_max_optimised_lhs_samples));
  if (iterations < 1) throw InputError(fmt::format("design iterations = {}: must be at least 1", iterations));
  if (stall_iterations < 1)
    throw InputError(fmt::format("design stall_iterations = {}: must be at least 1", stall_iterations));
  if (!(stall_tolerance >= 0.0 && stall_tolerance < 1.0))
    throw InputError(fmt::format("design stall_tolerance = {}: must be in [0, 1)", stall_tolerance));
  if (!(time_limit > 0.0)) throw InputError(fmt::format("design time_limit = {}: must be > 0", time_limit));
}

std::string to_string(DesignStop stop) {
  switch (stop) {
    case DesignStop::not_optimised:
      return "not optimised";
    case DesignStop::iterations:
      return "iterations";
    case DesignStop::no_improvement:
      return "no improvement";
    case DesignStop::time_limit:
      return "time limit";
  }
  return "unknown";
}

Eigen::MatrixXd latin_hypercube(int samples, int dimension, std::uint64_t seed, bool centred) {
  assert(samples >= 1 && dimension >= 1);
  Random rng(seed);
  Eigen::MatrixXd x(samples, dimension);
  std::vector<int> perm(static_cast<std::size_t>(samples));
  for (int k = 0; k < dimension; ++k) {
    std::iota(perm.begin(), perm.end(), 0);
    rng.shuffle(perm);
    for (int i = 0; i < samples; ++i) {
      const double offset = centred ? 0.5 : rng.uniform();
      x(i, k) = (perm[static_cast<std::size_t>(i)] + offset) / samples;
    }
  }
  return x;
}

namespace {

/// Primitive polynomial and initial direction numbers of one Sobol' dimension: degree s, the polynomial's inner
/// coefficients a (bits, most significant first) and m_1..m_s.
struct SobolPolynomial {
  int s;
  std::uint32_t a;
  std::array<std::uint32_t, 8> m;
};

/// Dimensions 2..40 of Joe & Kuo's table new-joe-kuo-6.21201 (S. Joe and F. Y. Kuo, "Constructing Sobol' sequences
/// with better two-dimensional projections", SIAM J. Sci. Comput. 30, 2635-2654, 2008), the direction numbers scipy
/// uses. Their 2-D projections have smaller t-values than those of Bratley & Fox (1988, GSL's), which matters for the
/// pairs of coordinates a Saltelli design combines.
constexpr std::array<SobolPolynomial, k_max_sobol_dimension - 1> k_joe_kuo{{
    {1, 0, {1}},
    {2, 1, {1, 3}},
    {3, 1, {1, 3, 1}},
    {3, 2, {1, 1, 1}},
    {4, 1, {1, 1, 3, 3}},
    {4, 4, {1, 3, 5, 13}},
    {5, 2, {1, 1, 5, 5, 17}},
    {5, 4, {1, 1, 5, 5, 5}},
    {5, 7, {1, 1, 7, 11, 19}},
    {5, 11, {1, 1, 5, 1, 1}},
    {5, 13, {1, 1, 1, 3, 11}},
    {5, 14, {1, 3, 5, 5, 31}},
    {6, 1, {1, 3, 3, 9, 7, 49}},
    {6, 13, {1, 1, 1, 15, 21, 21}},
    {6, 16, {1, 3, 1, 13, 27, 49}},
    {6, 19, {1, 1, 1, 15, 7, 5}},
    {6, 22, {1, 3, 1, 15, 13, 25}},
    {6, 25, {1, 1, 5, 5, 19, 61}},
    {7, 1, {1, 3, 7, 11, 23, 15, 103}},
    {7, 4, {1, 3, 7, 13, 13, 15, 69}},
    {7, 7, {1, 1, 3, 13, 7, 35, 63}},
    {7, 8, {1, 3, 5, 9, 1, 25, 53}},
    {7, 14, {1, 3, 1, 13, 9, 35, 107}},
    {7, 19, {1, 3, 1, 5, 27, 61, 31}},
    {7, 21, {1, 1, 5, 11, 19, 41, 61}},
    {7, 28, {1, 3, 5, 3, 3, 13, 69}},
    {7, 31, {1, 1, 7, 13, 1, 19, 1}},
    {7, 32, {1, 3, 7, 5, 13, 19, 59}},
    {7, 37, {1, 1, 3, 9, 25, 29, 41}},
    {7, 41, {1, 3, 5, 13, 23, 1, 55}},
    {7, 42, {1, 3, 7, 3, 13, 59, 17}},
    {7, 50, {1, 3, 1, 3, 5, 53, 69}},
    {7, 55, {1, 1, 5, 5, 23, 33, 13}},
    {7, 56, {1, 1, 7, 7, 1, 61, 123}},
    {7, 59, {1, 1, 7, 9, 13, 61, 49}},
    {7, 62, {1, 3, 3, 5, 3, 55, 33}},
    {8, 14, {1, 3, 1, 15, 31, 13, 49, 245}},
    {8, 21, {1, 3, 5, 15, 31, 59, 63, 97}},
    {8, 22, {1, 3, 1, 11, 11, 11, 77, 249}},
}};

constexpr int k_sobol_bits = 30;  // digits per coordinate; 2^30 points at most

/// Direction numbers v_1..v_30 of one dimension (0-based), as integers scaled by 2^30 (Bratley & Fox 1988, the
/// recurrence v_k = a_1 v_{k-1} ^ ... ^ a_{s-1} v_{k-s+1} ^ v_{k-s} ^ (v_{k-s} >> s); Joe & Kuo 2003).
std::array<std::uint32_t, k_sobol_bits> direction_numbers(int dimension) {
  std::array<std::uint32_t, k_sobol_bits> v{};
  if (dimension == 0) {
    for (int k = 0; k < k_sobol_bits; ++k) v[static_cast<std::size_t>(k)] = 1u << (k_sobol_bits - 1 - k);
    return v;
  }
  const SobolPolynomial& p = k_joe_kuo[static_cast<std::size_t>(dimension - 1)];
  for (int k = 0; k < k_sobol_bits; ++k) {
    const auto uk = static_cast<std::size_t>(k);
    if (k < p.s) {
      v[uk] = p.m[uk] << (k_sobol_bits - 1 - k);
      continue;
    }
    const std::uint32_t back = v[static_cast<std::size_t>(k - p.s)];
    std::uint32_t x = back ^ (back >> p.s);
    for (int j = 1; j < p.s; ++j)
      if ((p.a >> (p.s - 1 - j)) & 1u) x ^= v[static_cast<std::size_t>(k - j)];
    v[uk] = x;
  }
  return v;
}

/// The first n points of the unscrambled sequence as 30-bit integers, in Gray-code order (Antonov & Saleev 1979):
/// point i differs from point i-1 by the direction number of the lowest zero bit of i-1.
std::vector<std::uint32_t> sobol_integers(int samples, int dimension) {
  std::vector<std::uint32_t> x(static_cast<std::size_t>(samples) * static_cast<std::size_t>(dimension), 0u);
  for (int k = 0; k < dimension; ++k) {
    const std::array<std::uint32_t, k_sobol_bits> v = direction_numbers(k);
    std::uint32_t value = 0;
    for (int i = 1; i < samples; ++i) {
      const int c = std::countr_one(static_cast<unsigned>(i - 1));
      value ^= v[static_cast<std::size_t>(c)];
      x[static_cast<std::size_t>(i) * static_cast<std::size_t>(dimension) + static_cast<std::size_t>(k)] = value;
    }
  }
  return x;
}

void check_sobol_size(int samples, int dimension) {
  if (dimension < 1 || dimension > k_max_sobol_dimension)
    throw InputError(fmt::format("Sobol' sequence: dimension {} is outside 1..{}", dimension, k_max_sobol_dimension));
  if (samples < 1) throw InputError(fmt::format("Sobol' sequence: {} samples requested, need at least 1", samples));
  if (samples > (1 << k_sobol_bits))
    throw InputError(fmt::format("Sobol' sequence: {} samples requested, at most 2^{}", samples, k_sobol_bits));
}

}  // namespace

Eigen::MatrixXd sobol_sequence(int samples, int dimension) {
  check_sobol_size(samples, dimension);
  constexpr double scale = 1073741824.0;  // 2^30
  const std::vector<std::uint32_t> a = sobol_integers(samples, dimension);
  Eigen::MatrixXd x(samples, dimension);
  for (int i = 0; i < samples; ++i)
    for (int k = 0; k < dimension; ++k)
      x(i, k) =
          a[static_cast<std::size_t>(i) * static_cast<std::size_t>(dimension) + static_cast<std::size_t>(k)] / scale;
  return x;
}

Eigen::MatrixXd scrambled_sobol(int samples, int dimension, std::uint64_t seed) {
  check_sobol_size(samples, dimension);
  constexpr int bits = k_sobol_bits;
  constexpr double scale = 1073741824.0;  // 2^30

  // Matoušek's random linear scrambling: digit vector a (most significant first) -> L a + e (mod 2), L lower
  // triangular with a unit diagonal. Row r of L as a mask over the integer's bits (bit 29 = first digit).
  Random rng(seed);
  std::vector<std::uint32_t> masks(static_cast<std::size_t>(dimension * bits));
  std::vector<std::uint32_t> shifts(static_cast<std::size_t>(dimension));
  for (int k = 0; k < dimension; ++k) {
    for (int r = 0; r < bits; ++r) {
      const std::uint32_t diagonal = 1u << (bits - 1 - r);
      const std::uint32_t above =
          r == 0 ? 0u : static_cast<std::uint32_t>(rng.bits()) & ~((diagonal << 1) - 1u) & ((1u << bits) - 1u);
      masks[static_cast<std::size_t>(k * bits + r)] = diagonal | above;
    }
    shifts[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(rng.bits()) & ((1u << bits) - 1u);
  }

  // L a is linear over GF(2): the XOR of L's columns at the set bits of a. Tabulated per byte of a (4 bytes cover the
  // 30 bits), it is four lookups per value instead of 30 parities, with the same result.
  constexpr int bytes = (bits + 7) / 8;
  std::vector<std::uint32_t> table(static_cast<std::size_t>(dimension * bytes * 256), 0u);
  for (int k = 0; k < dimension; ++k)
    for (int j = 0; j < bits; ++j) {  // column j: the output digits whose row of L has bit j of the input
      std::uint32_t column = 0;
      for (int r = 0; r < bits; ++r)
        if ((masks[static_cast<std::size_t>(k * bits + r)] >> j) & 1u) column |= 1u << (bits - 1 - r);
      const int byte = j / 8;
      std::uint32_t* const t = &table[static_cast<std::size_t>((k * bytes + byte) * 256)];
      for (unsigned b = 0; b < 256; ++b)
        if ((b >> (j % 8)) & 1u) t[b] ^= column;
    }

  // The sequence starts at its first point, the origin, which completes the (t,m,d)-nets.
  const std::vector<std::uint32_t> points = sobol_integers(samples, dimension);
  Eigen::MatrixXd x(samples, dimension);
  for (int i = 0; i < samples; ++i) {
    for (int k = 0; k < dimension; ++k) {
      const std::uint32_t a =
          points[static_cast<std::size_t>(i) * static_cast<std::size_t>(dimension) + static_cast<std::size_t>(k)];
      const std::uint32_t* const t = &table[static_cast<std::size_t>(k * bytes * 256)];
      std::uint32_t y = 0;
      for (int byte = 0; byte < bytes; ++byte) y ^= t[byte * 256 + static_cast<int>((a >> (8 * byte)) & 0xffu)];
      y ^= shifts[static_cast<std::size_t>(k)];
      // The digits below 2^-30 are uniform (the shift continued), keeping points off the cell corners.
      x(i, k) = (static_cast<double>(y) + rng.uniform()) / scale;
    }
  }
  return x;
}

namespace {

/// k-d tree (Bentley 1975; the nearest-neighbour search of Friedman, Bentley & Finkel 1977) over the rows of a
/// design, used for the smallest distance between two rows: every row is queried against the tree with the best
/// squared distance found so far as the pruning radius, so a subtree is entered only when its splitting plane is
/// closer than that. O(n) memory.
class ClosestPair {
 public:
  explicit ClosestPair(const Eigen::MatrixXd& points)
      : m_d(points.cols()), m_rows(points.transpose()), m_index(static_cast<std::size_t>(points.rows())) {
    std::iota(m_index.begin(), m_index.end(), Eigen::Index{0});
    m_nodes.reserve(static_cast<std::size_t>(2 * points.rows() / k_leaf + 2));
    build(0, points.rows());
  }
  /// Smallest squared distance between two different rows.
  double min_squared() const {
    double best = std::numeric_limits<double>::infinity();
    // In the tree's order: neighbours follow each other, so the radius shrinks early and the rows stay in cache.
    for (const Eigen::Index row : m_index) search(0, row, best);
    return best;
  }

 private:
  static constexpr Eigen::Index k_leaf = 8;
  struct Node {
    Eigen::Index begin, end;  ///< range of m_index
    Eigen::Index dim = -1;    ///< split coordinate; -1 for a leaf
    double split = 0.0;
    int left = -1, right = -1;
  };
  double coord(Eigen::Index position, Eigen::Index k) const {
    return m_rows(k, m_index[static_cast<std::size_t>(position)]);
  }
  int build(Eigen::Index begin, Eigen::Index end) {
    const int id = static_cast<int>(m_nodes.size());
    m_nodes.push_back({begin, end});
    if (end - begin <= k_leaf) return id;
    Eigen::Index dim = 0;  // the coordinate of largest spread
    double spread = -1.0;
    for (Eigen::Index k = 0; k < m_d; ++k) {
      double lo = coord(begin, k), hi = lo;
      for (Eigen::Index i = begin + 1; i < end; ++i) {
        lo = std::min(lo, coord(i, k));
        hi = std::max(hi, coord(i, k));
      }
      if (hi - lo > spread) {
        spread = hi - lo;
        dim = k;
      }
    }
    const Eigen::Index mid = begin + (end - begin) / 2;
    const auto first = m_index.begin();
    std::nth_element(first + begin, first + mid, first + end,
                     [this, dim](Eigen::Index a, Eigen::Index b) { return m_rows(dim, a) < m_rows(dim, b); });
    const double split = coord(mid, dim);
    const int left = build(begin, mid);
    const int right = build(mid, end);
    Node& node = m_nodes[static_cast<std::size_t>(id)];
    node.dim = dim;
    node.split = split;
    node.left = left;
    node.right = right;
    return id;
  }
  void search(int id, Eigen::Index row, double& best) const {
    const Node& node = m_nodes[static_cast<std::size_t>(id)];
    const double* p = &m_rows(0, row);
    if (node.dim < 0) {
      for (Eigen::Index i = node.begin; i < node.end; ++i) {
        const Eigen::Index other = m_index[static_cast<std::size_t>(i)];
        if (other <= row) continue;  // each pair once, never a row with itself
        const double* q = &m_rows(0, other);
        double d2 = 0.0;
        for (Eigen::Index k = 0; k < m_d && d2 < best; ++k) d2 += (p[k] - q[k]) * (p[k] - q[k]);
        best = std::min(best, d2);
      }
      return;
    }
    // Left holds coordinates <= split, right >= split (nth_element), so a point on the plane may be on either side.
    const double gap = p[node.dim] - node.split;
    const int near = gap < 0.0 ? node.left : node.right;
    const int far = gap < 0.0 ? node.right : node.left;
    search(near, row, best);
    if (gap * gap <= best) search(far, row, best);
  }

  Eigen::Index m_d;
  Eigen::MatrixXd m_rows;  ///< a point per column
  std::vector<Eigen::Index> m_index;
  std::vector<Node> m_nodes;
};

}  // namespace

double min_distance(const Eigen::MatrixXd& points) {
  if (points.rows() < 2 || points.cols() < 1) return std::numeric_limits<double>::infinity();
  return std::sqrt(ClosestPair(points).min_squared());
}

double phi_p(const Eigen::MatrixXd& points, double p) {
  // Factor out the smallest distance so that d^-p stays in range for large p.
  const double dmin = min_distance(points);
  if (dmin == 0.0) return std::numeric_limits<double>::infinity();
  const Eigen::Index n = points.rows();
  const Eigen::Index d = points.cols();
  const Eigen::MatrixXd rows = points.transpose();  // a point per column, contiguous
  const double scale = 1.0 / (dmin * dmin);
  const double half = 0.5 * p;
  const int whole = std::floor(half) == half && half <= 400 ? static_cast<int>(half) : 0;
  double sum = 0.0;
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j) {
      double d2 = 0.0;
      for (Eigen::Index k = 0; k < d; ++k) d2 += (rows(k, i) - rows(k, j)) * (rows(k, i) - rows(k, j));
      const double ratio = 1.0 / (d2 * scale);  // (dmin / d)², at most 1
      if (whole == 0) {
        sum += std::pow(ratio, half);
        continue;
      }
      double base = ratio, term = 1.0;  // ratio^(p/2) by repeated squaring
      for (int e = whole; e > 0; e >>= 1, base *= base)
        if (e & 1) term *= base;
      sum += term;
    }
  return std::pow(sum, 1.0 / p) / dmin;
}

double centred_l2_discrepancy(const Eigen::MatrixXd& points) {
  // Hickernell 1998, eq. 5.1c, summed pair by pair (the diagonal once, each off-diagonal pair twice).
  const Eigen::Index n = points.rows();
  const Eigen::Index d = points.cols();
  const auto g1 = [](double u) {
    const double z = std::abs(u - 0.5);
    return 1.0 + 0.5 * z - 0.5 * z * z;
  };
  const auto c1 = [](double u, double v) {
    return 1.0 + 0.5 * std::abs(u - 0.5) + 0.5 * std::abs(v - 0.5) - 0.5 * std::abs(u - v);
  };
  double rows = 0.0, pairs = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    double g = 1.0;
    for (Eigen::Index k = 0; k < d; ++k) g *= g1(points(i, k));
    rows += g;
    double diagonal = 1.0;
    for (Eigen::Index k = 0; k < d; ++k) diagonal *= c1(points(i, k), points(i, k));
    pairs += diagonal;
    for (Eigen::Index j = i + 1; j < n; ++j) {
      double c = 1.0;
      for (Eigen::Index k = 0; k < d; ++k) c *= c1(points(i, k), points(j, k));
      pairs += 2.0 * c;
    }
  }
  const double nn = static_cast<double>(n);
  const double value2 = std::pow(13.0 / 12.0, static_cast<double>(d)) - 2.0 / nn * rows + pairs / (nn * nn);
  return std::sqrt(std::max(value2, 0.0));
}

DesignMetrics design_metrics(const Eigen::MatrixXd& points, double phi_p_power) {
  DesignMetrics m;
  m.min_distance = min_distance(points);
  m.phi_p_power = phi_p_power;
  if (points.rows() <= k_max_pair_metric_samples) {
    m.phi_p = phi_p(points, phi_p_power);
    m.centred_l2 = centred_l2_discrepancy(points);
  }
  return m;
}

DesignResult make_design(const DesignOptions& options, bool with_metrics) {
  options.validate();
  const Clock::time_point start = Clock::now();
  DesignResult result;
  result.kind = options.kind;
  result.seed = options.seed;
  switch (options.kind) {
    case DesignKind::lhs:
      result.points = latin_hypercube(options.samples, options.dimension, options.seed, false);
      break;
    case DesignKind::lhs_centred:
      result.points = latin_hypercube(options.samples, options.dimension, options.seed, true);
      break;
    case DesignKind::lhs_maximin:
      result.points = optimise_lhs(
          PhiPCriterion(latin_hypercube(options.samples, options.dimension, options.seed, false), options.phi_p_power),
          options, result, start);
      break;
    case DesignKind::lhs_cl2:
      result.points =
          optimise_lhs(Cl2Criterion(latin_hypercube(options.samples, options.dimension, options.seed, false)), options,
                       result, start);
      break;
    case DesignKind::sobol:
      result.points = scrambled_sobol(options.samples, options.dimension, options.seed);
      break;
  }
  if (with_metrics) result.metrics = design_metrics(result.points, options.phi_p_power);
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace demsa::sobol
