// SPDX-License-Identifier: GPL-3.0-or-later
// The exact engine's union area without a Boolean operation (exact/convex_union_area.hpp,
// internal header) against CGAL's aggregated union (PolygonSet2::join and the regions' areas,
// the route it replaces): the two exact rationals are equal (==, not doubles) on seeded random
// convex polygons full of degenerate contacts: shared edges going the same way and the other
// way, identical polygons, polygons inside others, touching at vertices, collinear overlapping
// edges, collinear vertices, triangles, slivers, points on coarse rational grids (many exact
// ties) and points made by lazy arithmetic (as clipping makes them). Also the rational-point
// helpers of the areas-only route (exact/rational_points.hpp) against their Epeck counterparts:
// hull, clip to a box, intervals, area signs. And a lit region's canonical boundary
// (exact/boundary_chain.hpp) from the union's uncovered pieces against the join's region.
#include "engine/engine_access.hpp"
#include "exact/boundary_chain.hpp"
#include "exact/convex_union_area.hpp"
#include "exact/exact_faces.hpp"
#include "exact/exact_receiver.hpp"
#include "exact/lazy_geometry.hpp"
#include "exact/rational_points.hpp"
#include "exact/regions.hpp"
#include "support/scene_builders.hpp"

#include <shadow/shadow.hpp>

#include <gtest/gtest.h>

#include <cmath>

#include <CGAL/convex_hull_2.h>

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace {

using shadow::exact::ConvexUnionArea;
using shadow::exact::FT;
using shadow::exact::Kernel;
using shadow::exact::Point2;
using shadow::exact::Polygon2;
using shadow::exact::PolygonSet2;
using shadow::exact::PolygonWithHoles2;
using EQ = ConvexUnionArea::EQ;

/// The reference: CGAL's union, the sum of its regions' exact areas.
EQ joined_area(const std::vector<Polygon2>& polygons) {
  PolygonSet2 set;
  set.join(polygons.begin(), polygons.end());
  std::vector<PolygonWithHoles2> regions;
  set.polygons_with_holes(std::back_inserter(regions));
  std::vector<FT> areas;
  for (const PolygonWithHoles2& r : regions) areas.push_back(shadow::exact::region_area(r));
  return CGAL::exact(shadow::exact::balanced_sum(areas));
}

EQ union_area(const std::vector<Polygon2>& polygons) {
  ConvexUnionArea u;
  EQ twice;
  EXPECT_TRUE(u.twice_area(polygons, twice));
  return twice / 2;
}

Polygon2 box(FT x0, FT y0, FT x1, FT y1) {
  const Point2 p[4] = {Point2(x0, y0), Point2(x1, y0), Point2(x1, y1), Point2(x0, y1)};
  return Polygon2(p, p + 4);
}

TEST(ExactUnionArea, AnalyticCases) {
  // Two unit squares overlapping by half, side by side (a shared edge going the other way), one
  // inside another, identical ones.
  EXPECT_EQ(union_area({box(0, 0, 1, 1), box(FT(1) / 2, 0, FT(3) / 2, 1)}), EQ(3) / 2);
  EXPECT_EQ(union_area({box(0, 0, 1, 1), box(1, 0, 2, 1)}), EQ(2));
  EXPECT_EQ(union_area({box(0, 0, 4, 4), box(1, 1, 2, 2)}), EQ(16));
  EXPECT_EQ(union_area({box(1, 1, 2, 2), box(0, 0, 4, 4)}), EQ(16));
  EXPECT_EQ(union_area({box(0, 0, 1, 1), box(0, 0, 1, 1), box(0, 0, 1, 1)}), EQ(1));
  // A shared edge going the same way: [0,2]x[0,1] and [0,1]x[0,1/3] share part of the bottom.
  EXPECT_EQ(union_area({box(0, 0, 2, 1), box(0, 0, 1, FT(1) / 3)}), EQ(2));
  EXPECT_EQ(union_area({box(0, 0, 1, FT(1) / 3), box(0, -1, 2, 0), box(0, 0, 2, 1)}), EQ(4));
  // Touching at a corner only.
  EXPECT_EQ(union_area({box(0, 0, 1, 1), box(1, 1, 3, 2)}), EQ(3));
  EXPECT_EQ(union_area({}), EQ(0));
}

TEST(ExactUnionArea, NonConvexIsRefused) {
  const Point2 p[6] = {Point2(0, 0), Point2(3, 0), Point2(3, 3), Point2(2, 3), Point2(2, 1), Point2(0, 1)};
  ConvexUnionArea u;
  EQ twice(7);
  EXPECT_FALSE(u.twice_area({box(0, 0, 1, 1), Polygon2(p, p + 6)}, twice));
  EXPECT_EQ(twice, EQ(7));
  // A pentagram turns left at every corner but winds twice.
  const Point2 star[5] = {Point2(0, 10), Point2(-6, -8), Point2(10, 3), Point2(-10, 3), Point2(6, -8)};
  EXPECT_FALSE(u.twice_area({Polygon2(star, star + 5)}, twice));
  // A spike back along an edge.
  const Point2 spike[4] = {Point2(0, 0), Point2(2, 0), Point2(1, 0), Point2(1, 1)};
  EXPECT_FALSE(u.twice_area({Polygon2(spike, spike + 4)}, twice));
  // Repeated and collinear vertices are fine.
  const Point2 rep[7] = {Point2(0, 0), Point2(0, 0), Point2(1, 0), Point2(2, 0), Point2(2, 2), Point2(0, 2), Point2(0, 0)};
  ASSERT_TRUE(u.twice_area({Polygon2(rep, rep + 7)}, twice));
  EXPECT_EQ(twice, EQ(8));
}

/// Seeded random convex polygons with many exact coincidences.
class Generator {
 public:
  explicit Generator(std::uint32_t seed) : rng_(seed) {}

  int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }

  /// A grid coordinate: integers over a small denominator (ties between polygons are common).
  FT coord(int denominator, int range) { return FT(uniform(0, range * denominator)) / FT(denominator); }

  /// The hull of a few grid points (CCW, no collinear vertices), optionally with an edge's
  /// midpoint put in (a straight-on vertex) or rebuilt by lazy arithmetic.
  Polygon2 hull(int denominator, int range, int points) {
    for (;;) {
      std::vector<Point2> in, out;
      for (int k = 0; k < points; ++k) in.emplace_back(coord(denominator, range), coord(denominator, range));
      CGAL::convex_hull_2(in.begin(), in.end(), std::back_inserter(out), Kernel());
      if (out.size() < 3) continue;
      Polygon2 p(out.begin(), out.end());
      if (CGAL::sign(shadow::exact::polygon_area(p)) != CGAL::POSITIVE) continue;
      if (uniform(0, 3) == 0) {  // a collinear vertex in the middle of an edge
        const std::size_t e = static_cast<std::size_t>(uniform(0, static_cast<int>(out.size()) - 1));
        const Point2& a = out[e];
        const Point2& b = out[(e + 1) % out.size()];
        out.insert(out.begin() + static_cast<std::ptrdiff_t>(e + 1), CGAL::midpoint(a, b));
        p = Polygon2(out.begin(), out.end());
      }
      return p;
    }
  }

  /// Points through lazy arithmetic nodes (a + (b - a) * t with t = 1), as clipping makes them.
  static Polygon2 lazy(const Polygon2& p) {
    Polygon2 q;
    const FT third = FT(1) / 3;
    for (auto v = p.vertices_begin(); v != p.vertices_end(); ++v)
      q.push_back(Point2((v->x() + third) - third, v->y() * 3 / 3));
    return q;
  }

  /// A thin triangle: two close points far from a third.
  Polygon2 sliver(int range) {
    for (;;) {
      const FT x = coord(7, range), y = coord(7, range);
      const Point2 a(x, y), b(x + FT(1) / 1024, y + FT(1) / 4096), c(coord(3, range), coord(5, range));
      if (CGAL::orientation(a, b, c) == CGAL::COLLINEAR) continue;
      Polygon2 t;
      t.push_back(a);
      t.push_back(b);
      t.push_back(c);
      if (t.is_clockwise_oriented()) t.reverse_orientation();
      return t;
    }
  }

  /// A cell of a grid partition (rectangles and their diagonal halves: shared edges both ways).
  Polygon2 cell(int range) {
    const int x = uniform(0, range - 1), y = uniform(0, range - 1);
    const Point2 p[4] = {Point2(x, y), Point2(x + 1, y), Point2(x + 1, y + 1), Point2(x, y + 1)};
    switch (uniform(0, 2)) {
      case 0: return Polygon2(p, p + 4);
      case 1: { const Point2 t[3] = {p[0], p[1], p[2]}; return Polygon2(t, t + 3); }
      default: { const Point2 t[3] = {p[0], p[2], p[3]}; return Polygon2(t, t + 3); }
    }
  }

  std::vector<Polygon2> scene(int n) {
    std::vector<Polygon2> polygons;
    const int range = uniform(2, 6);
    for (int k = 0; k < n; ++k) {
      switch (uniform(0, 7)) {
        case 0: polygons.push_back(hull(1, range, uniform(3, 6))); break;
        case 1: polygons.push_back(hull(3, range, uniform(3, 8))); break;
        case 2: polygons.push_back(lazy(hull(2, range, uniform(3, 6)))); break;
        case 3: polygons.push_back(sliver(range)); break;
        case 4: polygons.push_back(cell(range)); break;
        case 5:  // a copy of an earlier polygon (identical), sometimes through lazy nodes
          if (!polygons.empty()) {
            const Polygon2& q = polygons[static_cast<std::size_t>(uniform(0, static_cast<int>(polygons.size()) - 1))];
            polygons.push_back(uniform(0, 1) ? q : lazy(q));
          } else {
            polygons.push_back(cell(range));
          }
          break;
        case 6:  // an earlier polygon's vertex as one corner of a box (touching, sharing)
          if (!polygons.empty()) {
            const Polygon2& q = polygons.back();
            const Point2& c = q.vertex(static_cast<std::ptrdiff_t>(uniform(0, static_cast<int>(q.size()) - 1)));
            const FT w = FT(uniform(1, 4)) / 2, h = FT(uniform(1, 4)) / 2;
            switch (uniform(0, 3)) {
              case 0: polygons.push_back(box(c.x(), c.y(), c.x() + w, c.y() + h)); break;
              case 1: polygons.push_back(box(c.x() - w, c.y(), c.x(), c.y() + h)); break;
              case 2: polygons.push_back(box(c.x() - w, c.y() - h, c.x(), c.y())); break;
              default: polygons.push_back(box(c.x(), c.y() - h, c.x() + w, c.y())); break;
            }
          } else {
            polygons.push_back(cell(range));
          }
          break;
        default: {  // a triangle with rational corners
          for (;;) {
            const Point2 a(coord(5, range), coord(5, range)), b(coord(5, range), coord(5, range)),
                c(coord(5, range), coord(5, range));
            const CGAL::Orientation o = CGAL::orientation(a, b, c);
            if (o == CGAL::COLLINEAR) continue;
            const Point2 t[3] = {a, o == CGAL::LEFT_TURN ? b : c, o == CGAL::LEFT_TURN ? c : b};
            polygons.emplace_back(t, t + 3);
            break;
          }
        }
      }
    }
    return polygons;
  }

 private:
  std::mt19937 rng_;
};

