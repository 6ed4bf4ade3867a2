// SPDX-License-Identifier: GPL-3.0-or-later
// split_polygon_with_holes (core/polygon_holes.hpp): the pieces tile the polygon minus its holes
// exactly, checked two ways: exact rational areas (shoelace in CGAL's exact rationals) add up, and
// seeded sample points lie in exactly one piece when inside the polygon and in none outside.
#include "core/polygon_holes.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Polygon_2.h>
#include <glm/common.hpp>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <tuple>

namespace {

using shadow::core::PolygonHolesError;
using shadow::core::split_polygon_with_holes;
using Q = CGAL::Exact_rational;
using Ring = std::vector<glm::dvec3>;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

int dominant_axis(const Ring& ring) {
  glm::dvec3 n(0.0);
  for (std::size_t a = 0; a < ring.size(); ++a) {
    const glm::dvec3 u = ring[a] - ring[0], v = ring[(a + 1) % ring.size()] - ring[0];
    n += glm::dvec3(u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x);
  }
  n = glm::abs(n);
  return n.x >= n.y && n.x >= n.z ? 0 : (n.y >= n.z ? 1 : 2);
}

/// Twice the signed area of the ring in the chart that drops axis k, exactly.
Q chart_area2(const Ring& ring, int k) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  Q sum = 0;
  for (std::size_t a = 0; a < ring.size(); ++a) {
    const glm::dvec3& u = ring[a];
    const glm::dvec3& v = ring[(a + 1) % ring.size()];
    sum += Q(u[i]) * Q(v[j]) - Q(v[i]) * Q(u[j]);
  }
  return sum;
}

CGAL::Polygon_2<K> chart_polygon(const Ring& ring, int k) {
  CGAL::Polygon_2<K> p;
  for (const glm::dvec3& v : ring) p.push_back(K::Point_2(v[(k + 1) % 3], v[(k + 2) % 3]));
  return p;
}

/// Every check of the contract of split_polygon_with_holes on one input.
void check_split(const Ring& outer, const std::vector<Ring>& holes, int samples = 400) {
  const auto pieces = split_polygon_with_holes(outer, holes);
  ASSERT_FALSE(pieces.empty());
  const int k = dominant_axis(outer);
  const Q outer_area = chart_area2(outer, k);
  // Expected: |outer| - sum |hole|, signed like the outer ring.
  Q expected = outer_area > 0 ? outer_area : -outer_area;
  for (const Ring& h : holes) {
    const Q a = chart_area2(h, k);
    expected -= a > 0 ? a : -a;
  }
  std::set<std::tuple<double, double, double>> input;
  for (const glm::dvec3& v : outer) input.emplace(v.x, v.y, v.z);
  for (const Ring& h : holes)
    for (const glm::dvec3& v : h) input.emplace(v.x, v.y, v.z);
  Q total = 0;
  std::vector<CGAL::Polygon_2<K>> charts;
  for (const Ring& piece : pieces) {
    ASSERT_GE(piece.size(), 3u);
    for (const glm::dvec3& v : piece) EXPECT_TRUE(input.count({v.x, v.y, v.z})) << "a vertex not from the input";
    const Q a = chart_area2(piece, k);
    // Same way round as the outer ring, non-zero.
    EXPECT_TRUE((a > 0) == (outer_area > 0) && a != 0);
    total += a > 0 ? a : -a;
    charts.push_back(chart_polygon(piece, k));
    EXPECT_TRUE(charts.back().is_simple());
    EXPECT_TRUE(charts.back().is_convex());
  }
  EXPECT_EQ(total, expected) << "areas do not add up exactly";
  // Second way: sample points are in exactly one piece inside the domain, in none outside.
  const CGAL::Polygon_2<K> outer_chart = chart_polygon(outer, k);
  std::vector<CGAL::Polygon_2<K>> hole_charts;
  for (const Ring& h : holes) hole_charts.push_back(chart_polygon(h, k));
  const auto box = outer_chart.bbox();
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> ux(box.xmin(), box.xmax()), uy(box.ymin(), box.ymax());
  int inside_seen = 0;
  for (int s = 0; s < samples; ++s) {
    const K::Point_2 p(ux(rng), uy(rng));
    if (outer_chart.bounded_side(p) == CGAL::ON_BOUNDARY) continue;
    bool inside = outer_chart.bounded_side(p) == CGAL::ON_BOUNDED_SIDE, on_edge = false;
    for (const auto& h : hole_charts) {
      if (h.bounded_side(p) == CGAL::ON_BOUNDARY) on_edge = true;
      if (h.bounded_side(p) == CGAL::ON_BOUNDED_SIDE) inside = false;
    }
    int count = 0;
    for (const auto& c : charts) {
      if (c.bounded_side(p) == CGAL::ON_BOUNDARY) on_edge = true;
      if (c.bounded_side(p) == CGAL::ON_BOUNDED_SIDE) ++count;
    }
    if (on_edge) continue;
    EXPECT_EQ(count, inside ? 1 : 0);
    inside_seen += inside;
  }
  if (samples > 0) EXPECT_GT(inside_seen, 0);
}

