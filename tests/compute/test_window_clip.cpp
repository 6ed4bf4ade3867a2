// SPDX-License-Identifier: GPL-3.0-or-later
// The fast path's exact clip of a convex grid polygon to a convex receiver outline
// (fast/window_clip.hpp, internal header): analytic cases (inside, around, apart, touching,
// crossings on and off grid points, halves), and seeded random convex polygons from a few units
// (collinear points, shared edges, many ties) up to the grid's full 2^30 range against the same
// clip made in GMP rationals: the output must be exactly the rational clip's vertices each
// rounded to the nearest grid point (repeats dropped), and convex_contains must agree with the
// rationals. Seeded; no timing.
#include "fast/cluster_union.hpp"
#include "fast/receiver_job.hpp"
#include "fast/window_clip.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_2.h>
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <numeric>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace {

namespace CL = ClipperLib;
using shadow::fast::clip_to_window;
using shadow::fast::convex_contains;
using shadow::fast::round_quotient;
using shadow::fast::set_window;
using shadow::fast::WindowClipScratch;

CL::Path clip(const CL::Path& poly, const CL::Path& window) {
  WindowClipScratch s;
  set_window(window, s);
  CL::Path out;
  clip_to_window(poly, s, out);
  return out;
}

/// Whether a and b are the same cyclic sequence of points.
bool same_cycle(const CL::Path& a, const CL::Path& b) {
  if (a.size() != b.size()) return false;
  if (a.empty()) return true;
  for (std::size_t r = 0; r < b.size(); ++r) {
    bool same = true;
    for (std::size_t k = 0; k < a.size() && same; ++k) same = a[k] == b[(k + r) % b.size()];
    if (same) return true;
  }
  return false;
}

std::string text(const CL::Path& p) {
  std::string s;
  for (const CL::IntPoint& q : p) s += "(" + std::to_string(q.X) + "," + std::to_string(q.Y) + ")";
  return s;
}

CL::Path rect(CL::cInt x0, CL::cInt y0, CL::cInt x1, CL::cInt y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

TEST(WindowClip, RoundsHalvesUp) {
  EXPECT_EQ(round_quotient(1, 2), 1);
  EXPECT_EQ(round_quotient(-1, 2), 0);
  EXPECT_EQ(round_quotient(3, 2), 2);
  EXPECT_EQ(round_quotient(-3, 2), -1);
  EXPECT_EQ(round_quotient(5, 3), 2);
  EXPECT_EQ(round_quotient(-5, 3), -2);
  EXPECT_EQ(round_quotient(4, 3), 1);
  EXPECT_EQ(round_quotient(-4, 3), -1);
  EXPECT_EQ(round_quotient(0, 7), 0);
  EXPECT_EQ(round_quotient(-7, 7), -1);
}

// The fast grid's rounding (receiver_job::Grid::round_half_up) is std::llround on its range,
// without the library call: the halves, the doubles next to them, the range's ends, random values.
TEST(FastGrid, RoundHalfUpIsLlround) {
  using shadow::fast::receiver_job::Grid;
  std::vector<double> values{0.0, 0.5, 1.0, 1.5, 2.5, 2147483647.5, 2147483648.0, 1073741823.5, 4503599627370496.0};
  for (double v : std::vector<double>(values)) {
    values.push_back(std::nextafter(v, 0.0));
    values.push_back(std::nextafter(v, 1e300));
  }
  std::mt19937_64 rng(27);
  std::uniform_real_distribution<double> any(0.0, 2147483648.0), small(0.0, 4.0);
  for (int k = 0; k < 100000; ++k) values.push_back(k % 2 ? any(rng) : small(rng));
  for (double v : values) ASSERT_EQ(Grid::round_half_up(v), std::llround(v)) << v;
}

TEST(WindowClip, AnalyticCases) {
  const CL::Path tri{{0, 0}, {10, 0}, {0, 10}};
  // Inside the window: unchanged.
  EXPECT_TRUE(same_cycle(clip(rect(1, 1, 3, 3), tri), rect(1, 1, 3, 3)));
  // Around the window: the window.
  EXPECT_TRUE(same_cycle(clip(rect(-5, -5, 20, 20), tri), tri));
  // A square cut to the triangle that is its lower left half: the triangle.
  EXPECT_TRUE(same_cycle(clip(rect(0, 0, 10, 10), tri), tri)) << text(clip(rect(0, 0, 10, 10), tri));
  // Apart, touching along an edge, touching at a vertex: nothing.
  EXPECT_TRUE(clip(rect(20, 20, 30, 30), tri).empty());
  EXPECT_TRUE(clip(rect(-5, 0, 0, 10), tri).empty());
  EXPECT_TRUE(clip(rect(-5, -5, 0, 0), tri).empty());
  EXPECT_TRUE(clip({{5, 5}, {10, 5}, {10, 10}, {5, 10}}, tri).empty());  // touches the diagonal at (5, 5)
  // Crossings on grid points: a pentagon of area 87.5.
  const CL::Path big{{0, 0}, {15, 0}, {0, 15}};
  const CL::Path pentagon = clip(rect(0, 0, 10, 10), big);
  EXPECT_TRUE(same_cycle(pentagon, {{0, 0}, {10, 0}, {10, 5}, {5, 10}, {0, 10}})) << text(pentagon);
  EXPECT_EQ(shadow::fast::twice_area(pentagon), 175);
  // A crossing off the grid: 2x + 5y = 10 meets x = 2 at y = 1.2, rounded to 1.
  const CL::Path flat{{0, 0}, {5, 0}, {0, 2}};
  EXPECT_TRUE(same_cycle(clip(rect(0, 0, 2, 2), flat), {{0, 0}, {2, 0}, {2, 1}, {0, 2}})) << text(clip(rect(0, 0, 2, 2), flat));
  // A sliver whose crossings all round onto one line: nothing of positive area is left.
  const CL::Path thin{{0, 0}, {100, 1}, {0, 1}};
  // (50, 0.5) and (51, 0.51) round up to y = 1: the clip's 0.495 of a cell collapses.
  const CL::Path cut = clip(rect(50, 0, 51, 1), thin);
  EXPECT_TRUE(cut.empty()) << text(cut);
  // Collinear vertices on the polygon and on the window (straight-on points are convex).
  const CL::Path square_with_mids{{0, 0}, {5, 0}, {10, 0}, {10, 5}, {10, 10}, {0, 10}};
  const CL::Path tri_with_mid{{0, 0}, {5, 5}, {10, 10}, {0, 10}};
  EXPECT_TRUE(same_cycle(clip(square_with_mids, tri_with_mid), {{0, 0}, {10, 10}, {0, 10}}))
      << text(clip(square_with_mids, tri_with_mid));
  EXPECT_TRUE(same_cycle(clip(square_with_mids, rect(-1, -1, 11, 11)), square_with_mids));  // kept as they are
  EXPECT_TRUE(same_cycle(clip(rect(-1, -1, 11, 11), square_with_mids), rect(0, 0, 10, 10)));  // the window's corners
  // Containment.
  EXPECT_TRUE(convex_contains(rect(-5, -5, 20, 20), tri));
  EXPECT_TRUE(convex_contains(tri, tri));
  EXPECT_TRUE(convex_contains(rect(0, 0, 10, 10), tri));
  EXPECT_FALSE(convex_contains(tri, rect(0, 0, 10, 10)));
  EXPECT_FALSE(convex_contains(rect(0, 0, 9, 10), tri));
}

// ---- the same clip in GMP rationals -----------------------------------------------------------

struct QPoint {
  mpq_class x, y;
};

/// a x + b y + c of the line through p -> q (positive on the left) at r.
mpq_class side(const QPoint& p, const QPoint& q, const QPoint& r) {
  return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
}

/// Sutherland-Hodgman on rational points: keep what is left of or on each window edge.
std::vector<QPoint> rational_clip(const CL::Path& poly, const CL::Path& window) {
  std::vector<QPoint> pts;
  for (const CL::IntPoint& p : poly) pts.push_back({mpq_class(static_cast<long>(p.X)), mpq_class(static_cast<long>(p.Y))});
  for (std::size_t e = 0; e < window.size() && pts.size() >= 3; ++e) {
    const QPoint a{mpq_class(static_cast<long>(window[e].X)), mpq_class(static_cast<long>(window[e].Y))};
    const CL::IntPoint& wb = window[(e + 1) % window.size()];
    const QPoint b{mpq_class(static_cast<long>(wb.X)), mpq_class(static_cast<long>(wb.Y))};
    std::vector<QPoint> next;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const QPoint& p = pts[k];
      const QPoint& q = pts[(k + 1) % pts.size()];
      const mpq_class sp = side(a, b, p), sq = side(a, b, q);
      if (sgn(sp) >= 0) next.push_back(p);
      if ((sgn(sp) > 0 && sgn(sq) < 0) || (sgn(sp) < 0 && sgn(sq) > 0)) {
        const mpq_class t = sp / (sp - sq);
        next.push_back({p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)});
      }
    }
    pts.swap(next);
  }
  return pts;
}