TEST(ExactUnionArea, EqualsTheBooleanUnionOnRandomDegenerateScenes) {
  Generator g(20261126);
  ConvexUnionArea u;  // reused, as the engine's workers do
  int compared = 0;
  std::size_t inside = 0;  // polygons left out, inside another (identical ones, nested ones)
  for (int round = 0; round < 600; ++round) {
    const std::vector<Polygon2> polygons = g.scene(g.uniform(1, 14));
    EQ twice;
    ASSERT_TRUE(u.twice_area(polygons, twice)) << "round " << round;
    inside += u.counts().inside;
    const EQ expected = joined_area(polygons);
    ASSERT_EQ(twice / 2, expected) << "round " << round << ": " << polygons.size() << " polygons";
    ++compared;
  }
  EXPECT_EQ(compared, 600);
  EXPECT_GT(inside, 100u);
}

TEST(ExactUnionArea, OrderDoesNotMatter) {
  // The tie-break (the smaller index counts a shared stretch) must give the same area in any
  // order, including reversed.
  Generator g(7);
  ConvexUnionArea u;
  for (int round = 0; round < 100; ++round) {
    std::vector<Polygon2> polygons = g.scene(g.uniform(2, 10));
    EQ forward, backward;
    ASSERT_TRUE(u.twice_area(polygons, forward));
    std::reverse(polygons.begin(), polygons.end());
    ASSERT_TRUE(u.twice_area(polygons, backward));
    ASSERT_EQ(forward, backward) << "round " << round;
  }
}

TEST(ExactUnionArea, ManyBoxesInAGridEqualTheBooleanUnion) {
  // A larger cluster like a ground's: 150 overlapping rectangles with rational corners.
  Generator g(99);
  std::vector<Polygon2> polygons;
  for (int k = 0; k < 150; ++k) {
    const FT x = g.coord(4, 20), y = g.coord(4, 20);
    polygons.push_back(box(x, y, x + FT(g.uniform(1, 12)) / 4, y + FT(g.uniform(1, 12)) / 4));
  }
  ConvexUnionArea u;
  EQ twice;
  ASSERT_TRUE(u.twice_area(polygons, twice));
  EXPECT_EQ(twice / 2, joined_area(polygons));
  EXPECT_GT(u.counts().pairs, 0u);
}

TEST(ExactUnionArea, LongDiagonalShadowsApartAcrossAreNotNeighbours) {
  // A low sun's casts on a ground, diagonal: 60 long thin parallelograms along (1, 1), side by
  // side with gaps across (every fifth one shifted onto its neighbour); the boxes of strips up to
  // 20 apart overlap (997 pairs by their boxes alone). The neighbours are found across their main
  // direction, so only the 11 shifted strips that reach a neighbour make a pair, and the area is
  // the Boolean union's.
  std::vector<Polygon2> polygons;
  for (int k = 0; k < 60; ++k) {
    const FT x = FT(k) / 2 - (k % 5 == 0 ? FT(3) / 8 : FT(0)), w = FT(1) / 4;
    Polygon2 p;
    p.push_back(Point2(x, 0));
    p.push_back(Point2(x + w, 0));
    p.push_back(Point2(x + w + 10, 10));
    p.push_back(Point2(x + 10, 10));
    polygons.push_back(p);
  }
  ConvexUnionArea u;
  EQ twice;
  ASSERT_TRUE(u.twice_area(polygons, twice));
  EXPECT_EQ(twice / 2, joined_area(polygons));
  EXPECT_EQ(u.counts().pairs, 11u);  // (strip 0, shifted, has no neighbour before it)
}

TEST(ExactUnionArea, ShedScratchMeasuresTheSameAgain) {
  // A worker sheds the union's scratch after a union of many pairs (ExactWorker::trim): what it
  // measures next, large or small, is the same as from scratch kept or new.
  Generator g(7);
  std::vector<Polygon2> many, few = {box(0, 0, 2, 1), box(1, 0, 3, 2)};
  for (int k = 0; k < 120; ++k) {
    const FT x = g.coord(4, 3), y = g.coord(4, 3);  // crowded: most boxes meet most others
    many.push_back(box(x, y, x + FT(g.uniform(4, 12)) / 4, y + FT(g.uniform(4, 12)) / 4));
  }
  ConvexUnionArea kept, shed;
  EQ a, b;
  ASSERT_TRUE(kept.twice_area(many, a));
  ASSERT_TRUE(shed.twice_area(many, b));
  const std::size_t pairs = shed.counts().pairs;
  ASSERT_GT(pairs, 2000u);
  shed.shed(pairs * 2);  // room for this many: kept
  EXPECT_EQ(shed.counts().pairs, pairs);
  shed.shed(16);  // freed, counts and all
  EXPECT_EQ(shed.counts().pairs, 0u);
  ASSERT_TRUE(shed.twice_area(few, b));
  ASSERT_TRUE(kept.twice_area(few, a));
  EXPECT_EQ(a, b);
  EXPECT_EQ(b / 2, joined_area(few));
  shed.shed(16);
  ASSERT_TRUE(shed.twice_area(many, b));
  ASSERT_TRUE(kept.twice_area(many, a));
  EXPECT_EQ(a, b);
  EXPECT_EQ(b / 2, joined_area(many));
}

std::vector<shadow::exact::QPoint2> rational(const std::vector<Point2>& points) {
  std::vector<shadow::exact::QPoint2> out;
  for (const Point2& p : points) out.push_back({CGAL::exact(p.x()), CGAL::exact(p.y())});
  return out;
}

EQ twice_area_of(const std::vector<shadow::exact::QPoint2>& pts) {
  EQ out;
  shadow::exact::QScratch s;
  shadow::exact::twice_polygon_area(pts.data(), pts.data() + pts.size(), out, s);
  return out;
}

