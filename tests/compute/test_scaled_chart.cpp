// SPDX-License-Identifier: GPL-3.0-or-later
// The exact areas route computes in each receiver's chart scaled by K (exact/scaled_chart.hpp,
// internal), where a directional light's projections are integers. Checked here two ways:
//  - point by point, against the unscaled rationals of LeafProjector: every projection, plane
//    point and crossing is exactly K times them (seeded receivers, directions and points with
//    coordinates from 1e-9 to 1e6), and the chart box's bounds are too; the points are made both
//    in fixed width and by the GMP fallback (exact/fixed_width.hpp), and counted;
//  - whole scenes, against the unscaled route: a scene whose coordinates span too many bits for
//    integer charts (one far triangle with a tiny coordinate) must give the other faces the same
//    areas, bit for bit, as the scene without it, which uses them. Tiles, convex solids,
//    non-convex casters and faces crossing a receiver's plane are all in the scenes.
#include "core/dyadic.hpp"
#include "engine/engine_access.hpp"
#include "exact/exact_faces.hpp"
#include "exact/leaf_projector.hpp"
#include "exact/scaled_chart.hpp"

#include <shadow/shadow.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <stdexcept>
#include <vector>

namespace {

using shadow::exact::EQ;
using shadow::exact::QPoint2;

TEST(Dyadic, MantissaTimesPowerOfTwoIsTheDouble) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-1080, 1020);
  std::vector<double> values{1.0, -1.0, 0.75, 3.0, std::numeric_limits<double>::denorm_min(),
                             -std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::min(),
                             std::numeric_limits<double>::max(), 0x1.fffffffffffffp-1030};
  for (int k = 0; k < 5000; ++k) values.push_back(std::ldexp(unit(rng), exponent(rng)));
  for (double v : values) {
    if (v == 0.0) continue;
    const shadow::core::Dyadic d = shadow::core::dyadic(v);
    EXPECT_NE(d.mantissa % 2, 0) << v;
    EXPECT_EQ(std::ldexp(static_cast<double>(d.mantissa), d.exponent), v) << std::hexfloat << v;
  }
  EXPECT_EQ(shadow::core::dyadic(0.75).exponent, -2);
  EXPECT_EQ(shadow::core::dyadic(-12.0).mantissa, -3);
  EXPECT_EQ(shadow::core::dyadic(std::numeric_limits<double>::denorm_min()).exponent, -1074);
}

TEST(Dyadic, BitSpans) {
  shadow::core::BitSpan span;
  EXPECT_TRUE(span.empty());
  EXPECT_EQ(span.width(), 0);
  span.add(0.0);
  EXPECT_TRUE(span.empty());
  span.add(0.75);  // bits 2^-1 and 2^-2
  EXPECT_EQ(span.least, -2);
  EXPECT_EQ(span.top, -1);
  span.add(-8.0);
  EXPECT_EQ(span.top, 3);
  EXPECT_EQ(span.width(), 6);
  // Integer charts only while the scene spans at most kChartSpanBits bits.
  shadow::core::BitSpan wide;
  wide.add(std::ldexp(1.0, 99));
  wide.add(1.0);
  EXPECT_EQ(shadow::core::chart_least_bit(wide), 0);
  wide.add(std::ldexp(1.0, 100));
  EXPECT_EQ(wide.width(), shadow::core::kChartSpanBits + 1);
  EXPECT_FALSE(shadow::core::chart_least_bit(wide).has_value());
}

/// Sign of the receiver's plane (front positive) at y, as the engine decides it.
CGAL::Sign plane_side(const std::vector<glm::dvec3>& receiver, const shadow::core::FacePrep& prep, const glm::dvec3& y) {
  using EK = CGAL::Exact_predicates_inexact_constructions_kernel;
  auto p = [](const glm::dvec3& v) { return EK::Point_3(v.x, v.y, v.z); };
  CGAL::Sign s = CGAL::orientation(p(receiver[prep.corner[1]]), p(receiver[prep.corner[2]]), p(receiver[prep.corner[0]]), p(y));
  return prep.flipped ? CGAL::opposite(s) : s;
}

bool is_integer(const EQ& q) { return mpz_cmp_ui(mpq_denref(q.get_mpq_t()), 1) == 0; }

