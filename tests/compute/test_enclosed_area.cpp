// SPDX-License-Identifier: GPL-3.0-or-later
// The exact engine's enclosed union area (ConvexUnionArea::twice_area_in_window_enclosed) and
// the doubles it pins (EnclosedMeasure) against the exact area and its one rounding
// (measure_lit_and_shadow): the enclosure always holds the exact value, and every double taken
// from it is the one the exact value gives; where it cannot pin one it says so.
#include "exact/convex_union_area.hpp"
#include "exact/exact_faces.hpp"
#include "exact/rational_points.hpp"

#include <shadow/shadow.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

namespace {

using shadow::exact::ConvexUnionArea;
using shadow::exact::QPoint2;
using EQ = ConvexUnionArea::EQ;

/// 2^-k as an exact rational.
EQ two_to_minus(int k) {
  EQ out(1);
  mpq_div_2exp(out.get_mpq_t(), out.get_mpq_t(), static_cast<mp_bitcnt_t>(k));
  return out;
}

class Polygons {
 public:
  explicit Polygons(unsigned seed) : rng_(seed) {}
  int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }

  /// A convex polygon (counter-clockwise): k points on a circle about (cx, cy), rounded to
  /// integers, times `scale`; every third polygon with one coordinate in thirds (not integer).
  std::vector<QPoint2> polygon(int cx, int cy, int r, const EQ& scale) {
    const int k = uniform(3, 7);
    std::vector<double> angles;
    for (int a = 0; a < k; ++a) angles.push_back(std::uniform_real_distribution<double>(0, 6.283185307179586)(rng_));
    std::sort(angles.begin(), angles.end());
    std::vector<QPoint2> out;
    const bool thirds = uniform(0, 2) == 0;
    for (double a : angles) {
      EQ x(static_cast<long>(std::lround(cx + r * std::cos(a))));
      EQ y(static_cast<long>(std::lround(cy + r * std::sin(a))));
      x *= scale;
      y *= scale;
      if (thirds) x /= 3;
      out.emplace_back(x, y);
    }
    return out;
  }

 private:
  std::mt19937 rng_;
};

