// SPDX-License-Identifier: GPL-3.0-or-later
// The fast path's union area cluster by cluster (fast/cluster_union.hpp, internal header): the
// boundary measure of convex clusters against analytic areas (shared edges both ways, identical
// and nested polygons, collinear overlaps) and against Clipper's union of the same polygons
// scaled up 2^20 times (its rounding then negligible), each within the bound the function
// returns; clusters, singletons and the Clipper fallback for polygons that are not convex; and,
// inside the engine, areas-only fast results within their bounds of the exact engine. Seeded.
#include "fast/box_clip.hpp"
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

/// Clipper's union of `polygons` scaled by 2^shift, its area in the polygons' units.
double clipper_union_area(const CL::Paths& polygons, int shift) {
  CL::Paths scaled = polygons;
  for (CL::Path& p : scaled)
    for (CL::IntPoint& q : p) q = {q.X << shift, q.Y << shift};
  CL::Clipper clipper;
  clipper.AddPaths(scaled, CL::ptSubject, true);
  CL::Paths united;
  clipper.Execute(CL::ctUnion, united, CL::pftNonZero, CL::pftNonZero);
  double twice = 0;
  for (const CL::Path& p : united) twice += static_cast<double>(shadow::fast::twice_area(p));
  return 0.5 * std::ldexp(twice, -2 * shift);
}

/// The reference for a union's area: Clipper's at 2^20 times the scale, whose every rounded point
/// moves by under sqrt(2)/2 scaled units, so its area is within `error` (2 x that x the perimeter,
/// + pi r^2) of the exact union's, 2^-20 of a unit.
double fine_union_area(const CL::Paths& polygons, double& error) {
  constexpr double kScale = 1 << 20;
  error = (2 * 0.71 * perimeter(polygons) * kScale + 4) / (kScale * kScale);
  return clipper_union_area(polygons, 20);
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

// An edge that lies wholly in another polygon, decided in integers alone, has no uncovered part
// and no rounding: it adds nothing to the area or to the bound, however many polygons cover it.
// (Its other intervals are not computed: most edges of a crowded cluster are such.) A polygon
// wholly inside a convex one is left out before the measure, its edges and pairs with it.
TEST(ClusterUnion, EdgesInsideAnotherPolygonAddNothingToTheBound) {
  const CL::Path outer = rect(0, 0, 10, 10);
  const CL::Path across = rect(8, 2, 14, 4);  // its left side lies inside `outer`
  ClusterUnionCounts one_counts, three_counts;
  const ClusteredArea one = shadow::fast::clustered_union_area({outer, across}, 0, 1, &one_counts);
  const ClusteredArea three = shadow::fast::clustered_union_area(
      {outer, rect(2, 2, 4, 4), across, rect(5, 5, 9, 8), rect(3, 3, 8, 7)}, 0, 1, &three_counts);
  EXPECT_EQ(area_of(one), 108.0);
  EXPECT_EQ(area_of(three), 108.0);
  EXPECT_GT(one.boundary.error, 0.0);  // the sides that cross, measured
  EXPECT_EQ(three.boundary.error, one.boundary.error);
  EXPECT_EQ(one_counts.inside, 0u);
  EXPECT_EQ(three_counts.inside, 3u);
  // The measure itself, given polygons inside the outer square (the clusters leave them out
  // first): their edges lie wholly inside it, so they add no term and nothing to the bound, and
  // they cut none of its edges.
  const CL::Paths nested = {outer, rect(2, 2, 4, 4), rect(5, 5, 9, 8), rect(3, 3, 8, 7)};
  const shadow::fast::AcrossAxis axis = shadow::fast::across_axis(0, 1);
  std::vector<shadow::fast::GridBox> boxes;
  std::vector<std::pair<double, double>> extents;
  for (const CL::Path& p : nested) {
    boxes.push_back(shadow::fast::grid_box(p));
    extents.push_back(shadow::fast::across_extent(p, axis));
  }
  shadow::fast::ClusterScratch scratch;
  const shadow::fast::BoundaryArea alone =
      shadow::fast::boundary_union_area2(nested, boxes, extents, {0}, axis, scratch);
  const shadow::fast::BoundaryArea all =
      shadow::fast::boundary_union_area2(nested, boxes, extents, {0, 1, 2, 3}, axis, scratch);
  EXPECT_EQ(alone.twice_area, 200.0);
  EXPECT_EQ(all.twice_area, 200.0);
  EXPECT_GT(alone.error, 0.0);
  EXPECT_EQ(all.error, alone.error);
  // Along the outer square's sides, the same way, after it: inside by the rule for shared lines.
  const ClusteredArea along = shadow::fast::clustered_union_area({outer, rect(0, 0, 10, 3), rect(4, 0, 6, 9)}, 0, 1);
  EXPECT_EQ(area_of(along), 100.0);
  EXPECT_LT(error_of(along), 1e-9);
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
    double clipper_error = 0;
    const double fine = fine_union_area(polygons, clipper_error);
    EXPECT_NEAR(area_of(a), fine, error_of(a) + clipper_error + 1e-9 * fine) << "round " << round;
    EXPECT_LT(error_of(a), 1e-9 * (1 + fine)) << "round " << round;
  }
  EXPECT_GT(boundaries, 200u);  // the boundary measure was reached
}