/// At most 16 units in the last place of its ends wide (the quotients of truncated leading
/// bits, divided by K's: about ten; a useless interval would hold anything).
bool narrow(const shadow::exact::IA& i) {
  const double m = std::max(std::abs(i.inf()), std::abs(i.sup()));
  return i.sup() - i.inf() <= 16 * (std::nextafter(m, std::numeric_limits<double>::infinity()) - m);
}

/// Whether the point's intervals (of the unscaled chart) hold the unscaled coordinates u, and
/// are narrow.
bool intervals_hold(const QPoint2& q, const QPoint2& u) {
  return EQ(q.i.x.inf()) <= u.x && u.x <= EQ(q.i.x.sup()) && EQ(q.i.y.inf()) <= u.y && u.y <= EQ(q.i.y.sup()) &&
         narrow(q.i.x) && narrow(q.i.y);
}

TEST(ScaledChart, IsTheUnscaledChartTimesK) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> magnitude(-30, 20);  // coordinates 1e-9 .. 1e6
  int crossings = 0, projections = 0, coarse_rounds = 0;
  std::size_t fixed_steps = 0, gmp_steps = 0;  // both of ScaledChart's ways (exact/fixed_width.hpp)
  int fixed_setups = 0, gmp_setups = 0;        // the same for the chart's N, O, D, L and K
  std::size_t clipped = 0;
  for (int round = 0; round < 300; ++round) {
    const double scale = std::ldexp(1.0, magnitude(rng));
    const glm::dvec3 origin{unit(rng) * scale * 8, unit(rng) * scale * 8, unit(rng) * scale * 8};
    // Every third round on a coarse grid (multiples of 2^10 to 2^40: the scene's least bit e is
    // then positive) under an integer light direction.
    const bool coarse = round % 3 == 0;
    const double step = std::ldexp(1.0, 10 + round % 31);
    auto point = [&] {
      const glm::dvec3 p = origin + glm::dvec3{unit(rng), unit(rng), unit(rng)} * scale;
      if (!coarse) return p;
      return glm::dvec3{std::round(unit(rng) * 64) * step, std::round(unit(rng) * 64) * step, std::round(unit(rng) * 64) * step};
    };
    std::vector<glm::dvec3> receiver{point(), point(), point()};  // a triangle: exactly planar
    const shadow::core::FacePrep prep = shadow::exact::prepare_face(receiver);
    if (prep.degenerate || !prep.exactly_planar) continue;
    shadow::Light light;
    light.to_light = {unit(rng), unit(rng), unit(rng)};
    if (round % 7 == 0) light.to_light.x = 0.0;  // an axis-parallel component
    if (coarse) light.to_light = {std::round(unit(rng) * 9), std::round(unit(rng) * 9), 1 + std::round(unit(rng) * 9)};
    if (light.to_light == glm::dvec3{0, 0, 0}) continue;
    std::vector<glm::dvec3> points;
    for (int k = 0; k < 12; ++k) points.push_back(point());
    shadow::core::BitSpan span;
    for (const auto& v : receiver)
      for (int c = 0; c < 3; ++c) span.add(v[c]);
    for (const auto& v : points)
      for (int c = 0; c < 3; ++c) span.add(v[c]);
    ASSERT_TRUE(shadow::core::chart_least_bit(span).has_value());
    if (coarse) {
      EXPECT_GE(*shadow::core::chart_least_bit(span), 10);
      ++coarse_rounds;
    }

    shadow::exact::ScaledChart chart(receiver, prep, light, shadow::core::chart_least_bit(span));
    if (!chart.integer()) {  // only a light along the receiver's plane has no chart
      EXPECT_TRUE(coarse);
      continue;
    }
    EXPECT_GT(sgn(chart.scale()), 0);
    shadow::exact::LeafProjector unscaled(receiver, prep, light);
    for (int c = 0; c < 2; ++c) {
      EXPECT_EQ(chart.lo(c), EQ(prep.chart_min[c]) * chart.scale());
      EXPECT_EQ(chart.hi(c), EQ(prep.chart_max[c]) * chart.scale());
    }
    QPoint2 q, r;
    for (const glm::dvec3& y : points) {
      chart.project(y, q);
      unscaled.project(y, r);
      EXPECT_TRUE(is_integer(q.x) && is_integer(q.y));
      EXPECT_EQ(q.x, r.x * chart.scale());
      EXPECT_EQ(q.y, r.y * chart.scale());
      EXPECT_TRUE(intervals_hold(q, r));
      ++projections;
    }
    for (const glm::dvec3& v : receiver) {  // on the plane
      chart.chart(v, q);
      unscaled.chart(v, r);
      EXPECT_TRUE(is_integer(q.x) && is_integer(q.y));
      EXPECT_EQ(q.x, r.x * chart.scale());
      EXPECT_EQ(q.y, r.y * chart.scale());
      // A point of the plane keeps its double as an exact interval (its ties need no GMP).
      EXPECT_TRUE(q.i.x.is_point() && q.i.y.is_point());
      EXPECT_TRUE(intervals_hold(q, r));
    }
    for (std::size_t a = 0; a < points.size(); ++a)
      for (std::size_t b = a + 1; b < points.size(); ++b) {
        const CGAL::Sign sa = plane_side(receiver, prep, points[a]), sb = plane_side(receiver, prep, points[b]);
        if (sa == CGAL::ZERO || sb == CGAL::ZERO || sa == sb) continue;
        chart.crossing(points[a], points[b], q);
        unscaled.crossing(points[a], points[b], r);
        EXPECT_EQ(q.x, r.x * chart.scale());
        EXPECT_EQ(q.y, r.y * chart.scale());
        EXPECT_TRUE(intervals_hold(q, r));
        ++crossings;
      }
    // Clipped to the chart box in the scaled chart: K times the unscaled clip, the cut
    // coordinates exactly the bounds, as points.
    {
      std::vector<QPoint2> scaled_poly, unscaled_poly, scratch;
      std::vector<int> side;
      EQ bound;
      for (std::size_t a = 0; a < 6; ++a) {
        chart.project(points[a], scaled_poly.emplace_back());
        unscaled.project(points[a], unscaled_poly.emplace_back());
      }
      shadow::exact::QScratch qs;
      std::vector<std::size_t> order, hull_chain;
      std::vector<QPoint2> hull;
      shadow::exact::convex_hull(scaled_poly, hull, order, hull_chain, qs);
      scaled_poly = hull;
      shadow::exact::convex_hull(unscaled_poly, hull, order, hull_chain, qs);
      unscaled_poly = hull;
      ASSERT_EQ(scaled_poly.size(), unscaled_poly.size());
      for (int c = 0; c < 2; ++c) {
        shadow::exact::clip_convex_2d(scaled_poly, c, chart.lo(c), chart.ilo(c), true, scratch, side, chart.scale_interval());
        shadow::exact::clip_convex_2d(scaled_poly, c, chart.hi(c), chart.ihi(c), false, scratch, side, chart.scale_interval());
        shadow::exact::clip_convex_2d(unscaled_poly, c, prep.chart_min[c], true, scratch, side, bound);
        shadow::exact::clip_convex_2d(unscaled_poly, c, prep.chart_max[c], false, scratch, side, bound);
      }
      ASSERT_EQ(scaled_poly.size(), unscaled_poly.size());
      for (std::size_t a = 0; a < scaled_poly.size(); ++a) {
        EXPECT_EQ(scaled_poly[a].x, unscaled_poly[a].x * chart.scale());
        EXPECT_EQ(scaled_poly[a].y, unscaled_poly[a].y * chart.scale());
        EXPECT_TRUE(intervals_hold(scaled_poly[a], unscaled_poly[a]));
        for (int c = 0; c < 2; ++c) {
          const EQ& u = c == 0 ? unscaled_poly[a].x : unscaled_poly[a].y;
          if (u == EQ(prep.chart_min[c]) || u == EQ(prep.chart_max[c]))
            EXPECT_TRUE((c == 0 ? scaled_poly[a].i.x : scaled_poly[a].i.y).is_point());
        }
      }
      clipped += scaled_poly.size();
    }
    fixed_steps += chart.fixed_steps();
    ++(chart.fixed_setup() ? fixed_setups : gmp_setups);
    gmp_steps += chart.gmp_steps();
    // Areas come back divided by K^2; points of the unscaled chart go in times K.
    EQ area = EQ(3, 7) * chart.scale() * chart.scale();
    chart.unscale_area(area);
    EXPECT_EQ(area, EQ(3, 7));
    QPoint2 p{EQ(5, 3), EQ(-2)};
    chart.scale_point(p);
    EXPECT_EQ(p.x, EQ(5, 3) * chart.scale());
  }
  EXPECT_GT(projections, 3000);
  EXPECT_GT(crossings, 1000);
  EXPECT_GT(clipped, 100u);
  EXPECT_GT(coarse_rounds, 50);
  // Coordinates from 1e-9 to 1e6 take the GMP fallback (integers past 2^126), coarse ones the
  // fixed-width steps: both were checked above against the unscaled rationals.
  EXPECT_GT(fixed_steps, 1000u);
  EXPECT_GT(gmp_steps, 1000u);
  EXPECT_GT(fixed_setups, 50);
  EXPECT_GT(gmp_setups, 50);
}