TEST(RationalPoints, IntervalsHoldTheirValue) {
  std::mt19937 rng(5);
  for (int k = 0; k < 2000; ++k) {
    const long num = std::uniform_int_distribution<long>(-1000000, 1000000)(rng);
    const long den = std::uniform_int_distribution<long>(1, 5000)(rng);
    EQ q(num, den);
    q.canonicalize();
    if (k % 3 == 0) q = EQ(static_cast<double>(num) / 1024.0);  // exact doubles: point intervals
    const shadow::exact::IA i = shadow::exact::interval_of(q);
    EXPECT_LE(EQ(i.inf()), q);
    EXPECT_GE(EQ(i.sup()), q);
    if (k % 3 == 0) EXPECT_TRUE(i.is_point());
  }
  // Long numerators and denominators (as projections and clips make them), both signs.
  for (int k = 0; k < 500; ++k) {
    mpz_class num = 0, den = 0;
    for (int limb = 0; limb < 1 + k % 9; ++limb) {
      num = num * 4294967296.0 + static_cast<double>(rng());
      den = den * 4294967296.0 + static_cast<double>(rng() | 1u);
    }
    if (k % 2) num = -num;
    if (k % 5 == 0) den = 1;
    EQ q(num, den);
    q.canonicalize();
    const shadow::exact::IA i = shadow::exact::interval_of(q);
    EXPECT_LE(EQ(i.inf()), q) << k;
    EXPECT_GE(EQ(i.sup()), q) << k;
    EXPECT_LE(i.sup() - i.inf(), 1e-14 * std::fabs(q.get_d())) << k;
  }
}

// Dyadic values at the low end of the double range: exact point intervals only where the value
// is a normal double; just below the least normal one (which ldexp would round up to it) and
// among the subnormals, an interval that holds the value.
TEST(RationalPoints, IntervalsAtTheEndsOfTheDoubleRange) {
  const auto check = [](const EQ& q, bool point) {
    const shadow::exact::IA i = shadow::exact::interval_of(q);
    EXPECT_LE(EQ(i.inf()), q) << q;
    EXPECT_GE(EQ(i.sup()), q) << q;
    EXPECT_EQ(i.is_point(), point) << q;
  };
  auto power = [](long e) {  // 2^e exactly
    EQ q(1);
    if (e >= 0)
      mpq_mul_2exp(q.get_mpq_t(), q.get_mpq_t(), static_cast<mp_bitcnt_t>(e));
    else
      mpq_div_2exp(q.get_mpq_t(), q.get_mpq_t(), static_cast<mp_bitcnt_t>(-e));
    return q;
  };
  for (int sign : {1, -1}) {
    check(sign * power(-1022), true);                       // the least normal double
    check(sign * (power(-1022) - power(-1075)), false);     // just below it: 53 bits, not a double
    check(sign * (power(-1022) + power(-1074)), true);      // a normal double, 53 bits
    check(sign * power(-1030), false);                      // a subnormal: left to the slow path
    check(sign * (power(53) - 1) / 2, true);                 // 53 bits over a power of two
    // Quotients far up and down the range (the scaled quotient's branch: shifts of 899 and
    // -900, at its ends), tight around their value.
    for (const EQ& q : {EQ(sign * power(900) / 3), EQ(sign * power(-899) / 3)}) {
      check(q, false);
      const shadow::exact::IA i = shadow::exact::interval_of(q);
      EXPECT_LE(i.sup() - i.inf(), 1e-15 * std::fabs(q.get_d())) << q;
    }
  }
}

TEST(RationalPoints, HullClipAndAreaSignMatchEpeck) {
  Generator g(31);
  shadow::exact::QScratch s;
  std::vector<std::size_t> order, chain;
  std::vector<int> side;
  EQ bound, sum;
  for (int round = 0; round < 300; ++round) {
    // Points with ties (coarse grid, repeats, collinear runs), some through lazy nodes.
    std::vector<Point2> in;
    const int n = g.uniform(1, 12);
    for (int k = 0; k < n; ++k) in.emplace_back(g.coord(3, 4), g.coord(3, 4));
    if (n > 2) in.push_back(CGAL::midpoint(in[0], in[1]));
    if (n > 1) in.push_back(in[1]);
    std::vector<Point2> hull;
    CGAL::convex_hull_2(in.begin(), in.end(), std::back_inserter(hull), Kernel());
    std::vector<shadow::exact::QPoint2> q = rational(in), qhull;
    shadow::exact::convex_hull(q, qhull, order, chain, s);
    ASSERT_EQ(qhull.size(), hull.size()) << "round " << round;  // no collinear vertices either way
    if (hull.size() >= 3) {
      EXPECT_EQ(twice_area_of(qhull), CGAL::exact(shadow::exact::polygon_area(hull.begin(), hull.end())) * 2);
      EXPECT_EQ(shadow::exact::area_sign(qhull, s, sum), CGAL::POSITIVE);
      std::vector<shadow::exact::QPoint2> reversed(qhull.rbegin(), qhull.rend());
      EXPECT_EQ(shadow::exact::area_sign(reversed, s, sum), CGAL::NEGATIVE);
    }
    // Clip both to the same box (bounds on the grid: vertices exactly on them).
    std::vector<Point2> lazy = hull, scratch;
    std::vector<shadow::exact::QPoint2> rat = qhull, qscratch;
    const double x0 = g.uniform(0, 6) / 3.0, x1 = x0 + g.uniform(1, 6) / 3.0;
    const double y0 = g.uniform(0, 6) / 3.0, y1 = y0 + g.uniform(1, 6) / 3.0;
    for (int c = 0; c < 2; ++c) {
      shadow::exact::clip_convex_2d(lazy, c, c == 0 ? x0 : y0, true, scratch);
      shadow::exact::clip_convex_2d(lazy, c, c == 0 ? x1 : y1, false, scratch);
      shadow::exact::clip_convex_2d(rat, c, c == 0 ? x0 : y0, true, qscratch, side, bound);
      shadow::exact::clip_convex_2d(rat, c, c == 0 ? x1 : y1, false, qscratch, side, bound);
    }
    ASSERT_EQ(rat.size(), lazy.size()) << "round " << round;
    for (std::size_t v = 0; v < rat.size(); ++v) {
      EXPECT_EQ(rat[v].x, CGAL::exact(lazy[v].x()));
      EXPECT_EQ(rat[v].y, CGAL::exact(lazy[v].y()));
    }
  }
}

// The clip to a convex window on rational points (a chart's convex piece: measure_in_scaled_pieces)
// against the lazy Epeck clip (measure_in_convex_pieces) point for point, and both against
// CGAL's intersection's area: integer corners (the integer cut), grid rationals, lazy points,
// straight-on vertices on either side, windows sharing edges and corners with the polygon.
TEST(RationalPoints, WindowClipMatchesEpeckAndTheIntersection) {
  Generator g(47);
  shadow::exact::QScratch s;
  std::vector<int> side;
  std::size_t cut = 0, emptied = 0;
  for (int round = 0; round < 600; ++round) {
    const int denominator = round % 3 == 0 ? 1 : g.uniform(1, 3);
    Polygon2 polygon = g.hull(denominator, 4, g.uniform(3, 8));
    if (round % 5 == 1) polygon = Generator::lazy(polygon);
    const Polygon2 window = round % 7 == 2 ? polygon : g.hull(g.uniform(1, 2), 4, g.uniform(3, 7));
    std::vector<Point2> lazy(polygon.vertices_begin(), polygon.vertices_end()), scratch;
    shadow::exact::clip_convex_to_window(lazy, window, scratch);
    std::vector<Point2> in(polygon.vertices_begin(), polygon.vertices_end());
    std::vector<Point2> corners(window.vertices_begin(), window.vertices_end());
    std::vector<shadow::exact::QPoint2> rat = rational(in), qwindow = rational(corners), qscratch;
    shadow::exact::clip_convex_to_window(rat, qwindow, qscratch, side, shadow::exact::IA(1), s);
    ASSERT_EQ(rat.size(), lazy.size()) << "round " << round;
    for (std::size_t v = 0; v < rat.size(); ++v) {
      EXPECT_EQ(rat[v].x, CGAL::exact(lazy[v].x())) << "round " << round;
      EXPECT_EQ(rat[v].y, CGAL::exact(lazy[v].y())) << "round " << round;
      const double x = CGAL::to_double(lazy[v].x()), y = CGAL::to_double(lazy[v].y());
      EXPECT_TRUE(rat[v].i.x.inf() <= x && x <= rat[v].i.x.sup() && rat[v].i.y.inf() <= y && y <= rat[v].i.y.sup());
    }
    // The same in a chart scaled by K = 3 (the intervals stay around the unscaled points).
    std::vector<shadow::exact::QPoint2> scaled = rational(in), swindow = rational(corners);
    for (std::vector<shadow::exact::QPoint2>* points : {&scaled, &swindow})
      for (shadow::exact::QPoint2& p : *points) {
        p.x *= 3;
        p.y *= 3;
      }
    shadow::exact::clip_convex_to_window(scaled, swindow, qscratch, side, shadow::exact::IA(3), s);
    ASSERT_EQ(scaled.size(), lazy.size()) << "round " << round;
    for (std::size_t v = 0; v < scaled.size(); ++v) {
      EXPECT_EQ(scaled[v].x, 3 * CGAL::exact(lazy[v].x())) << "round " << round;
      EXPECT_EQ(scaled[v].y, 3 * CGAL::exact(lazy[v].y())) << "round " << round;
      const double x = CGAL::to_double(lazy[v].x()), y = CGAL::to_double(lazy[v].y());
      EXPECT_TRUE(scaled[v].i.x.inf() <= x && x <= scaled[v].i.x.sup() && scaled[v].i.y.inf() <= y &&
                  y <= scaled[v].i.y.sup());
    }
    PolygonSet2 meet(polygon);
    meet.intersection(window);
    std::vector<PolygonWithHoles2> regions;
    meet.polygons_with_holes(std::back_inserter(regions));
    std::vector<FT> areas;
    for (const PolygonWithHoles2& r : regions) areas.push_back(shadow::exact::region_area(r));
    const EQ expected = CGAL::exact(shadow::exact::balanced_sum(areas));
    const EQ got = rat.size() >= 3 ? twice_area_of(rat) / 2 : EQ(0);
    EXPECT_EQ(got, expected) << "round " << round;
    cut += rat.size() >= 3 && expected != CGAL::exact(shadow::exact::polygon_area(polygon));
    emptied += rat.empty();
  }
  EXPECT_GT(cut, 200u);  // the cuts themselves, not only polygons wholly inside or outside
  EXPECT_GT(emptied, 20u);
}

