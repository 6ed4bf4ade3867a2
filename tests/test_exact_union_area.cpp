// SPDX-License-Identifier: GPL-3.0-or-later
// The exact engine's union area without a Boolean operation (exact/convex_union_area.hpp,
// internal header) against CGAL's aggregated union (PolygonSet2::join and the regions' areas,
// the route it replaces): the two exact rationals are equal (==, not doubles) on seeded random
// convex polygons full of degenerate contacts: shared edges going the same way and the other
// way, identical polygons, polygons inside others, touching at vertices, collinear overlapping
// edges, collinear vertices, triangles, slivers, points on coarse rational grids (many exact
// ties) and points made by lazy arithmetic (as clipping makes them).
#include "exact/convex_union_area.hpp"
#include "exact/regions.hpp"

#include <gtest/gtest.h>

#include <CGAL/convex_hull_2.h>

#include <cstdint>
#include <iterator>
#include <random>
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
  for (int round = 0; round < 600; ++round) {
    const std::vector<Polygon2> polygons = g.scene(g.uniform(1, 14));
    EQ twice;
    ASSERT_TRUE(u.twice_area(polygons, twice)) << "round " << round;
    const EQ expected = joined_area(polygons);
    ASSERT_EQ(twice / 2, expected) << "round " << round << ": " << polygons.size() << " polygons";
    ++compared;
  }
  EXPECT_EQ(compared, 600);
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

}  // namespace