// ScaledChart::misses_box lets the engine skip a convex solid across the receiver's plane whose
// front part's shadow lies wholly beyond a side of the chart box. Checked against the unscaled
// rationals: wherever it says so, every vertex of the front part's projection (front vertices
// projected, plane crossings, points on the plane) lies strictly beyond one and the same side.
// Random solids (the hull of six grid points, every pair standing for an edge: the crossings of
// inner segments lie inside the front part) around triangles on coarse grids.
TEST(ScaledChart, MissesTheBoxOnlyWhereTheFrontPartLiesBeyondASide) {
  std::mt19937_64 rng(31);
  std::uniform_int_distribution<int> coordinate(-64, 64);
  std::uniform_int_distribution<int> direction(-9, 9);
  int misses = 0, misses_across = 0, across = 0, kept_beyond = 0;
  for (int round = 0; round < 4000; ++round) {
    const double step = std::ldexp(1.0, round % 20 - 4);
    auto point = [&](int reach) {
      return glm::dvec3{coordinate(rng) * reach * step, coordinate(rng) * reach * step, coordinate(rng) * reach * step};
    };
    const std::vector<glm::dvec3> receiver{point(1), point(1), point(1)};
    const shadow::core::FacePrep prep = shadow::exact::prepare_face(receiver);
    if (prep.degenerate || !prep.exactly_planar) continue;
    shadow::Light light;
    light.to_light = {direction(rng), direction(rng), 1 + std::abs(direction(rng))};
    shadow::core::BitSpan span;
    std::vector<glm::dvec3> solid;
    for (int k = 0; k < 6; ++k) solid.push_back(point(2));
    for (const std::vector<glm::dvec3>* set : {&receiver, static_cast<const std::vector<glm::dvec3>*>(&solid)})
      for (const auto& v : *set)
        for (int c = 0; c < 3; ++c) span.add(v[c]);
    shadow::exact::ScaledChart chart(receiver, prep, light, shadow::core::chart_least_bit(span));
    if (!chart.integer()) continue;
    shadow::exact::LeafProjector unscaled(receiver, prep, light);
    std::vector<CGAL::Sign> sign;
    bool front = false, behind = false;
    for (const glm::dvec3& y : solid) {
      sign.push_back(plane_side(receiver, prep, y));
      front |= sign.back() == CGAL::POSITIVE;
      behind |= sign.back() == CGAL::NEGATIVE;
    }
    if (!front) continue;
    across += behind ? 1 : 0;
    std::vector<std::array<int, 2>> edges;
    for (int a = 0; a < 6; ++a)
      for (int b = a + 1; b < 6; ++b) edges.push_back({a, b});
    // The front part's points, unscaled.
    std::vector<QPoint2> part;
    for (std::size_t a = 0; a < solid.size(); ++a) {
      if (sign[a] == CGAL::POSITIVE) unscaled.project(solid[a], part.emplace_back());
      if (sign[a] == CGAL::ZERO) unscaled.chart(solid[a], part.emplace_back());
    }
    for (const auto& [a, b] : edges)
      if ((sign[a] == CGAL::POSITIVE && sign[b] == CGAL::NEGATIVE) ||
          (sign[a] == CGAL::NEGATIVE && sign[b] == CGAL::POSITIVE))
        unscaled.crossing(solid[a], solid[b], part.emplace_back());
    auto all_beyond = [&](int c, bool low) {
      const EQ bound(low ? prep.chart_min[c] : prep.chart_max[c]);
      return std::all_of(part.begin(), part.end(), [&](const QPoint2& q) {
        const EQ& x = c == 0 ? q.x : q.y;
        return low ? x < bound : bound < x;
      });
    };
    const bool beyond = all_beyond(0, true) || all_beyond(0, false) || all_beyond(1, true) || all_beyond(1, false);
    if (chart.misses_box(solid, sign, edges)) {
      EXPECT_TRUE(beyond) << "round " << round;
      ++misses;
      misses_across += behind ? 1 : 0;  // the engine's only case: crossings bounded by their ends
    } else if (beyond && !behind) {
      ++kept_beyond;  // (a conservative test may keep some; wholly in front it decides exactly)
    }
  }
  EXPECT_GT(across, 1000);
  EXPECT_GT(misses, 40);
  EXPECT_GT(misses_across, 10);
  // In front of the plane the points are the projections themselves: nothing beyond is kept.
  EXPECT_EQ(kept_beyond, 0);
}