// Polygons inside others (the casts of low solids inside a tall one's shadow on a wall), equal
// ones, and ones inside a polygon that is itself inside another, among random convex polygons:
// those left out are exactly the ones inside another (of equal ones, all but the first; counted
// here by a test of every vertex against every edge), the area is within its bound of Clipper's
// union, and a cluster left with one polygon is its exact area.
TEST(ClusterUnion, PolygonsInsideOthersAreLeftOut) {
  std::mt19937 rng(20261206);
  auto within = [](const CL::Path& outer, const CL::Path& inner) {
    for (std::size_t f = 0; f < outer.size(); ++f) {
      const CL::IntPoint &a = outer[f], &b = outer[(f + 1) % outer.size()];
      for (const CL::IntPoint& v : inner)
        if (static_cast<double>(b.X - a.X) * static_cast<double>(v.Y - a.Y) -
                static_cast<double>(b.Y - a.Y) * static_cast<double>(v.X - a.X) < 0)
          return false;
    }
    return true;
  };
  std::size_t left_out = 0, nested = 0;
  for (int round = 0; round < 300; ++round) {
    CL::Paths polygons = random_convex(rng, 2 + static_cast<std::size_t>(round % 9), round % 2 ? 40 : 400);
    const std::size_t given = polygons.size();
    for (std::size_t k = 0; k < given; ++k) {
      const int kind = std::uniform_int_distribution<int>(0, 3)(rng);
      const CL::IntPoint o = polygons[k][0];
      if (kind == 1) polygons.push_back(polygons[k]);  // a copy
      if (kind >= 2) {
        // The polygon scaled by 4 about 0, with its half and its quarter towards its first vertex
        // (4o + (4q - 4o) / 2 and 4o + (4q - 4o) / 4: on the grid), each inside the one before.
        CL::Path half = polygons[k], quarter = polygons[k];
        for (CL::IntPoint& q : polygons[k]) q = {4 * q.X, 4 * q.Y};
        for (CL::IntPoint& q : half) q = {2 * o.X + 2 * q.X, 2 * o.Y + 2 * q.Y};
        for (CL::IntPoint& q : quarter) q = {3 * o.X + q.X, 3 * o.Y + q.Y};
        polygons.push_back(half);
        if (kind == 3) polygons.push_back(quarter);
        nested += kind - 1;
      }
    }
    std::shuffle(polygons.begin(), polygons.end(), rng);
    std::size_t expected = 0;
    for (std::size_t p = 0; p < polygons.size(); ++p)
      for (std::size_t q = 0; q < polygons.size(); ++q)
        if (q != p && within(polygons[q], polygons[p]) && (!within(polygons[p], polygons[q]) || q < p)) {
          ++expected;
          break;
        }
    ClusterUnionCounts counts;
    const ClusteredArea a = shadow::fast::clustered_union_area(polygons, 1, 0.5, &counts);
    EXPECT_EQ(counts.inside, expected) << "round " << round;
    left_out += counts.inside;
    double clipper_error = 0;
    const double fine = fine_union_area(polygons, clipper_error);
    EXPECT_NEAR(area_of(a), fine, error_of(a) + clipper_error + 1e-9 * fine) << "round " << round;
    EXPECT_FALSE(a.clipper);
  }
  EXPECT_GT(nested, 200u);
  EXPECT_GE(left_out, nested);
  // Only a convex polygon contains: an L (not convex) inside a square is left out, a rectangle
  // inside the L stays (the L is no container) and their cluster goes through Clipper.
  const CL::Path l_shape = {{0, 0}, {20, 0}, {20, 10}, {10, 10}, {10, 20}, {0, 20}};
  ClusterUnionCounts in_square, in_hull;
  const ClusteredArea l_in = shadow::fast::clustered_union_area({rect(-1, -1, 21, 21), l_shape}, 0, 1, &in_square);
  EXPECT_EQ(in_square.inside, 1u);
  EXPECT_FALSE(l_in.clipper);
  EXPECT_EQ(area_of(l_in), 22.0 * 22.0);
  const ClusteredArea hull_in = shadow::fast::clustered_union_area({l_shape, rect(1, 1, 19, 9)}, 0, 1, &in_hull);
  EXPECT_EQ(in_hull.inside, 0u);
  EXPECT_TRUE(hull_in.clipper);
  EXPECT_EQ(area_of(hull_in), 300.0);
  // A polygon with a copy and one inside it: one convex polygon left, its exact shoelace area.
  ClusterUnionCounts counts;
  const ClusteredArea one =
      shadow::fast::clustered_union_area({rect(0, 0, 10, 10), rect(1, 1, 3, 3), rect(0, 0, 10, 10)}, 0, 1, &counts);
  EXPECT_EQ(counts.inside, 2u);
  EXPECT_EQ(counts.singletons, 1u);
  EXPECT_EQ(counts.boundaries, 0u);
  EXPECT_EQ(area_of(one), 100.0);
  EXPECT_EQ(error_of(one), 0.0);
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

// Triangulated patches (the casts of a triangulated terrain's faces) share edges run both ways:
// a cluster of 16 convex polygons or more is first merged along them where the result is convex
// (merge_shared_edges). Seeded jittered grids split along random diagonals, with gaps (so some
// merges would turn right and are refused), loose triangles over them, shuffled: with and without
// the merge, the area is within its bound of Clipper's union of the polygons scaled by 2^20 (as
// above), and the merge ran.
TEST(ClusterUnion, TrianglesSharingEdgesMergeWithinTheBound) {
  std::mt19937 rng(20261130);
  auto uniform = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  std::size_t merged_clusters = 0;
  shadow::fast::ClusterScratch scratch;
  for (int round = 0; round < 80; ++round) {
    const int k = uniform(3, 9), spacing = round % 2 ? 40 : 4000;
    std::vector<std::vector<CL::IntPoint>> grid(static_cast<std::size_t>(k + 1));
    for (int i = 0; i <= k; ++i)
      for (int j = 0; j <= k; ++j)  // jitter under a quarter of the spacing: every triangle counter-clockwise
        grid[static_cast<std::size_t>(i)].push_back(
            {i * spacing + uniform(-spacing / 5, spacing / 5), j * spacing + uniform(-spacing / 5, spacing / 5)});
    auto at = [&](int i, int j) { return grid[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]; };
    CL::Paths polygons;
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) {
        if (round % 4 != 0 && uniform(0, 6) == 0) continue;  // a gap
        const CL::IntPoint a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
        if (uniform(0, 1) == 0) {
          polygons.push_back({a, b, c});
          polygons.push_back({a, c, d});
        } else {
          polygons.push_back({a, b, d});
          polygons.push_back({b, c, d});
        }
      }
    for (int extra = uniform(0, 3); extra > 0; --extra) {  // loose triangles across the patch
      const CL::cInt x = uniform(0, k * spacing), y = uniform(0, k * spacing), w = uniform(1, 2 * spacing);
      polygons.push_back({{x, y}, {x + w, y}, {x, y + uniform(1, 2 * spacing)}});
    }
    std::shuffle(polygons.begin(), polygons.end(), rng);
    double clipper_error = 0;
    const double fine = fine_union_area(polygons, clipper_error);
    for (const bool merge : {true, false}) {
      ClusterUnionCounts counts;
      const ClusteredArea got = shadow::fast::clustered_union_area(polygons, 0.6, 0.8, &counts, &scratch, merge);
      EXPECT_NEAR(area_of(got), fine, error_of(got) + clipper_error + 1e-9 * fine) << "round " << round << " merge " << merge;
      if (merge) merged_clusters += counts.merged;
      else EXPECT_EQ(counts.merged, 0u) << "round " << round;
    }
  }
  EXPECT_GT(merged_clusters, 40u);
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
    const double clipped = clipper_union_area(polygons, 0);
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

// The box clip that skips sides (fast/box_clip.hpp) gives the same doubles, vertex for vertex,
// as clip_axis at all four sides: polygons inside, across, outside and on the bounds, some
// clipped away by the first axis, with crossings whose rounded other coordinate may land just
// outside that axis' bounds.
TEST(ClusterUnion, BoxClipSkippingInsideSidesIsTheFourClips) {
  std::mt19937_64 random(20261130);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::size_t skipped = 0, clipped = 0, emptied = 0, large_clipped = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const std::array<double, 2> lo{unit(random) * 3 - 1.5, unit(random) * 3 - 1.5};
    const std::array<double, 2> hi{lo[0] + 0.1 + unit(random) * 2, lo[1] + 0.1 + unit(random) * 2};
    // A convex polygon about a centre near the box (a third of them small and inside it), some
    // vertices moved exactly onto a bound.
    const bool small = trial % 3 == 0;
    const glm::dvec2 centre = small ? glm::dvec2{lo[0] + (0.3 + 0.4 * unit(random)) * (hi[0] - lo[0]),
                                                 lo[1] + (0.3 + 0.4 * unit(random)) * (hi[1] - lo[1])}
                                    : glm::dvec2{lo[0] - 1 + unit(random) * (hi[0] - lo[0] + 2),
                                                 lo[1] - 1 + unit(random) * (hi[1] - lo[1] + 2)};
    const double rx = small ? 0.25 * (hi[0] - lo[0]) * unit(random) : 0.05 + unit(random) * 2.5;
    const double ry = small ? 0.25 * (hi[1] - lo[1]) * unit(random) : 0.05 + unit(random) * 2.5;
    const double turn = unit(random) * 6.283;
    // Every 40th polygon is too large for the clip's stack buffers (over 32 vertices): the
    // vectors' walk, from the start or after a clip that grew the polygon.
    const int n = trial % 40 == 7 ? 30 + static_cast<int>(unit(random) * 12) : 3 + static_cast<int>(unit(random) * 9);
    std::vector<double> angles(static_cast<std::size_t>(n));
    for (double& a : angles) a = unit(random) * 6.283;
    std::sort(angles.begin(), angles.end());
    shadow::fast::ChartPoints poly;
    for (double a : angles) {
      glm::dvec2 p{centre.x + rx * std::cos(a + turn), centre.y + ry * std::sin(a)};
      const double snap = unit(random);
      if (snap < 0.08) p.x = lo[0];
      else if (snap < 0.16) p.x = hi[0];
      else if (snap < 0.24) p.y = lo[1];
      else if (snap < 0.32) p.y = hi[1];
      poly.push_back(p);
    }
    shadow::fast::ChartPoints want = poly, got = poly, scratch;
    for (int c = 0; c < 2 && want.size() >= 3; ++c) {
      shadow::fast::clip_axis(want, c, lo[c], true, scratch);
      if (c == 0 && want.size() < 3) ++emptied;  // the loop ends before the second axis
      shadow::fast::clip_axis(want, c, hi[c], false, scratch);
    }
    shadow::fast::clip_to_box_sides(got, lo, hi, scratch);
    ASSERT_EQ(got.size(), want.size()) << "trial " << trial;
    for (std::size_t v = 0; v < got.size(); ++v) {
      ASSERT_EQ(std::memcmp(&got[v], &want[v], sizeof(glm::dvec2)), 0) << "trial " << trial << " vertex " << v;
    }
    (want == poly ? skipped : clipped) += 1;
    if (n > 32 && !(want == poly)) ++large_clipped;
  }
  // A crossing whose other coordinate rounds past that axis' bound: from (-1, -1) to (0, 1.2e-16)
  // at x = 0, y = -1 + (1.2e-16 + 1) = 2.2e-16 > 1.2e-16. Every vertex was inside y <= 1.2e-16
  // before the clip in x, not after: the second axis has to be tested on the clipped polygon.
  {
    const std::array<double, 2> lo{0.0, -2.0}, hi{2.0, 1.2e-16};
    shadow::fast::ChartPoints want{{-1.0, -1.0}, {0.0, 1.2e-16}, {1.0, -1.5}}, got = want, scratch;
    for (int c = 0; c < 2; ++c) {
      shadow::fast::clip_axis(want, c, lo[c], true, scratch);
      shadow::fast::clip_axis(want, c, hi[c], false, scratch);
    }
    shadow::fast::clip_to_box_sides(got, lo, hi, scratch);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t v = 0; v < got.size(); ++v) EXPECT_EQ(std::memcmp(&got[v], &want[v], sizeof(glm::dvec2)), 0) << v;
    for (const glm::dvec2& p : got) EXPECT_LE(p.y, hi[1]);
  }
  EXPECT_GT(skipped, 1000u);  // wholly inside: nothing to clip
  EXPECT_GT(clipped, 5000u);
  EXPECT_GT(emptied, 100u);
  EXPECT_GT(large_clipped, 100u);  // the vectors' walk
}