/// The union's area inside a convex window without clipping (twice_area_in_window) against
/// the casts clipped to the window and united (twice_area), and against CGAL's join
/// intersected with the window: the same exact rational; and the boundary chain of the window
/// minus the union (window's boundary first) the same canonical segments both ways. Seeded
/// degenerate scenes: windows that are one of the polygons, a cell of the same grid, or a hull.
/// Whether two chains have the same canonical form, segment for segment (a failure names `what`).
void expect_same_canonical(shadow::exact::BoundaryChain& x, shadow::exact::BoundaryChain& y, const std::string& what) {
  std::vector<shadow::exact::BoundaryChain::Segment> a, b;
  ASSERT_TRUE(x.canonical(a)) << what;
  ASSERT_TRUE(y.canonical(b)) << what;
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t k = 0; k < a.size(); ++k)
    EXPECT_TRUE(a[k].from.x == b[k].from.x && a[k].from.y == b[k].from.y && a[k].to.x == b[k].to.x &&
                a[k].to.y == b[k].to.y && a[k].left == b[k].left)
        << what << " segment " << k;
}

TEST(ExactUnionArea, InAWindowEqualsTheClippedUnion) {
  Generator g(2026113);
  std::size_t partial = 0, left_out = 0;
  for (int round = 0; round < 500; ++round) {
    const std::vector<Polygon2> polygons = g.scene(g.uniform(1, 9));
    Polygon2 window;
    switch (round % 4) {
      case 0: window = polygons[static_cast<std::size_t>(g.uniform(0, static_cast<int>(polygons.size()) - 1))]; break;
      case 1: window = g.cell(4); break;
      case 2: window = Generator::lazy(g.hull(1, 5, g.uniform(3, 6))); break;
      default: window = g.hull(g.uniform(1, 3), 5, g.uniform(3, 7)); break;
    }
    std::vector<Point2> corners(window.vertices_begin(), window.vertices_end());
    const std::vector<shadow::exact::QPoint2> qwindow = rational(corners);
    std::vector<shadow::exact::QPoint2> all, clipped, poly, scratch;
    std::vector<std::size_t> all_first{0}, clipped_first{0};
    shadow::exact::QScratch qs;
    std::vector<int> side;
    for (const Polygon2& p : polygons) {
      std::vector<Point2> in(p.vertices_begin(), p.vertices_end());
      poly = rational(in);
      all.insert(all.end(), poly.begin(), poly.end());
      all_first.push_back(all.size());
      shadow::exact::clip_convex_to_window(poly, qwindow, scratch, side, shadow::exact::IA(1), qs);
      if (poly.size() < 3) continue;
      clipped.insert(clipped.end(), poly.begin(), poly.end());
      clipped_first.push_back(clipped.size());
    }
    ConvexUnionArea u;
    shadow::exact::BoundaryChain in_window, by_clip;
    for (shadow::exact::BoundaryChain* chain : {&in_window, &by_clip})
      for (std::size_t v = 0; v < qwindow.size(); ++v) {
        const auto& a = qwindow[v];
        const auto& b = qwindow[(v + 1) % qwindow.size()];
        chain->add(a.x, a.y, b.x, b.y);
      }
    EQ got, expected(0);
    ASSERT_TRUE(u.twice_area_in_window(all.data(), all_first, qwindow.data(), qwindow.size(), got, &in_window))
        << "round " << round;
    if (clipped_first.size() > 1) ASSERT_TRUE(u.twice_area(clipped, clipped_first, expected, &by_clip)) << "round " << round;
    EXPECT_EQ(got, expected) << "round " << round;
    // Areas only (no chain: polygons inside others left out), the same rational.
    EQ areas_only;
    ASSERT_TRUE(u.twice_area_in_window(all.data(), all_first, qwindow.data(), qwindow.size(), areas_only))
        << "round " << round;
    EXPECT_EQ(areas_only, got) << "round " << round;
    left_out += u.counts().inside;
    // CGAL: (join of the polygons) n window.
    PolygonSet2 joined;
    joined.join(polygons.begin(), polygons.end());
    joined.intersection(window);
    std::vector<PolygonWithHoles2> regions;
    joined.polygons_with_holes(std::back_inserter(regions));
    std::vector<FT> areas;
    for (const PolygonWithHoles2& r : regions) areas.push_back(shadow::exact::region_area(r));
    EXPECT_EQ(got, 2 * CGAL::exact(shadow::exact::balanced_sum(areas))) << "round " << round;
    expect_same_canonical(in_window, by_clip, "round " + std::to_string(round));
    const EQ window_twice = twice_area_of(qwindow);
    partial += got != 0 && got != window_twice;
  }
  EXPECT_GT(partial, 150u);
  EXPECT_GT(left_out, 50u);
}

