// SPDX-License-Identifier: GPL-3.0-or-later
// Regions that come out of CGAL's Boolean operations, turned into what the outputs promise:
// simple polygons and exact areas. Include only from src/exact/*.cpp (CGAL).
#pragma once

#include "exact/kernel.hpp"

#include <CGAL/Polygon_triangulation_decomposition_2.h>

#include <algorithm>
#include <iterator>
#include <vector>

namespace shadow::exact {

/// Exact area of a polygon with holes (holes come out clockwise).
inline FT region_area(const PolygonWithHoles2& region) {
  FT area = region.outer_boundary().area();
  for (auto h = region.holes_begin(); h != region.holes_end(); ++h) area -= CGAL::abs(h->area());
  return area;
}

/// Whether a boundary visits some point twice. The boundaries Boolean operations return are
/// relatively simple (edges never cross or overlap; vertices may touch), so this is exactly
/// "not simple", and far cheaper than a general simplicity sweep.
inline bool has_repeated_vertex(const Polygon2& polygon) {
  std::vector<Point2> points(polygon.vertices_begin(), polygon.vertices_end());
  std::sort(points.begin(), points.end(),
            [](const Point2& a, const Point2& b) { return CGAL::compare_xy(a, b) == CGAL::SMALLER; });
  return std::adjacent_find(points.begin(), points.end()) != points.end();
}

/// Splits a region into simple polygons: the region itself when its boundary is simple, else
/// triangles. Boolean operations return outer boundaries that are only relatively simple (a hole
/// touching the boundary at a vertex is merged into it, and the vertex repeats), so a region
/// without holes is not necessarily simple either.
inline void append_simple_cells(const PolygonWithHoles2& region, std::vector<Polygon2>& cells) {
  if (region.number_of_holes() == 0 && !has_repeated_vertex(region.outer_boundary())) {
    cells.push_back(region.outer_boundary());
    return;
  }
  CGAL::Polygon_triangulation_decomposition_2<Kernel> triangulate;
  triangulate(region, std::back_inserter(cells));
}

}  // namespace shadow::exact
