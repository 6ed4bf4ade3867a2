// SPDX-License-Identifier: GPL-3.0-or-later
// Doubles as integers times powers of two. Every finite nonzero double is m 2^k with an odd
// integer m of at most 53 bits; the exact areas route scales each receiver's chart so that its
// projected points are integers (exact/scaled_chart.hpp), which needs the least k of all the
// scene's coordinates. Plain C++: no GMP here.
#pragma once

#include <climits>
#include <cstdint>
#include <cstring>
#include <optional>

namespace shadow::core {

/// v = mantissa 2^exponent exactly, with an odd mantissa (v finite and nonzero).
struct Dyadic {
  std::int64_t mantissa = 0;
  int exponent = 0;
};

/// The odd mantissa and exponent of a finite nonzero double (read from its bits).
inline Dyadic dyadic(double v) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  std::uint64_t m = bits & ((std::uint64_t{1} << 52) - 1);
  int k = -1074;  // subnormal: v = m 2^-1074
  if (biased != 0) {
    m |= std::uint64_t{1} << 52;
    k = biased - 1075;
  }
  const int zeros = __builtin_ctzll(m);  // m != 0: v is nonzero
  m >>= zeros;
  const auto signed_m = static_cast<std::int64_t>(m);
  return {(bits >> 63) != 0 ? -signed_m : signed_m, k + zeros};
}

/// The bits that a set of doubles spans: the exponent of the least set bit and of the highest
/// bit over its nonzero values (zeros have none).
struct BitSpan {
  int least = INT_MAX;
  int top = INT_MIN;

  void add(double v) {
    if (v == 0.0) return;
    const Dyadic d = dyadic(v);
    const auto magnitude = static_cast<std::uint64_t>(d.mantissa < 0 ? -d.mantissa : d.mantissa);
    const int highest = d.exponent + 63 - __builtin_clzll(magnitude);
    if (d.exponent < least) least = d.exponent;
    if (highest > top) top = highest;
  }
  void add(const BitSpan& other) {
    if (other.least < least) least = other.least;
    if (other.top > top) top = other.top;
  }
  [[nodiscard]] bool empty() const { return least > top; }
  /// Bits from the least to the highest, both included (0 when empty).
  [[nodiscard]] int width() const { return empty() ? 0 : top - least + 1; }
};

/// The widest span of the scene's coordinates (BitSpan::width) with the exact areas route's
/// integer charts (exact/scaled_chart.hpp): its integers stay below 2^430.
constexpr int kChartSpanBits = 100;

/// The scene's least coordinate bit when integer charts can be used (its coordinates span at
/// most kChartSpanBits), else nullopt (PreparedScene::chart_least_bit).
inline std::optional<int> chart_least_bit(const BitSpan& scene) {
  if (scene.empty() || scene.width() > kChartSpanBits) return std::nullopt;
  return scene.least;
}

}  // namespace shadow::core
