#pragma once
// Seeded random numbers that give the same stream on every platform (std::uniform_*_distribution does not): a
// 64-bit Mersenne Twister with explicit conversions.
#include <cassert>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace demsa::sobol {

class Random {
 public:
  explicit Random(std::uint64_t seed) : m_engine(seed) {}
  /// Uniform on [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(m_engine() >> 11) * 0x1.0p-53; }
  /// Uniform integer in [0, n), unbiased (rejection of the incomplete last block).
  std::uint64_t below(std::uint64_t n) {
    assert(n > 0);
    const std::uint64_t limit = UINT64_MAX - UINT64_MAX % n;
    std::uint64_t r = m_engine();
    while (r >= limit) r = m_engine();
    return r % n;
  }
  std::uint64_t bits() { return m_engine(); }
  /// Fisher-Yates shuffle.
  template <class T>
  void shuffle(std::vector<T>& v) {
    for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[below(i)]);
  }
  /// Standard normal (Box-Muller, one value per call).
  double normal() {
    double u = uniform();
    while (u <= 0.0) u = uniform();
    const double v = uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * 3.141592653589793238 * v);
  }

 private:
  std::mt19937_64 m_engine;
};

}  // namespace demsa::sobol