// A low sun's casts on a ground, diagonal: 60 long thin strips along (1, 1), side by side with
// gaps across them (every fifth shifted onto its neighbour), whose boxes overlap up to 20 strips
// apart. Measured across the shadows' direction, the strips apart across are clusters of their
// own: 38 singletons (exact shoelace areas) and 11 pairs measured by their boundary, where the
// boxes alone made one cluster of all 60. The area is the Clipper union's within the bound.
TEST(ClusterUnion, DiagonalStripsApartAcrossTheShadowsAreClustersOfTheirOwn) {
  CL::Paths strips;
  for (CL::cInt k = 0; k < 60; ++k) {
    const CL::cInt x = 4 * k - (k % 5 == 0 ? 3 : 0);
    strips.push_back({{x, 0}, {x + 2, 0}, {x + 82, 80}, {x + 80, 80}});
  }
  ClusterUnionCounts counts;
  const ClusteredArea a = shadow::fast::clustered_union_area(strips, 1, 1, &counts);
  EXPECT_EQ(counts.singletons, 38u);
  EXPECT_EQ(counts.boundaries, 11u);
  EXPECT_FALSE(a.clipper);
  double clipper_error = 0;
  const double fine = fine_union_area(strips, clipper_error);
  EXPECT_NEAR(area_of(a), fine, error_of(a) + clipper_error);
  // Along x (the shadows' direction taken as (0, 1), the fallback), the strips are wide across
  // and their boxes overlap: the same area, from fewer, larger clusters.
  ClusterUnionCounts along_x;
  const ClusteredArea b = shadow::fast::clustered_union_area(strips, 0, 1, &along_x);
  EXPECT_LT(along_x.singletons, counts.singletons);
  EXPECT_NEAR(area_of(b), fine, error_of(b) + clipper_error);
}

