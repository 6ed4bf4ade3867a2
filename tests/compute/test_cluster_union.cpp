// SPDX-License-Identifier: GPL-3.0-or-later
// The fast path's union area cluster by cluster (fast/cluster_union.hpp, internal header): the
// boundary measure of convex clusters against analytic areas (shared edges both ways, identical
// and nested polygons, collinear overlaps) and against Clipper's union of the same polygons
// scaled up 2^20 times (its rounding then negligible), each within the bound the function
// returns; clusters, singletons and the Clipper fallback for polygons that are not convex; and,
// inside the engine, areas-only fast results within their bounds of the exact engine. Seeded.
#include "fast/cluster_union.hpp"

#include <shadow/shadow.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>

namespace {

namespace CL = ClipperLib;
using shadow::fast::ClusteredArea;
using shadow::fast::ClusterUnionCounts;

double area_of(const ClusteredArea& a) { return 0.5 * (static_cast<double>(a.exact2) + a.boundary.twice_area); }
double error_of(const ClusteredArea& a) { return 0.5 * a.boundary.error; }

CL::Path rect(CL::cInt x0, CL::cInt y0, CL::cInt x1, CL::cInt y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

double perimeter(const CL::Paths& paths) {
  double length = 0;
  for (const CL::Path& p : paths)
    for (std::size_t v = 0; v < p.size(); ++v) {
      const CL::IntPoint& q = p[(v + 1) % p.size()];
      length += std::hypot(static_cast<double>(q.X - p[v].X), static_cast<double>(q.Y - p[v].Y));
    }
  return length;
}

TEST(ClusterUnion, AnalyticCasesWithSharedAndCollinearEdges) {
  struct Case {
    std::string name;
    CL::Paths polygons;
    double area;
  };
  const std::vector<Case> cases = {
      {"two overlapping squares", {rect(0, 0, 10, 10), rect(5, 5, 15, 15)}, 175},
      {"identical squares", {rect(0, 0, 10, 10), rect(0, 0, 10, 10), rect(0, 0, 10, 10)}, 100},
      {"nested", {rect(0, 0, 10, 10), rect(2, 2, 4, 4)}, 100},
      {"shared edge, opposite ways", {rect(0, 0, 10, 10), rect(10, 0, 20, 10)}, 200},
      {"collinear bottoms, same way", {rect(0, 0, 10, 10), rect(5, 0, 15, 4)}, 120},
      {"both sides of one line", {rect(0, 0, 10, 10), rect(5, 0, 15, 4), rect(2, -6, 8, 0)}, 156},
      {"a cross", {rect(0, 4, 12, 8), rect(4, 0, 8, 12)}, 80},
      {"triangles around a point",
       {{{0, 0}, {10, 0}, {0, 10}}, {{0, 0}, {0, 10}, {-10, 0}}, {{0, 0}, {-10, 0}, {0, -10}}},
       150},
      {"overlapping triangles, thirds", {{{0, 0}, {3, 0}, {0, 3}}, {{1, 1}, {4, 1}, {1, 4}}}, 4.5 + 4.5 - 0.5},
  };
  for (const Case& c : cases) {
    ClusterUnionCounts counts;
    const ClusteredArea a = shadow::fast::clustered_union_area(c.polygons, 0, 1, &counts);
    EXPECT_NEAR(area_of(a), c.area, error_of(a) + 1e-12) << c.name;
    EXPECT_LT(error_of(a), 1e-9) << c.name;
    EXPECT_FALSE(a.clipper) << c.name;
    EXPECT_EQ(counts.unions, 0u) << c.name;
  }
  // Disjoint: two singletons, no boundary measure, exact.
  ClusterUnionCounts counts;
  const ClusteredArea apart = shadow::fast::clustered_union_area({rect(0, 0, 2, 2), rect(5, 5, 6, 7)}, 0, 1, &counts);
  EXPECT_EQ(counts.singletons, 2u);
  EXPECT_EQ(counts.boundaries, 0u);
  EXPECT_EQ(area_of(apart), 6.0);
  EXPECT_EQ(apart.boundary.error, 0.0);
}

TEST(ClusterUnion, PolygonsThatAreNotConvexGoThroughClipper) {
  const CL::Path pentagram = {{0, 100}, {59, -81}, {-95, 31}, {95, 31}, {-59, -81}};
  EXPECT_FALSE(shadow::fast::is_convex_ccw(pentagram));
  const CL::Path l_shape = {{0, 0}, {20, 0}, {20, 10}, {10, 10}, {10, 20}, {0, 20}};
  EXPECT_FALSE(shadow::fast::is_convex_ccw(l_shape));
  EXPECT_TRUE(shadow::fast::is_convex_ccw(rect(0, 0, 3, 4)));
  EXPECT_FALSE(shadow::fast::is_convex_ccw({{0, 0}, {0, 4}, {3, 4}, {3, 0}}));  // clockwise
  ClusterUnionCounts counts;
  const ClusteredArea a = shadow::fast::clustered_union_area({l_shape, rect(5, 5, 15, 15), rect(100, 100, 101, 101)}, 0, 1, &counts);
  EXPECT_TRUE(a.clipper);
  EXPECT_EQ(counts.unions, 1u);
  EXPECT_EQ(counts.singletons, 1u);
  EXPECT_EQ(area_of(a), 300.0 + 100.0 - 75.0 + 1.0);  // the L and the square share 50 + 25
}

/// Random convex polygons (hulls of random points, some long and thin along a direction) on a
/// small grid, many sharing coordinates, so that ties and collinear edges are common.
CL::Paths random_convex(std::mt19937& rng, std::size_t count, CL::cInt range) {
  std::uniform_int_distribution<CL::cInt> where(-range, range), size(1, range / 3);
  std::uniform_int_distribution<int> points(3, 8);
  CL::Paths out;
  while (out.size() < count) {
    const CL::cInt cx = where(rng), cy = where(rng), w = size(rng), h = size(rng);
    std::uniform_int_distribution<CL::cInt> dx(-w, w), dy(-h, h);
    std::vector<CL::IntPoint> p;
    const int k = points(rng);
    for (int a = 0; a < k; ++a) p.push_back({cx + dx(rng), cy + dy(rng)});
    // Monotone-chain hull, counter-clockwise, no collinear points.
    std::sort(p.begin(), p.end(), [](const CL::IntPoint& a, const CL::IntPoint& b) {
      return a.X < b.X || (a.X == b.X && a.Y < b.Y);
    });
    p.erase(std::unique(p.begin(), p.end()), p.end());
    if (p.size() < 3) continue;
    auto cross = [](const CL::IntPoint& o, const CL::IntPoint& a, const CL::IntPoint& b) {
      return (a.X - o.X) * (b.Y - o.Y) - (a.Y - o.Y) * (b.X - o.X);
    };
    CL::Path hull(2 * p.size());
    std::size_t n = 0;
    for (std::size_t a = 0; a < p.size(); ++a) {
      while (n >= 2 && cross(hull[n - 2], hull[n - 1], p[a]) <= 0) --n;
      hull[n++] = p[a];
    }
    for (std::size_t a = p.size() - 1, t = n + 1; a-- > 0;) {
      while (n >= t && cross(hull[n - 2], hull[n - 1], p[a]) <= 0) --n;
      hull[n++] = p[a];
    }
    hull.resize(n - 1);
    if (hull.size() >= 3) out.push_back(hull);
  }
  return out;
}

TEST(ClusterUnion, RandomConvexClustersAgreeWithAFineClipperUnion) {
  std::mt19937 rng(20261126);
  std::size_t boundaries = 0;
  for (int round = 0; round < 300; ++round) {
    const std::size_t count = 2 + static_cast<std::size_t>(round % 25);
    const CL::Paths polygons = random_convex(rng, count, round % 2 ? 40 : 400);
    ClusterUnionCounts counts;
    const ClusteredArea a = shadow::fast::clustered_union_area(polygons, 1, static_cast<double>(round % 7), &counts);
    boundaries += counts.boundaries;
    EXPECT_FALSE(a.clipper);
    // Clipper on the same polygons scaled by 2^20: every point it rounds moves by under
    // sqrt(2)/2 scaled units, so its area is within 2 x that x the perimeter (+ pi r^2) of the
    // exact union's, 2^-20 of a unit here.
    constexpr double kScale = 1 << 20;
    CL::Paths scaled = polygons;
    const double length = perimeter(polygons);
    for (CL::Path& p : scaled)
      for (CL::IntPoint& q : p) q = {q.X << 20, q.Y << 20};
    CL::Clipper clipper;
    clipper.AddPaths(scaled, CL::ptSubject, true);
    CL::Paths united;
    clipper.Execute(CL::ctUnion, united, CL::pftNonZero, CL::pftNonZero);
    double fine = 0;
    for (const CL::Path& p : united) fine += static_cast<double>(shadow::fast::twice_area(p));
    fine = 0.5 * fine / (kScale * kScale);
    const double clipper_error = (2 * 0.71 * length * kScale + 4) / (kScale * kScale);
    EXPECT_NEAR(area_of(a), fine, error_of(a) + clipper_error + 1e-9 * fine) << "round " << round;
    EXPECT_LT(error_of(a), 1e-9 * (1 + fine)) << "round " << round;
  }
  EXPECT_GT(boundaries, 200u);  // the boundary measure was reached
}

// The fast path's workers keep one ClusterScratch for every union they measure (no allocation,
// no thread-local look-up per receiver): a scratch reused across clusters of every size, large
// after small and small after large, gives the same bits as a fresh one each time.
TEST(ClusterUnion, AReusedScratchGivesTheSameBitsAsAFreshOne) {
  std::mt19937 rng(20261129);
  shadow::fast::ClusterScratch reused;
  std::size_t boundaries = 0;
  for (int round = 0; round < 200; ++round) {
    const std::size_t count = 1 + static_cast<std::size_t>((round * 7) % 30);
    const CL::Paths polygons = random_convex(rng, count, round % 3 ? 40 : 400);
    ClusterUnionCounts counts;
    const ClusteredArea fresh = shadow::fast::clustered_union_area(polygons, 1, 0.25, &counts);
    const ClusteredArea again = shadow::fast::clustered_union_area(polygons, 1, 0.25, nullptr, &reused);
    boundaries += counts.boundaries;
    EXPECT_TRUE(fresh.exact2 == again.exact2) << "round " << round;
    EXPECT_EQ(std::memcmp(&fresh.boundary.twice_area, &again.boundary.twice_area, sizeof(double)), 0) << "round " << round;
    EXPECT_EQ(std::memcmp(&fresh.boundary.error, &again.boundary.error, sizeof(double)), 0) << "round " << round;
  }
  EXPECT_GT(boundaries, 100u);
}

// Near the grid's limits (coordinates up to 2^30, as on a receiver's grid): the interval ends are
// rounded there, and the bound the measure returns must cover it. Against Clipper's union of the
// same polygons, whose own rounding moves its boundary by under one grid step.
TEST(ClusterUnion, LargeCoordinatesStayWithinTheReturnedBound) {
  std::mt19937 rng(20261127);
  std::size_t boundaries = 0;
  for (int round = 0; round < 200; ++round) {
    CL::Paths polygons = random_convex(rng, 2 + static_cast<std::size_t>(round % 12), 64);
    const CL::cInt scale = CL::cInt(1) << (20 + round % 4), shift = (round % 3 - 1) * (CL::cInt(1) << 28);
    for (CL::Path& p : polygons)
      for (CL::IntPoint& q : p) q = {q.X * scale + shift + 7 * round, q.Y * scale - shift + 3};
    ClusterUnionCounts counts;
    const ClusteredArea a = shadow::fast::clustered_union_area(polygons, 1, 0.5, &counts);
    boundaries += counts.boundaries;
    CL::Clipper clipper;
    clipper.AddPaths(polygons, CL::ptSubject, true);
    CL::Paths united;
    clipper.Execute(CL::ctUnion, united, CL::pftNonZero, CL::pftNonZero);
    double clipped = 0;
    for (const CL::Path& p : united) clipped += static_cast<double>(shadow::fast::twice_area(p));
    clipped *= 0.5;
    const double clipper_error = 2 * 1.42 * perimeter(polygons) + 3.15 * 1.42 * 1.42;
    EXPECT_NEAR(area_of(a), clipped, error_of(a) + clipper_error + 1e-15 * clipped) << "round " << round;
    EXPECT_LT(error_of(a), 1e-12 * clipped + 1e6) << "round " << round;
  }
  EXPECT_GT(boundaries, 100u);
}

// Inside the engine, areas only: the fast areas of a city under suns of the year (most
// receivers' casts go through the boundary measure) stay within their bounds of the exact ones.
TEST(ClusterUnion, EngineFastAreasOnlyWithinBounds) {
  using namespace shadow;
  Scene scene = make_city(100, 120, 7);
  for (double elevation : {8.0, 25.0, 50.0, 75.0})
    scene.lights.push_back(directional_light("sun", sun_direction(elevation, 40 + 2 * elevation)));
  validate_scene(scene);
  ShadowOptions options;
  options.threads = 2;
  options.polygons = false;
  options.planes = false;
  const ShadowResult exact = compute_shadows(scene, options);
  options.arithmetic = Arithmetic::Fast;
  const ShadowResult fast = compute_shadows(scene, options);
  ASSERT_EQ(fast.lighting.size(), exact.lighting.size());
  std::size_t shadowed = 0;
  for (std::size_t n = 0; n < fast.lighting.size(); ++n) {
    const FaceLighting& e = exact.lighting[n];
    const FaceLighting& f = fast.lighting[n];
    EXPECT_LE(std::abs(f.lit_area - e.lit_area), f.lit_area_error_bound) << "face " << f.face_id << " light " << f.light_id;
    EXPECT_LE(f.lit_area_error_bound, 1e-4 * (1 + e.area)) << "face " << f.face_id;
    shadowed += e.shadow_area > 0 && e.lit_area > 0 ? 1 : 0;
  }
  EXPECT_GT(shadowed, 100u);
}

}  // namespace
