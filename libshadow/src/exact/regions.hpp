// SPDX-License-Identifier: GPL-3.0-or-later
// Regions that come out of CGAL's Boolean operations, turned into what the outputs promise:
// simple polygons and exact areas. Include only from src/exact/*.cpp (CGAL).
#pragma once

#include "exact/kernel.hpp"

#include <CGAL/Polygon_triangulation_decomposition_2.h>

#include <iterator>
#include <vector>

namespace shadow::exact {

/// Exact area of a polygon with holes (holes come out clockwise).
inline FT region_area(const PolygonWithHoles2& region) {
  FT area = region.outer_boundary().area();
  for (auto h = region.holes_begin(); h != region.holes_end(); ++h) area -= CGAL::abs(h->area());
  return area;
}

/// Splits a region into simple polygons: the region itself when its boundary is simple, else
/// triangles. Boolean operations return outer boundaries that are only relatively simple (a hole
/// touching the boundary at a vertex is merged into it, and the vertex repeats), so a region
/// without holes is not necessarily simple either.
inline void append_simple_cells(const PolygonWithHoles2& region, std::vector<Polygon2>& cells) {
  if (region.number_of_holes() == 0 && region.outer_boundary().is_simple()) {
    cells.push_back(region.outer_boundary());
    return;
  }
  CGAL::Polygon_triangulation_decomposition_2<Kernel> triangulate;
  triangulate(region, std::back_inserter(cells));
}

}  // namespace shadow::exact