// The sweep across the shadows finds exactly the pairs whose boxes overlap (with positive area,
// or touching too when closed) and whose extents across are not apart, as a test of every pair
// does, for directions along the axes, diagonal and zero (the fallback), with and without a
// polygon passed over.
TEST(ClusterUnion, TheSweepAcrossFindsThePairsThatMeetInBoxAndAcross) {
  std::mt19937_64 random(7);
  std::uniform_int_distribution<CL::cInt> corner(0, 60), size(1, 25);
  const double directions[][2] = {{1, 0}, {0, 1}, {1, 1}, {-3, 1}, {0, 0}};
  for (int trial = 0; trial < 300; ++trial) {
    CL::Paths polygons(1 + trial % 40);
    std::vector<shadow::fast::GridBox> boxes;
    for (CL::Path& path : polygons) {
      // A quadrilateral long along x in some trials: its box is not its extent across.
      const CL::cInt x = corner(random), y = corner(random), w = size(random) * (trial % 3 == 0 ? 4 : 1);
      const CL::cInt h = size(random), skew = size(random) - 12;
      path = {{x, y}, {x + w, y + skew}, {x + w, y + skew + h}, {x, y + h}};
      boxes.push_back(shadow::fast::grid_box(path));
    }
    const double* d = directions[trial % 5];
    const shadow::fast::AcrossAxis axis = shadow::fast::across_axis(d[0], d[1]);
    std::vector<std::pair<double, double>> across;
    for (const CL::Path& path : polygons) across.push_back(shadow::fast::across_extent(path, axis));
    const std::size_t skipped = trial % 4 == 0 ? 0 : polygons.size();  // one passed over in a quarter
    for (bool closed : {false, true}) {
      std::vector<std::pair<std::size_t, std::size_t>> swept, brute;
      std::vector<shadow::geometry::AcrossSweepEntry<shadow::fast::GridBox>> scratch;
      auto add = [&](std::size_t p, std::size_t o) { swept.emplace_back(std::min(p, o), std::max(p, o)); };
      auto passed = [&](std::size_t p) { return p == skipped; };
      if (closed) shadow::geometry::sweep_across<true>(boxes, across, scratch, add, passed);
      else shadow::geometry::sweep_across<false>(boxes, across, scratch, add, passed);
      for (std::size_t a = 0; a < boxes.size(); ++a)
        for (std::size_t b = a + 1; b < boxes.size(); ++b) {
          if (a == skipped || b == skipped) continue;
          const shadow::fast::GridBox &p = boxes[a], &q = boxes[b];
          const bool meet = closed ? p.x0 <= q.x1 && q.x0 <= p.x1 && p.y0 <= q.y1 && q.y0 <= p.y1
                                   : p.x0 < q.x1 && q.x0 < p.x1 && p.y0 < q.y1 && q.y0 < p.y1;
          if (meet && !shadow::fast::apart(across[a], across[b])) brute.emplace_back(a, b);
        }
      std::sort(swept.begin(), swept.end());
      ASSERT_EQ(swept, brute) << "trial " << trial << (closed ? " closed" : " open");
    }
  }
}