/// A triangulated patch's casts share edges run both ways: ConvexUnionArea merges such
/// neighbours into convex polygons (merge_shared_edges) before it measures. Seeded jittered grids
/// split along random diagonals (some neighbours merge, some would not be convex), shuffled,
/// with loose triangles over them and, in half the rounds, a window: the same exact area as
/// CGAL's join (n window), and the same canonical boundary as the join's regions.
TEST(ExactUnionArea, TrianglesSharingEdgesMergeIntoTheSameUnion) {
  std::mt19937 rng(20261130);
  auto uniform = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  std::size_t merged = 0, rounds_merged = 0;
  for (int round = 0; round < 60; ++round) {
    const int k = uniform(3, 8), spacing = 40;
    std::vector<std::vector<Point2>> grid(static_cast<std::size_t>(k + 1));
    for (int i = 0; i <= k; ++i)
      for (int j = 0; j <= k; ++j)  // jitter under a quarter of the spacing: every triangle counter-clockwise
        grid[static_cast<std::size_t>(i)].emplace_back(FT(i * spacing + uniform(-9, 9)) / 7, FT(j * spacing + uniform(-9, 9)) / 7);
    std::vector<Polygon2> polygons;
    auto at = [&](int i, int j) { return grid[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]; };
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) {
        if (uniform(0, 9) == 0) continue;  // a gap
        const Point2 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
        const Point2 t1[3] = {a, b, c}, t2[3] = {a, c, d}, t3[3] = {a, b, d}, t4[3] = {b, c, d};
        if (uniform(0, 1) == 0) {
          polygons.emplace_back(t1, t1 + 3);
          polygons.emplace_back(t2, t2 + 3);
        } else {
          polygons.emplace_back(t3, t3 + 3);
          polygons.emplace_back(t4, t4 + 3);
        }
      }
    for (int extra = uniform(0, 4); extra > 0; --extra) {  // loose triangles across the patch
      const int x = uniform(0, k * spacing), y = uniform(0, k * spacing);
      const Point2 t[3] = {Point2(FT(x) / 7, FT(y) / 7), Point2(FT(x + uniform(10, 90)) / 7, FT(y) / 7),
                           Point2(FT(x) / 7, FT(y + uniform(10, 90)) / 7)};
      polygons.emplace_back(t, t + 3);
    }
    std::shuffle(polygons.begin(), polygons.end(), rng);
    std::vector<shadow::exact::QPoint2> all;
    std::vector<std::size_t> first{0};
    for (const Polygon2& p : polygons) {
      const std::vector<Point2> in(p.vertices_begin(), p.vertices_end());
      const std::vector<shadow::exact::QPoint2> q = rational(in);
      all.insert(all.end(), q.begin(), q.end());
      first.push_back(all.size());
    }
    PolygonSet2 joined;
    joined.join(polygons.begin(), polygons.end());
    const bool windowed = round % 2 == 1;
    const Polygon2 window = box(FT(spacing) / 21, FT(spacing) / 14, FT(k * spacing * 2) / 21, FT(k * spacing * 3) / 28);
    ConvexUnionArea u;
    shadow::exact::BoundaryChain chain, reference;
    EQ got;
    if (windowed) {
      const std::vector<Point2> corners(window.vertices_begin(), window.vertices_end());
      const std::vector<shadow::exact::QPoint2> qwindow = rational(corners);
      for (shadow::exact::BoundaryChain* c : {&chain, &reference})
        for (std::size_t v = 0; v < qwindow.size(); ++v) {
          const auto& a = qwindow[v];
          const auto& b = qwindow[(v + 1) % qwindow.size()];
          c->add(a.x, a.y, b.x, b.y);
        }
      ASSERT_TRUE(u.twice_area_in_window(all.data(), first, qwindow.data(), qwindow.size(), got, &chain));
      joined.intersection(window);
    } else {
      ASSERT_TRUE(u.twice_area(all, first, got, &chain));
    }
    std::vector<PolygonWithHoles2> regions;
    joined.polygons_with_holes(std::back_inserter(regions));
    std::vector<FT> areas;
    auto add_reversed = [&](const Polygon2& ring) {  // the union's boundary run backwards, as the chain gets it
      for (auto v = ring.vertices_begin(); v != ring.vertices_end(); ++v) {
        const Point2 from = *v, to = std::next(v) == ring.vertices_end() ? *ring.vertices_begin() : *std::next(v);
        reference.add(EQ(CGAL::exact(to.x())), EQ(CGAL::exact(to.y())), EQ(CGAL::exact(from.x())), EQ(CGAL::exact(from.y())));
      }
    };
    for (const PolygonWithHoles2& r : regions) {
      areas.push_back(shadow::exact::region_area(r));
      add_reversed(r.outer_boundary());
      for (auto h = r.holes_begin(); h != r.holes_end(); ++h) add_reversed(*h);
    }
    EXPECT_EQ(got, 2 * CGAL::exact(shadow::exact::balanced_sum(areas))) << "round " << round;
    expect_same_canonical(chain, reference, "round " + std::to_string(round));
    if (polygons.size() >= ConvexUnionArea::kMergeFrom) {
      merged += u.counts().merged;
      rounds_merged += u.counts().merged > 0;
    } else {
      EXPECT_EQ(u.counts().merged, 0u) << "round " << round;
    }
  }
  EXPECT_GT(rounds_merged, 40u);
  EXPECT_GT(merged, 1000u);
}

/// The engine with areas only (the route without a Boolean operation) against the engine with
/// polygons (PolygonSet2::join, then the regions' areas): the same doubles, bit for bit.
/// Every face's lit and shadow areas and lit fraction the same doubles in `a` and `b`; returns the
/// number of partly shadowed receivers (where a union was measured).
std::size_t expect_same_lighting(const shadow::ShadowResult& a, const shadow::ShadowResult& b) {
  EXPECT_EQ(a.lighting.size(), b.lighting.size());
  std::size_t shadowed = 0;
  for (std::size_t r = 0; r < a.lighting.size() && r < b.lighting.size(); ++r) {
    EXPECT_EQ(a.lighting[r].lit_area, b.lighting[r].lit_area) << "face " << a.lighting[r].face_id;
    EXPECT_EQ(a.lighting[r].shadow_area, b.lighting[r].shadow_area) << "face " << a.lighting[r].face_id;
    EXPECT_EQ(a.lighting[r].lit_fraction, b.lighting[r].lit_fraction) << "face " << a.lighting[r].face_id;
    shadowed += a.lighting[r].faces_light && a.lighting[r].shadow_area > 0 && a.lighting[r].lit_area > 0;
  }
  return shadowed;
}

void expect_areas_route_equals_join_route(const shadow::Scene& scene, std::size_t tile_casters) {
  shadow::ShadowOptions areas, polygons;
  areas.threads = polygons.threads = 2;
  areas.polygons = false;
  areas.tile_casters = polygons.tile_casters = tile_casters;
  const std::size_t shadowed =
      expect_same_lighting(shadow::compute_shadows(scene, areas), shadow::compute_shadows(scene, polygons));
  EXPECT_GT(shadowed, 10u);  // partly shadowed receivers: the unions were exercised
}

/// Closed solids that are not convex cast through their faces turned to a directional light
/// (ReceiverCuller): L-shaped buildings in triangles, closed and open at the bottom, on a ground
/// and facing each other, under suns from every side, low and high. The same scene with every
/// face a mesh of its own (no solid found) gives the same exact areas, bit for bit, with more
/// candidates.
TEST(ExactUnionAreaInTheEngine, ClosedSolidsCastThroughTheirFacesTurnedToTheLight) {
  const auto l_prism = [](glm::dvec3 at, double h, bool floor) { return shadow::test::l_prism_triangles(at, h, floor); };
  shadow::Scene solids, apart;
  std::vector<std::vector<shadow::Polygon3>> meshes;
  meshes.push_back({{{-30, -30, 0}, {40, -30, 0}, {40, 40, 0}, {-30, 40, 0}}});
  meshes.push_back(l_prism({0, 0, 0}, 9, true));
  meshes.push_back(l_prism({8, 1, 0}, 5.5, false));
  meshes.push_back(l_prism({-2, 9, 0}, 12, false));
  meshes.push_back(l_prism({9, 10, 0.0}, 3, true));
  meshes.push_back(l_prism({-12, -3, 0}, 7, true));  // these two inward (outward -1 and -2)
  meshes.push_back(l_prism({-11, 12, 0}, 4, false));
  for (std::size_t m = meshes.size() - 2; m < meshes.size(); ++m)
    for (shadow::Polygon3& f : meshes[m]) std::reverse(f.begin(), f.end());
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    shadow::add_mesh(solids, "mesh" + std::to_string(m), meshes[m]);
    for (std::size_t f = 0; f < meshes[m].size(); ++f)
      shadow::add_mesh(apart, "mesh" + std::to_string(m) + "/" + std::to_string(f), {meshes[m][f]});
  }
  for (shadow::Scene* scene : {&solids, &apart}) {
    for (int azimuth = 0; azimuth < 360; azimuth += 45)
      scene->lights.push_back(shadow::directional_light("sun", shadow::sun_direction(azimuth % 90 == 0 ? 12 : 47, azimuth)));
    scene->lights.push_back(shadow::point_light("lamp", {5, 4, 20}));
    shadow::validate_scene(*scene);
  }
  shadow::ShadowOptions options;
  options.threads = 2;
  options.polygons = false;
  const shadow::ShadowResult a = shadow::compute_shadows(solids, options);
  const shadow::ShadowResult b = shadow::compute_shadows(apart, options);
  const std::size_t shadowed = expect_same_lighting(a, b);
  EXPECT_GT(shadowed, 40u);
  // The faces turned away were dropped. (Many of them are left out in both scenes by the
  // caster-plane rule too, core/culling.hpp: the receiver lies on the light's side of their plane.)
  EXPECT_LT(a.stats.candidate_pairs, b.stats.candidate_pairs * 9 / 10);
}

TEST(ExactUnionAreaInTheEngine, CityUnderSunsAndALampEqualsTheJoin) {
  shadow::Scene scene = shadow::make_city(60, 120, 17);
  scene.lights.push_back(shadow::directional_light("low sun", shadow::sun_direction(12, 130)));
  scene.lights.push_back(shadow::directional_light("noon", shadow::sun_direction(60, 185)));
  scene.lights.push_back(shadow::directional_light("oblique", {0.3, -0.7, 0.5}));
  scene.lights.push_back(shadow::point_light("lamp", {15, -20, 40}));
  shadow::validate_scene(scene);
  expect_areas_route_equals_join_route(scene, 0);
  expect_areas_route_equals_join_route(scene, 40);  // the ground in tiles
}

