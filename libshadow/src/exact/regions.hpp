// SPDX-License-Identifier: GPL-3.0-or-later
// Regions that come out of CGAL's Boolean operations, turned into what the outputs promise:
// simple polygons and exact areas. Include only from src/exact/*.cpp (CGAL).
#pragma once

#include "exact/kernel.hpp"

#include <CGAL/Polygon_triangulation_decomposition_2.h>

#include <algorithm>
#include <iterator>
#include <map>
#include <utility>
#include <vector>

namespace shadow::exact {

/// Exact area of a polygon with holes (holes come out clockwise).
inline FT region_area(const PolygonWithHoles2& region) {
  std::vector<FT> terms{polygon_area(region.outer_boundary())};
  for (auto h = region.holes_begin(); h != region.holes_end(); ++h) terms.push_back(-CGAL::abs(polygon_area(*h)));
  return balanced_sum(terms);
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

/// Merges triangles that tile a region into convex polygons (Hertel-Mehlhorn): a shared edge is
/// removed whenever both of its ends stay convex. Fewer, fatter cells than a triangulation, and
/// no new vertices. Input triangles counter-clockwise.
inline std::vector<Polygon2> merge_into_convex(const std::vector<Polygon2>& triangles) {
  struct LessXY {
    bool operator()(const Point2& a, const Point2& b) const { return CGAL::compare_xy(a, b) == CGAL::SMALLER; }
  };
  std::map<Point2, int, LessXY> id_of;
  std::vector<Point2> point;
  std::vector<std::vector<int>> polygon;
  for (const Polygon2& t : triangles) {
    std::vector<int> ids;
    for (auto v = t.vertices_begin(); v != t.vertices_end(); ++v) {
      auto [it, inserted] = id_of.emplace(*v, static_cast<int>(point.size()));
      if (inserted) point.push_back(*v);
      ids.push_back(it->second);
    }
    polygon.push_back(std::move(ids));
  }
  std::vector<bool> alive(polygon.size(), true);
  std::map<std::pair<int, int>, std::size_t> owner;  // directed edge -> polygon
  for (std::size_t p = 0; p < polygon.size(); ++p)
    for (std::size_t a = 0; a < polygon[p].size(); ++a)
      owner[{polygon[p][a], polygon[p][(a + 1) % polygon[p].size()]}] = p;
  auto convex_at = [&](const std::vector<int>& v, std::size_t at) {
    const std::size_t n = v.size();
    return CGAL::orientation(point[v[(at + n - 1) % n]], point[v[at]], point[v[(at + 1) % n]]) != CGAL::RIGHT_TURN;
  };
  for (std::size_t p = 0; p < polygon.size(); ++p) {
    bool merged_any = true;
    while (alive[p] && merged_any) {
      merged_any = false;
      const std::vector<int>& pv = polygon[p];
      for (std::size_t a = 0; a < pv.size() && !merged_any; ++a) {
        const int from = pv[a], to = pv[(a + 1) % pv.size()];
        const auto twin = owner.find({to, from});
        if (twin == owner.end() || twin->second == p || !alive[twin->second]) continue;
        const std::size_t q = twin->second;
        const std::vector<int>& qv = polygon[q];
        // p runs ... from, to ...; q runs ... to, from ...: merged = p from `to` round to `from`,
        // then q strictly between `from` and `to`.
        std::vector<int> merged;
        for (std::size_t k = 0; k < pv.size(); ++k) merged.push_back(pv[(a + 1 + k) % pv.size()]);
        const std::size_t qa = static_cast<std::size_t>(std::find(qv.begin(), qv.end(), from) - qv.begin());
        for (std::size_t k = 1; k + 1 < qv.size(); ++k) merged.push_back(qv[(qa + k) % qv.size()]);
        // The shared edge's ends: `to` at position 0, `from` at position pv.size() - 1.
        if (!convex_at(merged, 0) || !convex_at(merged, pv.size() - 1)) continue;
        alive[q] = false;
        owner.erase({from, to});
        owner.erase({to, from});
        polygon[p] = std::move(merged);
        for (std::size_t k = 0; k < polygon[p].size(); ++k)
          owner[{polygon[p][k], polygon[p][(k + 1) % polygon[p].size()]}] = p;
        merged_any = true;
      }
    }
  }
  std::vector<Polygon2> out;
  for (std::size_t p = 0; p < polygon.size(); ++p) {
    if (!alive[p]) continue;
    Polygon2 cell;
    for (int v : polygon[p]) cell.push_back(point[v]);
    out.push_back(std::move(cell));
  }
  return out;
}

/// Splits a region into simple polygons: the region itself when its boundary is simple, else
/// convex pieces (a triangulation merged back into convex polygons). Boolean operations return outer boundaries that are only relatively simple (a hole
/// touching the boundary at a vertex is merged into it, and the vertex repeats), so a region
/// without holes is not necessarily simple either.
inline void append_simple_cells(const PolygonWithHoles2& region, std::vector<Polygon2>& cells) {
  if (region.number_of_holes() == 0 && !has_repeated_vertex(region.outer_boundary())) {
    cells.push_back(region.outer_boundary());
    return;
  }
  CGAL::Polygon_triangulation_decomposition_2<Kernel> triangulate;
  std::vector<Polygon2> triangles;
  triangulate(region, std::back_inserter(triangles));
  for (Polygon2& cell : merge_into_convex(triangles)) cells.push_back(std::move(cell));
}

}  // namespace shadow::exact