// Extents that touch exactly (integers: a box's own y extent) are not apart, and an item marked
// passed by `pair` itself (as clustered_union_area leaves a cast out) makes no later pair.
TEST(ClusterUnion, TheSweepAcrossKeepsTouchingExtentsAndStopsAtAPassedItem) {
  std::vector<shadow::fast::GridBox> boxes = {{0, 0, 10, 2}, {0, 2, 10, 4}, {0, 4, 10, 6}, {20, 0, 30, 6}};
  std::vector<std::pair<double, double>> across;
  for (const shadow::fast::GridBox& b : boxes) across.emplace_back(static_cast<double>(b.y0), static_cast<double>(b.y1));
  std::vector<shadow::geometry::AcrossSweepEntry<shadow::fast::GridBox>> scratch;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  shadow::geometry::sweep_across<true>(boxes, across, scratch, [&](std::size_t p, std::size_t o) {
    pairs.emplace_back(std::min(p, o), std::max(p, o));
  });
  std::sort(pairs.begin(), pairs.end());
  // Boxes 0-1 and 1-2 touch along y = 2 and y = 4 (extents touching too); box 3 is apart in x.
  EXPECT_EQ(pairs, (std::vector<std::pair<std::size_t, std::size_t>>{{0, 1}, {1, 2}}));
  // Three boxes overlapping one another: the first pair marks its earlier item passed, so that
  // item meets nothing more, and the other two still pair.
  boxes = {{0, 0, 10, 10}, {1, 1, 9, 9}, {2, 2, 8, 8}};
  across = {{0, 10}, {1, 9}, {2, 8}};
  std::vector<char> passed(3, 0);
  pairs.clear();
  shadow::geometry::sweep_across<false>(boxes, across, scratch, [&](std::size_t later, std::size_t earlier) {
    pairs.emplace_back(earlier, later);
    passed[earlier] = 1;
  }, [&](std::size_t p) { return passed[p] != 0; });
  EXPECT_EQ(pairs, (std::vector<std::pair<std::size_t, std::size_t>>{{0, 1}, {1, 2}}));
}

}  // namespace