// Areas only, a receiver's casts begin with the solids whose light-space box contains its own,
// and one whose cast holds the whole chart box ends the job before the candidate search. Every
// area is the join's all the same (those casts are ones the search would make, in another
// order), receivers so decided are dark, and neither the areas nor the counts depend on the
// number of threads. Walls shaded whole by a slab in front of them and by one across their
// plane, and a city under a low and a high sun.
TEST(ExactUnionAreaInTheEngine, ReceiversInOneSolidsShadowEqualTheJoin) {
  for (const glm::dvec3 to_light : {glm::dvec3(0.125, 1, 1), glm::dvec3(4, 1, 1)}) {
    shadow::Scene scene;
    shadow::add_mesh(scene, "house", shadow::box_faces({0, -5, 0}, {10, 0, 10}));
    if (to_light.x < 1) shadow::add_mesh(scene, "slab", shadow::box_faces({-0.625, 2, 0}, {11.25, 3, 20}));
    else shadow::add_mesh(scene, "slab", shadow::box_faces({11, -2, 0}, {25, 3, 20}));  // across the wall's plane
    scene.lights.push_back(shadow::directional_light("sun", to_light));
    shadow::validate_scene(scene);
    shadow::ShadowOptions areas;
    areas.polygons = false;
    const shadow::ShadowResult result = shadow::compute_shadows(scene, areas);
    const shadow::FaceLighting* wall = nullptr;
    for (const shadow::FaceLighting& l : result.lighting) {
      const shadow::Polygon3& face = scene.faces[l.face_id].vertices;
      if (l.face_id < 6 && face[0].y == 0 && face[1].y == 0 && face[2].y == 0) wall = &l;
    }
    ASSERT_NE(wall, nullptr);
    EXPECT_TRUE(wall->faces_light);
    EXPECT_EQ(wall->lit_area, 0.0);
    EXPECT_EQ(wall->shadow_area, wall->area);
    expect_same_lighting(result, shadow::compute_shadows(scene, shadow::ShadowOptions{}));
  }
  shadow::Scene city = shadow::make_city(80, 120, 11);
  city.lights.push_back(shadow::directional_light("low sun", shadow::sun_direction(8, 200)));
  city.lights.push_back(shadow::directional_light("high sun", shadow::sun_direction(35, 120)));
  shadow::validate_scene(city);
  expect_areas_route_equals_join_route(city, 0);
  shadow::ShadowOptions two, one;
  two.polygons = one.polygons = false;
  two.threads = 2;
  one.threads = 1;
  const shadow::ShadowResult a = shadow::compute_shadows(city, two), b = shadow::compute_shadows(city, one);
  expect_same_lighting(a, b);
  EXPECT_EQ(a.stats.candidate_pairs, b.stats.candidate_pairs);
  EXPECT_EQ(a.stats.casting_pairs, b.stats.casting_pairs);
  std::size_t dark = 0;
  for (const shadow::FaceLighting& l : a.lighting) dark += l.faces_light && l.lit_area == 0.0 ? 1 : 0;
  EXPECT_GE(dark, 20u);  // the low sun shades many walls whole
}

// A city turned 30 degrees about the vertical: its roofs and its ground are rectangles whose
// charts are not their bounding boxes (the walls' still are), so the casts on them are clipped
// to the convex chart and united from their boundaries, not joined; on the L-shaped forecourt,
// the turned L-shaped terrace among the buildings and a turned L-shaped yard that is not
// exactly planar (charts that are not convex) the casts are clipped to each convex piece and
// the pieces' areas added. Every area as the polygons route gives it.
TEST(ExactUnionAreaInTheEngine, TurnedCityOnTurnedAndLShapedChartsEqualsTheJoin) {
  shadow::Scene scene = shadow::make_city(40, 100, 5);
  shadow::add_mesh(scene, "terrace",
                   {shadow::Polygon3{{-12, -12, 0.25}, {12, -12, 0.25}, {12, -2, 0.25}, {-2, -2, 0.25}, {-2, 12, 0.25}, {-12, 12, 0.25}}});
  // Not exactly planar (one corner 1e-9 high, within the planarity tolerance): the lazy route's
  // pieces (measure_in_convex_pieces), not the rational points'.
  const std::size_t yard = scene.faces.size();
  shadow::add_mesh(scene, "yard",
                   {shadow::Polygon3{{40, 40, 0.3}, {64, 40, 0.3}, {64, 50, 0.3 + 1e-9}, {50, 50, 0.3}, {50, 64, 0.3}, {40, 64, 0.3}}});
  const double c = std::cos(0.5235987755982988), s = std::sin(0.5235987755982988);
  for (shadow::Face& face : scene.faces)
    for (glm::dvec3& v : face.vertices) v = {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
  shadow::add_mesh(scene, "forecourt",
                   {shadow::Polygon3{{-30, -30, 0.5}, {-5, -30, 0.5}, {-5, -20, 0.5}, {-20, -20, 0.5}, {-20, 5, 0.5}, {-30, 5, 0.5}}});
  shadow::add_mesh(scene, "pavilion", shadow::box_faces({-28, -28, 0.5}, {-24, -24, 6}));
  scene.lights.push_back(shadow::directional_light("low sun", shadow::sun_direction(15, 120)));
  scene.lights.push_back(shadow::directional_light("noon", shadow::sun_direction(55, 190)));
  scene.lights.push_back(shadow::directional_light("west", shadow::sun_direction(25, 250)));
  scene.lights.push_back(shadow::point_light("lamp", {10, -15, 35}));
  shadow::validate_scene(scene);
  expect_areas_route_equals_join_route(scene, 0);
  expect_areas_route_equals_join_route(scene, 40);  // the ground in tiles
  expect_areas_route_equals_join_route(scene, 6);   // the L-shaped faces in tiles too
  // The yard is partly in shadow under some sun (its pieces' route was exercised).
  shadow::ShadowOptions areas;
  areas.polygons = false;
  const shadow::ShadowResult a = shadow::compute_shadows(scene, areas);
  int partly = 0;
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    const shadow::FaceLighting* f = a.find(yard, l);
    partly += f != nullptr && f->lit_area > 0 && f->shadow_area > 0;
  }
  EXPECT_GE(partly, 1);
}

// Comb-shaped receivers (turned, so that neither is a box) with few and with many convex pieces
// (12 teeth: within kMaxChartPiecesToClip, clipped piece by piece; 60 teeth: beyond it, the
// join), under boxes whose shadows span several teeth: every area as the polygons route gives it.
/// A triangulated terrain (a TIN of gently jittered heights) under low suns: each triangle
/// receives the casts of its neighbours, which share edges run both ways and are merged before
/// the union is measured (geometry/shared_edge_merge.hpp), with an L-shaped building and a
/// capped one (closed solids) on it. The areas-only route equals the polygons route (the join,
/// which merges nothing) bit for bit.
TEST(ExactUnionAreaInTheEngine, TriangulatedTerrainWithMergedCastsEqualsTheJoin) {
  std::mt19937 rng(2026113023);
  std::uniform_real_distribution<double> height(0.0, 0.75);
  constexpr int kCells = 14;
  std::vector<std::vector<double>> z(kCells + 1, std::vector<double>(kCells + 1));
  for (auto& row : z)
    for (double& h : row) h = std::round(height(rng) * 64) / 64;  // dyadic: exactly planar triangles
  std::vector<shadow::Polygon3> terrain;
  auto p = [&](int i, int j) { return glm::dvec3(2.0 * i, 2.0 * j, z[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]); };
  for (int i = 0; i < kCells; ++i)
    for (int j = 0; j < kCells; ++j) {
      if ((i + 2 * j) % 3 == 0) {
        terrain.push_back({p(i, j), p(i + 1, j), p(i + 1, j + 1)});
        terrain.push_back({p(i, j), p(i + 1, j + 1), p(i, j + 1)});
      } else {
        terrain.push_back({p(i, j), p(i + 1, j), p(i, j + 1)});
        terrain.push_back({p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)});
      }
    }
  shadow::Scene scene;
  shadow::add_mesh(scene, "terrain", terrain);
  shadow::add_mesh(scene, "building", shadow::test::l_prism_triangles({8, 9, 0.75}, 6, true));
  shadow::add_mesh(scene, "capped", shadow::test::l_prism_triangles({17, 6, 0.75}, 4, false));
  scene.lights.push_back(shadow::directional_light("low", shadow::sun_direction(4, 200)));
  scene.lights.push_back(shadow::directional_light("grazing", shadow::sun_direction(2, 75)));
  scene.lights.push_back(shadow::directional_light("afternoon", shadow::sun_direction(14, 250)));
  shadow::validate_scene(scene);
  expect_areas_route_equals_join_route(scene, 0);
}