/// Seeded scenes of convex casts in a rectangular window, small integers and integers of a
/// hundred bits (the engine's scaled charts): lo <= twice the exact area <= lo + slack 2^-k, lo
/// the exact area where there is no slack (a window the casts cover whole among them).
TEST(EnclosedUnionArea, HoldsTheExactArea) {
  Polygons g(20261201);
  const EQ huge = EQ(mpz_class(1) << 100) + 12345;  // (not a power of two: odd integers)
  std::size_t with_slack = 0, covered_whole = 0, rounds = 0, refused = 0;
  ConvexUnionArea u;  // one object throughout: nothing of a call may be left for the next
  const std::vector<QPoint2> spike{{EQ(0), EQ(0)}, {EQ(4), EQ(0)}, {EQ(2), EQ(0)}, {EQ(2), EQ(3)}};  // not convex
  for (int round = 0; round < 600; ++round) {
    const EQ& scale = round % 2 == 0 ? EQ(1) : huge;
    std::vector<QPoint2> all;
    std::vector<std::size_t> first{0};
    const int n = g.uniform(1, 8);
    const bool cover = round % 5 == 0;  // one large cast and others over a small window
    for (int p = 0; p < n; ++p) {
      const std::vector<QPoint2> poly =
          g.polygon(g.uniform(0, 400), g.uniform(0, 400), cover && p < 2 ? 2000 : g.uniform(20, 300), scale);
      all.insert(all.end(), poly.begin(), poly.end());
      first.push_back(all.size());
    }
    const int x0 = g.uniform(0, 300), y0 = g.uniform(0, 300), w = cover ? 10 : g.uniform(20, 300);
    std::vector<QPoint2> window;
    for (const auto& [x, y] : {std::pair{x0, y0}, {x0 + w, y0}, {x0 + w, y0 + w}, {x0, y0 + w}})
      window.emplace_back(EQ(x) * scale, EQ(y) * scale);
    EQ exact;
    if (!u.twice_area_in_window(all.data(), first, window.data(), window.size(), exact)) continue;  // rounded not convex
    ++rounds;
    ConvexUnionArea::Enclosure e;
    if (round % 7 == 0) {  // a refused enclosed call first (a spike among the casts)
      std::vector<QPoint2> with_spike = all;
      std::vector<std::size_t> spike_first = first;
      with_spike.insert(with_spike.end(), spike.begin(), spike.end());
      spike_first.push_back(with_spike.size());
      EXPECT_FALSE(u.twice_area_in_window_enclosed(with_spike.data(), spike_first, window.data(), window.size(), e));
      ++refused;
    }
    ASSERT_TRUE(u.twice_area_in_window_enclosed(all.data(), first, window.data(), window.size(), e)) << "round " << round;
    const EQ hi = e.lo + EQ(static_cast<unsigned long>(e.slack)) * two_to_minus(ConvexUnionArea::kEnclosureBits);
    EXPECT_LE(e.lo, exact) << "round " << round;
    EXPECT_LE(exact, hi) << "round " << round;
    if (e.slack == 0) EXPECT_EQ(e.lo, exact) << "round " << round;
    with_slack += e.slack > 0;
    covered_whole += exact == EQ(2 * w * w) * scale * scale;
    // The exact call after the enclosed one: nothing of the enclosure left behind.
    EQ again;
    ASSERT_TRUE(u.twice_area_in_window(all.data(), first, window.data(), window.size(), again));
    EXPECT_EQ(again, exact) << "round " << round;
    // Without a window (a tile's casts, already clipped): the same bounds on the plain union.
    shadow::exact::QPointList listed;
    for (const QPoint2& p : all) listed.push_back(p);
    EQ plain;
    ASSERT_TRUE(u.twice_area(listed, first, plain));
    ConvexUnionArea::Enclosure f;
    ASSERT_TRUE(u.twice_area_enclosed(listed, first, f));
    EXPECT_LE(f.lo, plain) << "round " << round;
    EXPECT_LE(plain, f.lo + EQ(static_cast<unsigned long>(f.slack)) * two_to_minus(ConvexUnionArea::kEnclosureBits))
        << "round " << round;
    if (f.slack == 0) EXPECT_EQ(f.lo, plain) << "round " << round;
  }
  EXPECT_GT(refused, 50u);
  EXPECT_GT(rounds, 400u);
  EXPECT_GT(with_slack, 150u);   // partly covered edges, divided out
  EXPECT_GT(covered_whole, 20u);  // windows covered whole: exact lo
}

/// The three doubles measure_lit_and_shadow rounds from an exact shadow, against the same from
/// an enclosure of it (its lower end up to `slack` units of 2^-128 below, and `slack` units
/// wide), in axis planes (no root) and turned ones, in scaled charts and plain ones.
TEST(EnclosedMeasure, PinsTheDoublesTheExactShadowRoundsTo) {
  std::mt19937_64 rng(7);
  const auto big = [&](int bits) {
    mpz_class z(1);
    for (int b = 0; b < bits; b += 60) z = (z << 60) + static_cast<unsigned long>(rng() >> 4);
    return z;
  };
  shadow::exact::EnclosedMeasure m;
  std::size_t pinned = 0;
  for (int round = 0; round < 2000; ++round) {
    const EQ chart_area(big(100) + 1, big(40) + 1);
    EQ shadow(chart_area * EQ(big(50), big(52)));  // some fraction of the chart (below 1 mostly)
    if (shadow >= chart_area) shadow = chart_area / 3;
    const EQ scale_squared = round % 3 == 0 ? EQ(1) : EQ(big(30) + 3, big(30) + 7);
    const EQ k = round % 2 == 0 ? EQ(big(55) + 1) : EQ(big(60) + 5, 1024);
    const EQ* scale = round % 4 < 2 ? &k : nullptr;
    EQ twice = 2 * shadow;
    if (scale) twice *= k * k;
    const unsigned long slack = 1 + rng() % 7;
    const EQ twice_lo = twice - EQ(static_cast<unsigned long>(rng() % (slack + 1))) * two_to_minus(128);
    shadow::FaceLighting exact, enclosed;
    EQ lit, scratch;
    shadow::exact::measure_lit_and_shadow(chart_area, scale_squared, shadow, lit, scratch, exact);
    if (!m.measure(chart_area, scale_squared, twice_lo, slack, 128, scale, enclosed)) continue;
    ++pinned;
    EXPECT_EQ(enclosed.lit_area, exact.lit_area) << "round " << round;
    EXPECT_EQ(enclosed.shadow_area, exact.shadow_area) << "round " << round;
    EXPECT_EQ(enclosed.lit_fraction, exact.lit_fraction) << "round " << round;
  }
  EXPECT_GT(pinned, 1990u);  // undecided only next to a rounding boundary
}