mpq_class twice_area(const std::vector<QPoint>& p) {
  mpq_class sum = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const QPoint& q = p[(k + 1) % p.size()];
    sum += p[k].x * q.y - q.x * p[k].y;
  }
  return sum;
}

/// Nearest integer, halves up.
long nearest(const mpq_class& v) {
  mpz_class twice = v.get_num() * 2 + v.get_den();
  mpz_class den = v.get_den() * 2;
  mpz_class q;
  mpz_fdiv_q(q.get_mpz_t(), twice.get_mpz_t(), den.get_mpz_t());
  return q.get_si();
}

/// The convex hull of grid points, counter-clockwise without collinear points (CGAL's, whose
/// predicates are exact on these doubles: every coordinate is below 2^30); empty when flat.
/// `p` with a lattice point put in on one of its edges where one exists (a straight-on vertex,
/// which the engine's casts and outlines may have).
CL::Path with_collinear_vertex(CL::Path p, std::size_t edge) {
  for (std::size_t k = 0; k < p.size(); ++k) {
    const std::size_t e = (edge + k) % p.size();
    const CL::IntPoint a = p[e], b = p[(e + 1) % p.size()];
    const long long g = std::gcd(std::llabs(b.X - a.X), std::llabs(b.Y - a.Y));
    if (g < 2) continue;
    p.insert(p.begin() + static_cast<std::ptrdiff_t>(e + 1), CL::IntPoint{a.X + (b.X - a.X) / g, a.Y + (b.Y - a.Y) / g});
    return p;
  }
  return p;
}