Ring square(double x0, double y0, double x1, double y1, double z = 0) {
  return {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
}

TEST(PolygonHoles, ConvexWithoutHolesIsItself) {
  const Ring outer = square(0, 0, 4, 3);
  const auto pieces = split_polygon_with_holes(outer, {});
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(pieces[0], outer);
}

TEST(PolygonHoles, SquareWithSquareHole) { check_split(square(0, 0, 10, 10), {square(3, 3, 6, 7)}); }

TEST(PolygonHoles, HoleEitherWayRoundAndClockwiseOuter) {
  Ring outer = square(0, 0, 10, 10);
  std::reverse(outer.begin(), outer.end());
  Ring hole = square(2, 2, 4, 4);
  check_split(outer, {hole});
  std::reverse(hole.begin(), hole.end());
  check_split(outer, {hole});
}

TEST(PolygonHoles, NonConvexOuterTwoHolesTiltedPlane) {
  // An L in the plane z = x/2 + y/4 (dyadic, so every vertex lies exactly on it), two holes.
  auto lift = [](double x, double y) { return glm::dvec3(x, y, x / 2 + y / 4); };
  const Ring outer = {lift(0, 0), lift(8, 0), lift(8, 3), lift(3, 3), lift(3, 8), lift(0, 8)};
  const Ring triangle = {lift(1, 1), lift(2.5, 1), lift(1, 2.5)};
  const Ring quad = {lift(1, 5), lift(2, 5), lift(2, 7), lift(1, 6.5)};
  check_split(outer, {triangle, quad});
}

TEST(PolygonHoles, VerticalWallWithWindowAtCityCoordinates) {
  // A facade at projected coordinates (about 1e5 m east, 4e5 m north): a wall in the plane
  // y = 435440.44 with a window; millimetre coordinates, as CityJSON's transform gives them.
  const double x = 90409.321, y = 435440.44;
  const Ring wall = {{x, y, 0}, {x + 12.345, y, 0}, {x + 12.345, y, 7.5}, {x, y, 7.5}};
  const Ring window = {{x + 1.001, y, 1.2}, {x + 1.001, y, 2.4}, {x + 2.6, y, 2.4}, {x + 2.6, y, 1.2}};
  const Ring door = {{x + 5, y, 0.001}, {x + 6, y, 0.001}, {x + 6, y, 2.1}, {x + 5, y, 2.1}};
  check_split(wall, {window, door});
}

TEST(PolygonHoles, CollinearVerticesAndClosingDuplicate) {
  const Ring outer = {{0, 0, 0}, {2, 0, 0}, {4, 0, 0}, {4, 4, 0}, {2, 4, 0}, {0, 4, 0}, {0, 0, 0}};
  check_split(outer, {square(1, 1, 3, 3)});
}

// Random grids of rectangular holes (disjoint by construction) in a random convex or notched
// outer ring: exact areas and sampled coverage.
RC_GTEST_PROP(PolygonHoles, RandomGridsOfHolesTileExactly, ()) {
  const int nx = *rc::gen::inRange(1, 5), ny = *rc::gen::inRange(1, 5);
  const bool notch = *rc::gen::arbitrary<bool>();
  std::vector<Ring> holes;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      if (!*rc::gen::arbitrary<bool>()) continue;
      const double x0 = 1 + 4 * i + *rc::gen::inRange(0, 4) * 0.25, y0 = 1 + 4 * j + *rc::gen::inRange(0, 4) * 0.25;
      holes.push_back(square(x0, y0, x0 + 1 + *rc::gen::inRange(0, 8) * 0.125, y0 + 1.5));
    }
  const double w = 4.0 * nx + 1, h = 4.0 * ny + 1;
  Ring outer = notch ? Ring{{0, 0, 0}, {w, 0, 0}, {w, h, 0}, {w / 2 + 0.1, h, 0}, {w / 2 + 0.1, h + 0.5, 0},
                            {w / 2 - 0.1, h + 0.5, 0}, {w / 2 - 0.1, h, 0}, {0, h, 0}}
                     : square(0, 0, w, h);
  check_split(outer, holes, 100);
}