TEST(ExactUnionAreaInTheEngine, CombReceiversUnderBoxesEqualTheJoin) {
  shadow::Scene scene;
  shadow::add_mesh(scene, "small comb", {shadow::comb_polygon(12, 0)});
  shadow::Polygon3 big = shadow::comb_polygon(60, 0);
  for (glm::dvec3& v : big) v.y += 12;
  shadow::add_mesh(scene, "big comb", {big});
  std::vector<shadow::Polygon3> boxes;
  for (int k = 0; k < 12; ++k) {
    const double x = 1.3 + 4.7 * k, y = k % 2 == 0 ? 3.1 : 15.4;
    const std::vector<shadow::Polygon3> b = shadow::box_faces({x, y, 0.5}, {x + 1.1, y + 0.9, 2.5 + (k % 3)});
    boxes.insert(boxes.end(), b.begin(), b.end());
  }
  shadow::add_mesh(scene, "boxes", boxes);
  const double c = std::cos(0.4), s = std::sin(0.4);
  for (shadow::Face& face : scene.faces)
    for (glm::dvec3& v : face.vertices) v = {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
  scene.lights.push_back(shadow::directional_light("sun", shadow::sun_direction(35, 150)));
  scene.lights.push_back(shadow::directional_light("low", shadow::sun_direction(12, 250)));
  shadow::validate_scene(scene);
  EXPECT_LE(shadow::exact::prepare_face(scene.faces[0].vertices).convex_pieces.size(), shadow::exact::kMaxChartPiecesToClip);
  EXPECT_GT(shadow::exact::prepare_face(scene.faces[1].vertices).convex_pieces.size(), shadow::exact::kMaxChartPiecesToClip);
  shadow::ShadowOptions areas, polygons;
  areas.polygons = false;
  const shadow::ShadowResult a = shadow::compute_shadows(scene, areas);
  const shadow::ShadowResult b = shadow::compute_shadows(scene, polygons);
  ASSERT_EQ(a.lighting.size(), b.lighting.size());
  int partly = 0;
  for (std::size_t r = 0; r < a.lighting.size(); ++r) {
    EXPECT_EQ(a.lighting[r].lit_area, b.lighting[r].lit_area) << "face " << a.lighting[r].face_id;
    EXPECT_EQ(a.lighting[r].lit_fraction, b.lighting[r].lit_fraction) << "face " << a.lighting[r].face_id;
    partly += a.lighting[r].face_id < 2 && a.lighting[r].lit_area > 0 && a.lighting[r].shadow_area > 0;
  }
  EXPECT_EQ(partly, 4);  // both combs partly shadowed under both suns
}

TEST(ExactUnionAreaInTheEngine, NonConvexCastFallsBackToTheJoin) {
  // A comb (one polygon cast whole: not convex) over a ground with boxes whose shadows overlap it.
  shadow::Scene scene;
  shadow::add_mesh(scene, "ground", {shadow::rectangle_z(-10, -10, 40, 30, 0)});
  shadow::add_mesh(scene, "comb", {shadow::comb_polygon(20, 2)}, false);
  std::vector<shadow::Polygon3> boxes = shadow::box_faces({3, 3, 0}, {6, 5, 4});
  const std::vector<shadow::Polygon3> more = shadow::box_faces({10.5, -2, 0}, {12, 12, 3});
  boxes.insert(boxes.end(), more.begin(), more.end());
  shadow::add_mesh(scene, "boxes", boxes);
  scene.lights.push_back(shadow::directional_light("sun", {0.1, 0.2, 1}));
  scene.lights.push_back(shadow::directional_light("sun 2", {-0.3, 0.1, 1}));
  shadow::validate_scene(scene);
  shadow::ShadowOptions areas, polygons;
  areas.polygons = false;
  const shadow::ShadowResult a = shadow::compute_shadows(scene, areas);
  const shadow::ShadowResult b = shadow::compute_shadows(scene, polygons);
  ASSERT_EQ(a.lighting.size(), b.lighting.size());
  for (std::size_t r = 0; r < a.lighting.size(); ++r) {
    EXPECT_EQ(a.lighting[r].lit_area, b.lighting[r].lit_area);
    EXPECT_EQ(a.lighting[r].lit_fraction, b.lighting[r].lit_fraction);
  }
  const shadow::FaceLighting* ground = a.find(0, 0);
  ASSERT_NE(ground, nullptr);
  EXPECT_GT(ground->shadow_area, 5.5 * 20);  // the comb's shadow and the boxes'
}


// ---- a lit region's boundary without a Boolean operation (exact_lit_boundary) -----------------

using shadow::exact::BoundaryChain;

/// Twice the signed area enclosed by canonical segments (each counted on its region's side).
EQ twice_area_of_segments(const std::vector<BoundaryChain::Segment>& segments) {
  EQ sum(0);
  for (const BoundaryChain::Segment& s : segments) {
    const EQ cross = s.from.x * s.to.y - s.from.y * s.to.x;
    if (s.left) sum += cross;
    else sum -= cross;
  }
  return sum;
}

BoundaryChain::Point pt(int x, int y) { return {EQ(x), EQ(y)}; }

TEST(BoundaryChain, CanonicalFormIgnoresSplitsOrderAndCancellingStretches) {
  // The unit-by-two rectangle [0, 2] x [0, 1] minus nothing, described three ways.
  BoundaryChain a, b, c;
  std::vector<BoundaryChain::Segment> ca, cb, cc;
  a.add(pt(0, 0), pt(2, 0));
  a.add(pt(2, 0), pt(2, 1));
  a.add(pt(2, 1), pt(0, 1));
  a.add(pt(0, 1), pt(0, 0));
  // Two unit squares side by side (their shared side both ways), one side split, reordered.
  b.add(pt(1, 1), pt(0, 1));
  b.add(pt(1, 0), pt(2, 0));
  b.add(pt(0, 0), pt(1, 0));
  b.add(pt(1, 0), pt(1, 1));
  b.add(pt(2, 1), pt(1, 1));
  b.add(pt(0, 1), pt(0, 0));
  b.add(pt(1, 1), pt(1, 0));
  b.add(pt(2, 0), pt(2, 1));
  // The rectangle, then a square inside removed and put back (its boundary both ways).
  c.add(pt(0, 0), pt(2, 0));
  c.add(pt(2, 0), pt(2, 1));
  c.add(pt(2, 1), pt(0, 1));
  c.add(pt(0, 1), pt(0, 0));
  c.add({EQ(1, 4), EQ(1, 4)}, {EQ(1, 4), EQ(3, 4)});
  c.add({EQ(1, 4), EQ(3, 4)}, {EQ(3, 4), EQ(3, 4)});
  c.add({EQ(3, 4), EQ(1, 4)}, {EQ(3, 4), EQ(3, 4)});
  c.add({EQ(3, 4), EQ(1, 4)}, {EQ(1, 4), EQ(1, 4)});
  c.add({EQ(3, 4), EQ(3, 4)}, {EQ(3, 4), EQ(1, 4)});
  c.add({EQ(1, 4), EQ(1, 4)}, {EQ(3, 4), EQ(1, 4)});
  c.add({EQ(3, 4), EQ(3, 4)}, {EQ(1, 4), EQ(3, 4)});
  c.add({EQ(1, 4), EQ(3, 4)}, {EQ(1, 4), EQ(1, 4)});
  ASSERT_TRUE(a.canonical(ca));
  ASSERT_TRUE(b.canonical(cb));
  ASSERT_TRUE(c.canonical(cc));
  ASSERT_EQ(ca.size(), 4u);
  for (const auto* other : {&cb, &cc}) {
    ASSERT_EQ(other->size(), ca.size());
    for (std::size_t k = 0; k < ca.size(); ++k) {
      EXPECT_EQ((*other)[k].from.x, ca[k].from.x);
      EXPECT_EQ((*other)[k].from.y, ca[k].from.y);
      EXPECT_EQ((*other)[k].to.x, ca[k].to.x);
      EXPECT_EQ((*other)[k].to.y, ca[k].to.y);
      EXPECT_EQ((*other)[k].left, ca[k].left);
    }
  }
  EXPECT_EQ(twice_area_of_segments(ca), EQ(4));
  // Lines in order (non-vertical by slope, then intercept; vertical last), stretches along them.
  EXPECT_EQ(ca[0].from.y, EQ(0));
  EXPECT_TRUE(ca[0].left);   // the bottom, run left to right, region above: on its left
  EXPECT_FALSE(ca[1].left);  // the top: region below
  EXPECT_EQ(ca[2].from.x, EQ(0));
  EXPECT_FALSE(ca[2].left);  // x = 0 run upwards: the region on its right
  // A stretch counted twice the same way is not a region's boundary.
  BoundaryChain d;
  d.add(pt(0, 0), pt(2, 0));
  d.add(pt(1, 0), pt(3, 0));
  std::vector<BoundaryChain::Segment> cd;
  EXPECT_FALSE(d.canonical(cd));
  // Two triangles touching at a point on a line, their regions on either side of it.
  BoundaryChain e;
  e.add(pt(0, 0), pt(1, 0));
  e.add(pt(1, 0), pt(0, 1));
  e.add(pt(0, 1), pt(0, 0));
  e.add(pt(1, 0), pt(2, -1));
  e.add(pt(2, -1), pt(2, 0));
  e.add(pt(2, 0), pt(1, 0));
  std::vector<BoundaryChain::Segment> ce;
  ASSERT_TRUE(e.canonical(ce));
  EXPECT_EQ(twice_area_of_segments(ce), EQ(2));
}

/// Every receiver and light of `scene`: the boundary route's canonical boundary is the join's,
/// segment for segment, and both enclose the lit area. `by_chain`: the pairs the boundary route
/// (not the join) answered with a partly lit region.
void expect_lit_boundaries_equal_the_join(const shadow::Scene& scene, std::size_t& by_chain,
                                          bool integer_charts = true) {
  const shadow::ShadowEngine engine(scene, 1);
  const shadow::core::PreparedScene ctx = shadow::engine::prepared_scene(engine);
  EXPECT_EQ(ctx.chart_least_bit.has_value(), integer_charts);
  shadow::exact::ExactWorker w;
  w.reset(scene.faces.size(), ctx.solids->size());
  shadow::ShadowStats stats;
  by_chain = 0;
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    const shadow::Light& light_in = scene.lights[l];
    const shadow::exact::ExactLight light = shadow::exact::to_exact_light(light_in);
    std::optional<shadow::core::LightSpaceGrid> grid;
    if (light_in.type == shadow::LightType::Directional) grid.emplace(*ctx.cull, *ctx.prep, light_in.to_light);
    for (std::size_t f = 0; f < scene.faces.size(); ++f) {
      if ((*ctx.prep)[f].degenerate) continue;
      const shadow::exact::ExactFace& P = w.face(ctx, f);
      const int side = CGAL::sign(shadow::exact::plane_at_light(P, light));
      const shadow::core::LightSpaceGrid* g = grid ? &*grid : nullptr;
      const shadow::exact::LitBoundary a = shadow::exact::exact_lit_boundary(ctx, w, f, l, light, side, light_in, g, stats);
      const shadow::exact::LitBoundary b =
          shadow::exact::exact_lit_boundary(ctx, w, f, l, light, side, light_in, g, stats, true);
      const std::string where = "face " + std::to_string(f) + ", light " + std::to_string(l);
      EXPECT_EQ(a.kind, b.kind) << where;
      EXPECT_EQ(CGAL::exact(a.lit_chart_area), CGAL::exact(b.lit_chart_area)) << where;
      EXPECT_EQ(a.lighting.lit_area, b.lighting.lit_area) << where;
      EXPECT_EQ(a.lighting.shadow_area, b.lighting.shadow_area) << where;
      if (a.kind == shadow::exact::LitRegion::Kind::Partial && !a.via_join) ++by_chain;
      ASSERT_EQ(a.segments.size(), b.segments.size()) << where;
      EQ twice(0);
      for (std::size_t k = 0; k < a.segments.size(); ++k) {
        const shadow::exact::BoundarySegment &sa = a.segments[k], &sb = b.segments[k];
        ASSERT_TRUE(sa.from == sb.from && sa.to == sb.to && sa.left == sb.left) << where << ", segment " << k;
        ASSERT_EQ(CGAL::compare_xy(sa.from, sa.to), CGAL::SMALLER) << where;
        const EQ cross = CGAL::exact(sa.from.x() * sa.to.y() - sa.from.y() * sa.to.x());
        twice += sa.left ? cross : EQ(-cross);
      }
      if (a.kind == shadow::exact::LitRegion::Kind::Partial)
        EXPECT_EQ(twice, 2 * CGAL::exact(a.lit_chart_area)) << where;
    }
  }
}