TEST(ScaledChart, WideScenesAndDirectionsKeepTheUnscaledRationals) {
  const std::vector<glm::dvec3> receiver{{0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}};
  const shadow::core::FacePrep prep = shadow::exact::prepare_face(receiver);
  shadow::Light light;
  light.to_light = {0.3, -0.2, 0.9};
  const glm::dvec3 y{1.25, 0.5, 2.0};
  QPoint2 q, r;
  shadow::exact::LeafProjector(receiver, prep, light).project(y, r);

  shadow::exact::ScaledChart unscaled(receiver, prep, light, std::nullopt);  // a scene too wide
  EXPECT_FALSE(unscaled.integer());
  EXPECT_EQ(unscaled.scale(), 1);
  unscaled.project(y, q);
  EXPECT_EQ(q.x, r.x);
  EXPECT_EQ(q.y, r.y);

  light.to_light = {1e-300, -0.2, 0.9};  // a direction spanning a thousand bits
  shadow::exact::ScaledChart wide(receiver, prep, light, -2);
  EXPECT_FALSE(wide.integer());
  shadow::exact::LeafProjector(receiver, prep, light).project(y, r);
  wide.project(y, q);
  EXPECT_EQ(q.x, r.x);

  light.to_light = {0.3, -0.2, 0.9};
  shadow::exact::ScaledChart integer(receiver, prep, light, -2);  // 1.25 = 5 2^-2
  EXPECT_TRUE(integer.integer());
  integer.project(y, q);
  EXPECT_TRUE(is_integer(q.x));

  // A least bit above a corner's (the scene changed after the engine was made): the fixed-width
  // setup leaves it to the GMP steps, which refuse it as they always did.
  const std::vector<glm::dvec3> off_bit{{0, 0, 0}, {4, 0, 0}, {4, 3.5, 0}, {0, 3.5, 0}};
  const shadow::core::FacePrep off_prep = shadow::exact::prepare_face(off_bit);
  EXPECT_THROW(shadow::exact::ScaledChart(off_bit, off_prep, light, 0), std::logic_error);
}