int error_ring(const Ring& outer, const std::vector<Ring>& holes, std::string* text = nullptr) {
  try {
    split_polygon_with_holes(outer, holes);
  } catch (const PolygonHolesError& e) {
    if (text) *text = e.what();
    return e.ring;
  }
  return -100;
}

TEST(PolygonHoles, Errors) {
  const Ring outer = square(0, 0, 10, 10);
  std::string text;
  EXPECT_EQ(error_ring(outer, {square(1, 1, 2, 2), square(11, 1, 12, 2)}, &text), 1);
  EXPECT_NE(text.find("hole 1 is outside the outer ring"), std::string::npos) << text;
  EXPECT_EQ(error_ring(outer, {square(0, 1, 2, 2)}, &text), 0);  // a vertex on the boundary
  EXPECT_NE(text.find("touches"), std::string::npos) << text;
  EXPECT_EQ(error_ring(outer, {square(8, 1, 12, 2)}, &text), 0);  // crosses
  EXPECT_EQ(error_ring(outer, {square(1, 1, 4, 4), square(3, 3, 5, 5)}, &text), 1);
  EXPECT_NE(text.find("overlap"), std::string::npos) << text;
  EXPECT_EQ(error_ring(outer, {square(1, 1, 6, 6), square(2, 2, 3, 3)}, &text), 1);  // nested
  EXPECT_EQ(error_ring(outer, {square(1, 1, 4, 4), square(4, 1, 5, 2)}, &text), 1);  // shared edge
  Ring tilted = square(1, 1, 2, 2);
  tilted[2].z = 0.5;
  EXPECT_EQ(error_ring(outer, {tilted}, &text), 0);
  EXPECT_NE(text.find("not in the plane"), std::string::npos) << text;
  Ring bowtie = {{1, 1, 0}, {3, 3, 0}, {3, 1, 0}, {1, 3, 0}};
  EXPECT_EQ(error_ring(outer, {bowtie}, &text), 0);
  EXPECT_NE(text.find("not simple"), std::string::npos) << text;
  EXPECT_EQ(error_ring({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {}, &text), -1);
  EXPECT_NE(text.find("zero area"), std::string::npos) << text;
  EXPECT_EQ(error_ring({{0, 0, 0}, {1, 0, 0}}, {}, &text), -1);
  const auto checked = shadow::core::split_polygon_with_holes_checked(outer, {square(20, 20, 21, 21)});
  EXPECT_TRUE(checked.pieces.empty());
  EXPECT_EQ(checked.ring, 0);
  EXPECT_FALSE(checked.error.empty());
}

}  // namespace