/// A tiled face's tiles' enclosures added (EnclosedMeasure::measure_between): an exact shadow
/// anywhere in [lo, lo + width] pins the same doubles as the exact one, or none.
TEST(EnclosedMeasure, BetweenPinsTheDoublesOfAnyShadowInside) {
  std::mt19937_64 rng(11);
  shadow::exact::EnclosedMeasure m;
  std::size_t pinned = 0;
  for (int round = 0; round < 1000; ++round) {
    const EQ chart_area(mpz_class(rng() >> 8) * (rng() >> 8) + 1, mpz_class(rng() >> 20) + 1);
    const EQ shadow = chart_area * EQ(static_cast<unsigned long>(rng() % 1000 + 1), 1003);
    const EQ scale_squared = round % 2 == 0 ? EQ(1) : EQ(static_cast<unsigned long>(rng() % 1000 + 2), 997);
    const EQ width = EQ(static_cast<unsigned long>(rng() % 50 + 1)) * two_to_minus(140);
    const EQ lo = shadow - width * EQ(static_cast<unsigned long>(rng() % 3), 2);  // lo <= shadow <= lo + width
    shadow::FaceLighting exact, between;
    EQ lit, scratch;
    shadow::exact::measure_lit_and_shadow(chart_area, scale_squared, shadow, lit, scratch, exact);
    if (!m.measure_between(chart_area, scale_squared, lo, width, between)) continue;
    ++pinned;
    EXPECT_EQ(between.lit_area, exact.lit_area) << "round " << round;
    EXPECT_EQ(between.shadow_area, exact.shadow_area) << "round " << round;
    EXPECT_EQ(between.lit_fraction, exact.lit_fraction) << "round " << round;
  }
  EXPECT_GT(pinned, 990u);
  shadow::FaceLighting out;
  EXPECT_FALSE(m.measure_between(EQ(1), EQ(1), EQ(1) - two_to_minus(150), two_to_minus(140), out));  // lit may be 0
  EXPECT_FALSE(m.measure_between(EQ(1), EQ(1), EQ(0), two_to_minus(140), out));   // a shadow that may be 0
  EXPECT_FALSE(m.measure_between(EQ(-1), EQ(1), EQ(1, 4), EQ(0), out));           // no positive chart
  EXPECT_TRUE(m.measure_between(EQ(1), EQ(1), EQ(1, 4), EQ(0), out));             // exact: width 0
  EXPECT_EQ(out.lit_area, 0.75);
  EXPECT_EQ(out.shadow_area, 0.25);
  EXPECT_EQ(out.lit_fraction, 0.75);
}

/// Where the enclosure cannot decide, it says so and writes nothing: a lit part that may be
/// zero (a chart covered whole), an enclosure wider than a double's spacing, and a lit area
/// exactly halfway between two doubles (1 - 2^-54) with the enclosure around it.
TEST(EnclosedMeasure, LeavesUndecidedCasesToTheExactShadow) {
  shadow::exact::EnclosedMeasure m;
  shadow::FaceLighting out;
  out.lit_area = -1;
  const EQ one(1);
  // Covered whole: twice the shadow is twice the chart, enclosed from just below.
  EXPECT_FALSE(m.measure(one, one, EQ(2) - two_to_minus(128), 2, 128, nullptr, out));
  // Wide: a shadow of about a third, enclosed to within 2^-20 only.
  EXPECT_FALSE(m.measure(one, one, EQ(2, 3), 1, 20, nullptr, out));
  // Halfway: lit = 1 - 2^-54 exactly inside the enclosure (the exact value rounds to even: 1).
  const EQ twice = 2 * two_to_minus(54);
  EXPECT_FALSE(m.measure(one, one, twice - two_to_minus(128), 2, 128, nullptr, out));
  EXPECT_EQ(out.lit_area, -1);
  // The same enclosure but narrow and one side of the halfway point: pinned.
  EXPECT_TRUE(m.measure(one, one, twice + two_to_minus(100), 1, 128, nullptr, out));
  EXPECT_EQ(out.lit_area, 1 - std::ldexp(1.0, -53));
}

}  // namespace