/// A city with tiles, non-convex casters (an L-shaped slab over the ground, combs), faces that
/// cross other receivers' planes (a leaning board) and several suns.
shadow::Scene test_city(std::uint64_t seed) {
  shadow::Scene scene = shadow::make_city(60, 40.0, seed);
  std::vector<std::vector<glm::dvec3>> extra;
  auto add = [&](std::vector<glm::dvec3> v) { extra.push_back(std::move(v)); };
  // An L-shaped slab 6 m up, facing up and down.
  std::vector<glm::dvec3> l_shape{{1, 1, 6}, {9, 1, 6}, {9, 3, 6}, {3.1, 3, 6}, {3.1, 8.7, 6}, {1, 8.7, 6}};
  add(l_shape);
  std::reverse(l_shape.begin(), l_shape.end());
  add(l_shape);
  // A comb of 20 teeth (non-convex, many convex pieces), 4.3 m up.
  std::vector<glm::dvec3> comb;
  for (int t = 0; t < 20; ++t) {
    comb.push_back({-20 + t * 1.1, -15, 4.3});
    comb.push_back({-20 + t * 1.1 + 0.55, -15, 4.3});
    comb.push_back({-20 + t * 1.1 + 0.55, -12.7, 4.3});
    comb.push_back({-20 + t * 1.1 + 1.1, -12.7, 4.3});
  }
  comb.push_back({2, -10.1, 4.3});
  comb.push_back({-20, -10.1, 4.3});
  add(comb);
  // A quad warped by 2^-20 m (not exactly planar: it casts by the lazy route, converted into
  // the scaled chart).
  add({{10.1, 20.3, 5.0}, {14.7, 20.3, 5.0}, {14.7, 24.9, 5.0}, {10.1, 24.9, 5.0 + std::ldexp(1.0, -20)}});
  // A board leaning through other faces' planes.
  add({{-5.3, 7.1, 0.0}, {-1.2, 7.1, 0.0}, {-1.7, 9.9, 7.3}, {-5.8, 9.9, 7.3}});
  shadow::add_mesh(scene, "extra", extra);
  return scene;
}

