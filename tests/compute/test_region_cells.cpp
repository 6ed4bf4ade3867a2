// SPDX-License-Identifier: GPL-3.0-or-later
// exact::append_simple_cells (exact/regions.hpp): the regions CGAL's union returns, holes and
// all, split into simple cells (a constrained Delaunay triangulation whose vertices go in in
// spatial order, merged back into convex cells). Checked on seeded unions of many convex
// polygons, among them the long thin shadows of a low sun: the cells' exact areas add up to the
// region's exact area, every cell is simple and counter-clockwise with a positive area, no cell
// has a vertex the region's boundaries lack, and the same region gives the same cells twice.
#include "exact/regions.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <vector>

namespace shadow::exact {
namespace {

struct LessXY {
  bool operator()(const Point2& a, const Point2& b) const { return CGAL::compare_xy(a, b) == CGAL::SMALLER; }
};

/// A convex quadrilateral: the parallelogram spanned by `u` and `v` from corner (x, y), counter-clockwise.
Polygon2 parallelogram(double x, double y, double ux, double uy, double vx, double vy) {
  Polygon2 p;
  p.push_back(Point2(x, y));
  p.push_back(Point2(FT(x) + FT(ux), FT(y) + FT(uy)));
  p.push_back(Point2(FT(x) + FT(ux) + FT(vx), FT(y) + FT(uy) + FT(vy)));
  p.push_back(Point2(FT(x) + FT(vx), FT(y) + FT(vy)));
  if (p.orientation() == CGAL::CLOCKWISE) p.reverse_orientation();
  return p;
}

/// The union's regions of `count` seeded parallelograms in a square of side 100: boxes of sides
/// 2-10 and, with `long_shadows`, slanted strips 30-60 long and 1-3 wide (a low sun's shadows).
std::vector<PolygonWithHoles2> union_regions(unsigned seed, std::size_t count, bool long_shadows) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0, 100), side(2, 10), length(30, 60), width(1, 3);
  std::vector<Polygon2> pieces;
  for (std::size_t a = 0; a < count; ++a) {
    const double x = std::round(pos(rng) * 100) / 100, y = std::round(pos(rng) * 100) / 100;
    if (long_shadows && a % 2 == 1) {
      const double l = length(rng), w = width(rng);
      pieces.push_back(parallelogram(x, y, l * 0.8, l * 0.6, -w * 0.6, w * 0.8));
    } else {
      pieces.push_back(parallelogram(x, y, side(rng), 0, 0, side(rng)));
    }
  }
  PolygonSet2 set;
  set.join(pieces.begin(), pieces.end());
  std::vector<PolygonWithHoles2> regions;
  set.polygons_with_holes(std::back_inserter(regions));
  return regions;
}

void check_cells(const std::vector<PolygonWithHoles2>& regions, std::size_t& holed) {
  for (const PolygonWithHoles2& region : regions) {
    std::vector<Polygon2> cells;
    append_simple_cells(region, cells);
    ASSERT_FALSE(cells.empty());
    holed += region.number_of_holes() > 0 ? 1 : 0;
    std::set<Point2, LessXY> boundary(region.outer_boundary().vertices_begin(), region.outer_boundary().vertices_end());
    for (auto h = region.holes_begin(); h != region.holes_end(); ++h) boundary.insert(h->vertices_begin(), h->vertices_end());
    std::vector<FT> areas;
    for (const Polygon2& cell : cells) {
      EXPECT_TRUE(cell.is_simple());
      const FT area = polygon_area(cell);
      EXPECT_GT(area, 0);  // counter-clockwise, not flat
      areas.push_back(area);
      for (auto v = cell.vertices_begin(); v != cell.vertices_end(); ++v) EXPECT_EQ(boundary.count(*v), 1u);
    }
    EXPECT_EQ(balanced_sum(areas), region_area(region));  // exactly
    std::vector<Polygon2> again;
    append_simple_cells(region, again);
    EXPECT_EQ(again, cells);
  }
}

TEST(RegionCells, CellsOfUnitedBoxesTileTheirRegionsExactly) {
  std::size_t holed = 0;
  for (unsigned seed : {1u, 2u, 3u}) check_cells(union_regions(seed, 400, false), holed);
  EXPECT_GT(holed, 0u) << "no region with holes: the test checks nothing new";
}

TEST(RegionCells, CellsOfALowSunsLongShadowsTileTheirRegionsExactly) {
  // Long strips crossing many boxes: comb-like boundaries around many holes, the case whose
  // vertices, inserted along the boundaries, made every insertion flip many edges.
  std::size_t holed = 0;
  for (unsigned seed : {4u, 5u}) check_cells(union_regions(seed, 600, true), holed);
  EXPECT_GT(holed, 0u) << "no region with holes: the test checks nothing new";
}

}  // namespace
}  // namespace shadow::exact