CL::Path convex_hull(const std::vector<CL::IntPoint>& pts) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<K::Point_2> in, hull;
  for (const CL::IntPoint& p : pts) in.emplace_back(static_cast<double>(p.X), static_cast<double>(p.Y));
  CGAL::convex_hull_2(in.begin(), in.end(), std::back_inserter(hull));
  CL::Path out;
  for (const K::Point_2& p : hull) out.push_back({static_cast<CL::cInt>(p.x()), static_cast<CL::cInt>(p.y())});
  return out.size() >= 3 ? out : CL::Path{};
}

TEST(WindowClip, SeededPolygonsAgainstRationalClip) {
  std::mt19937_64 rng(20261130);
  const long long ranges[] = {6, 40, 1000, (1LL << 20), (1LL << 30) - 2};
  int compared = 0, empty = 0, rounded = 0, contained = 0;
  for (long long range : ranges) {
    std::uniform_int_distribution<long long> coord(-range, range);
    std::uniform_int_distribution<int> count(3, 9);
    for (int trial = 0; trial < 1500; ++trial) {
      auto polygon = [&] {
        CL::Path hull;
        while (hull.empty()) {
          std::vector<CL::IntPoint> pts(static_cast<std::size_t>(count(rng)));
          for (CL::IntPoint& p : pts) p = {coord(rng), coord(rng)};
          hull = convex_hull(pts);
        }
        return hull;
      };
      CL::Path poly = polygon(), window = polygon();
      // Now and then the window shares an edge with the polygon (either way round), or is it.
      if (trial % 7 == 1) {
        const CL::Path shared = convex_hull({poly[0], poly[1], {coord(rng), coord(rng)}});
        if (!shared.empty()) window = shared;
      }
      if (trial % 7 == 2) window = poly;
      if (trial % 5 == 3) poly = with_collinear_vertex(poly, static_cast<std::size_t>(trial));
      if (trial % 5 == 4) window = with_collinear_vertex(window, static_cast<std::size_t>(trial));
      const std::string label = "range " + std::to_string(range) + " trial " + std::to_string(trial) + ": " + text(poly) + " in " + text(window);
      const CL::Path got = clip(poly, window);
      const std::vector<QPoint> exact = rational_clip(poly, window);
      const bool positive = exact.size() >= 3 && sgn(twice_area(exact)) > 0;
      CL::Path expected;
      if (positive) {
        for (const QPoint& q : exact) {
          const CL::IntPoint p{nearest(q.x), nearest(q.y)};
          if (expected.empty() || !(expected.back() == p)) expected.push_back(p);
        }
        while (expected.size() > 1 && expected.front() == expected.back()) expected.pop_back();
        if (expected.size() < 3) expected.clear();
      }
      EXPECT_TRUE(same_cycle(got, expected)) << label << "\n got " << text(got) << "\n expected " << text(expected);
      ++compared;
      empty += expected.empty() ? 1 : 0;
      for (const QPoint& q : exact) rounded += q.x.get_den() != 1 || q.y.get_den() != 1 ? 1 : 0;
      // convex_contains against the rationals: every window vertex left of or on every polygon edge.
      bool inside = true;
      for (std::size_t e = 0; e < poly.size() && inside; ++e) {
        const QPoint a{mpq_class(static_cast<long>(poly[e].X)), mpq_class(static_cast<long>(poly[e].Y))};
        const CL::IntPoint& pb = poly[(e + 1) % poly.size()];
        const QPoint b{mpq_class(static_cast<long>(pb.X)), mpq_class(static_cast<long>(pb.Y))};
        for (const CL::IntPoint& w : window)
          inside = inside && sgn(side(a, b, {mpq_class(static_cast<long>(w.X)), mpq_class(static_cast<long>(w.Y))})) >= 0;
      }
      EXPECT_EQ(convex_contains(poly, window), inside) << label;
      contained += inside ? 1 : 0;
    }
  }
  std::printf("%d clips, %d empty, %d rational vertices rounded, %d windows contained\n", compared, empty, rounded, contained);
  EXPECT_GT(rounded, 1000);  // the rounding was exercised
  EXPECT_GT(empty, 100);     // so were empty results
}

}  // namespace