std::vector<shadow::Light> suns() {
  std::vector<shadow::Light> lights;
  for (const glm::dvec3& d : {glm::dvec3{0.31, -0.52, 0.79}, glm::dvec3{-0.9, 0.13, 0.0871557},
                              glm::dvec3{0.0, 0.0, 1.0}, glm::dvec3{0.1, 0.95, 0.3}}) {
    shadow::Light light;
    light.type = shadow::LightType::Directional;
    light.to_light = d;
    lights.push_back(light);
  }
  return lights;
}

TEST(ScaledChart, ScenesGiveTheSameBitsWithAndWithoutIntegerCharts) {
  for (std::uint64_t seed : {3u, 17u}) {
    shadow::Scene narrow = test_city(seed);
    narrow.lights = suns();
    shadow::Scene wide = narrow;
    // Far from everything: a triangle with a coordinate 2^-150, so that the scene's coordinates
    // span more than kChartSpanBits bits.
    shadow::add_mesh(wide, "far", {shadow::Polygon3{{5000, 5000, std::ldexp(1.0, -150)}, {5001, 5000, 0}, {5000, 5001, 0}}});

    shadow::ShadowOptions options;
    options.polygons = false;
    options.planes = false;
    options.tile_casters = 40;  // the ground in tiles
    const shadow::ShadowEngine narrow_engine(narrow, 2), wide_engine(wide, 2);
    ASSERT_TRUE(shadow::engine::prepared_scene(narrow_engine).chart_least_bit.has_value());
    ASSERT_FALSE(shadow::engine::prepared_scene(wide_engine).chart_least_bit.has_value());
    const shadow::ShadowResult a = narrow_engine.compute(options);
    const shadow::ShadowResult b = wide_engine.compute(options);
    EXPECT_GT(a.stats.tiles, 0u);
    std::size_t compared = 0, shadowed = 0;
    for (const shadow::FaceLighting& la : a.lighting) {
      const shadow::FaceLighting* lb = b.find(la.face_id, la.light_id);
      ASSERT_NE(lb, nullptr);
      EXPECT_EQ(la.lit_area, lb->lit_area) << "face " << la.face_id << " light " << la.light_id;
      EXPECT_EQ(la.shadow_area, lb->shadow_area) << "face " << la.face_id << " light " << la.light_id;
      EXPECT_EQ(la.lit_fraction, lb->lit_fraction) << "face " << la.face_id << " light " << la.light_id;
      ++compared;
      shadowed += la.faces_light && la.lit_area < la.area;
    }
    EXPECT_GT(shadowed, 100u);
    // And the fragments route (Epeck polygons, Boolean operations) measures the same areas.
    options.polygons = true;
    const shadow::ShadowResult c = narrow_engine.compute(options);
    for (const shadow::FaceLighting& la : a.lighting) {
      const shadow::FaceLighting* lc = c.find(la.face_id, la.light_id);
      ASSERT_NE(lc, nullptr);
      EXPECT_EQ(la.lit_area, lc->lit_area) << "face " << la.face_id << " light " << la.light_id;
    }
    EXPECT_EQ(compared, a.lighting.size());
  }
}

}  // namespace