// The turned city of TurnedCityOnTurnedAndLShapedChartsEqualsTheJoin (box charts, turned
// convex charts, L-shaped charts clipped piece by piece, a yard not exactly planar: the join),
// a comb within and one beyond kMaxChartPiecesToClip, a caster cast whole as one non-convex
// polygon (the join), under suns and a lamp (the join).
TEST(LitBoundary, FromTheUnionsPiecesEqualsTheJoinsCanonicalBoundary) {
  // A turned city (its ground and roofs have charts that are not boxes, its walls box charts).
  shadow::Scene scene = shadow::make_city(24, 60, 5);
  const double c = std::cos(0.5235987755982988), s = std::sin(0.5235987755982988);
  for (shadow::Face& face : scene.faces)
    for (glm::dvec3& v : face.vertices) v = {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
  // L-shaped charts (pieces), one of them not exactly planar (the lazy route: the join).
  shadow::add_mesh(scene, "terrace",
                   {shadow::Polygon3{{-12, -12, 0.25}, {12, -12, 0.25}, {12, -2, 0.25}, {-2, -2, 0.25}, {-2, 12, 0.25}, {-12, 12, 0.25}}});
  shadow::add_mesh(scene, "yard",
                   {shadow::Polygon3{{30, 30, 0.3}, {54, 30, 0.3}, {54, 40, 0.3 + 1e-9}, {40, 40, 0.3}, {40, 54, 0.3}, {30, 54, 0.3}}});
  // Combs within and beyond kMaxChartPiecesToClip (the join), and a comb cast whole as one
  // non-convex polygon (the join), over boxes.
  shadow::Polygon3 comb = shadow::comb_polygon(12, 0);
  for (glm::dvec3& v : comb) v += glm::dvec3(-40, 20, 0.2);
  shadow::add_mesh(scene, "small comb", {comb});
  shadow::Polygon3 big = shadow::comb_polygon(60, 0);
  for (glm::dvec3& v : big) v += glm::dvec3(-40, -40, 0.2);
  shadow::add_mesh(scene, "big comb", {big});
  shadow::Polygon3 hanging = shadow::comb_polygon(20, 2);
  for (glm::dvec3& v : hanging) v += glm::dvec3(-38, 21, 3);
  shadow::add_mesh(scene, "hanging comb", {hanging}, false);
  std::vector<shadow::Polygon3> boxes;
  for (int k = 0; k < 8; ++k) {
    const double x = -38.7 + 4.7 * k, y = k % 2 == 0 ? 23.1 : -36.6;
    const std::vector<shadow::Polygon3> b = shadow::box_faces({x, y, 0.2}, {x + 1.1, y + 0.9, 2.5 + (k % 3)});
    boxes.insert(boxes.end(), b.begin(), b.end());
  }
  shadow::add_mesh(scene, "boxes", boxes);
  scene.lights.push_back(shadow::directional_light("low sun", shadow::sun_direction(15, 120)));
  scene.lights.push_back(shadow::directional_light("noon", shadow::sun_direction(55, 190)));
  scene.lights.push_back(shadow::directional_light("west", shadow::sun_direction(25, 250)));
  scene.lights.push_back(shadow::point_light("lamp", {10, -15, 35}));
  shadow::validate_scene(scene);
  std::size_t by_chain = 0;
  expect_lit_boundaries_equal_the_join(scene, by_chain);
  EXPECT_GT(by_chain, 100u);
  // A city not turned: box charts throughout (the ground's casts cut by its box).
  shadow::Scene plain = shadow::make_city(16, 40, 9);
  plain.lights = scene.lights;
  shadow::validate_scene(plain);
  expect_lit_boundaries_equal_the_join(plain, by_chain);
  EXPECT_GT(by_chain, 50u);  // box charts throughout
  // The same city with a far triangle that has a coordinate 2^-150: the scene spans too many
  // bits for integer charts, so the route works in the unscaled rationals (K = 1).
  shadow::add_mesh(plain, "far", {shadow::Polygon3{{5000, 5000, std::ldexp(1.0, -150)}, {5001, 5000, 0}, {5000, 5001, 0}}});
  shadow::validate_scene(plain);
  expect_lit_boundaries_equal_the_join(plain, by_chain, false);
  EXPECT_GT(by_chain, 50u);
}

}  // namespace
