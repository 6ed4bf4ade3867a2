// SPDX-License-Identifier: GPL-3.0-or-later
// Regions that come out of CGAL's Boolean operations, turned into what the outputs promise:
// simple polygons and exact areas. Include only from src/exact/*.cpp (CGAL).
#pragma once

#include "exact/kernel.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>

#include <algorithm>
#include <iterator>
#include <map>
#include <utility>
#include <vector>

namespace shadow::exact {

/// Exact area of a polygon with holes (holes come out clockwise).
inline FT region_area(const PolygonWithHoles2& region) {
  if (region.number_of_holes() == 0) return polygon_area(region.outer_boundary());  // the common case
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
/// no new vertices. Input triangles counter-clockwise. The pieces are cycles of half-edges: a
/// removal splices two cycles in O(1) and tests only the edges next to the removed one, so the
/// whole merge is one pass, O(n log n) with the point and edge maps. (It used to copy the growing
/// polygon at every merge: quadratic, minutes for a ground whose lit region surrounds a comb of
/// 8,000 vertices.) One pass suffices: removing an edge never makes another removable.
inline std::vector<Polygon2> merge_into_convex(const std::vector<Polygon2>& triangles) {
  struct LessXY {
    bool operator()(const Point2& a, const Point2& b) const { return CGAL::compare_xy(a, b) == CGAL::SMALLER; }
  };
  std::map<Point2, int, LessXY> id_of;
  std::vector<Point2> point;
  std::vector<int> origin;  // half-edge 3 t + k: triangle t's vertex k to vertex k + 1
  for (const Polygon2& t : triangles) {
    for (auto v = t.vertices_begin(); v != t.vertices_end(); ++v) {
      auto [it, inserted] = id_of.emplace(*v, static_cast<int>(point.size()));
      if (inserted) point.push_back(*v);
      origin.push_back(it->second);
    }
  }
  const std::size_t halves = origin.size();
  std::vector<std::size_t> next(halves), prev(halves);
  std::map<std::pair<int, int>, std::size_t> half_of;
  for (std::size_t h = 0; h < halves; ++h) {
    const std::size_t base = h - h % 3;
    next[h] = base + (h % 3 + 1) % 3;
    prev[h] = base + (h % 3 + 2) % 3;
    half_of[{origin[h], origin[next[h]]}] = h;
  }
  std::vector<char> alive(halves, 1);
  std::vector<std::size_t> parent(triangles.size());
  for (std::size_t t = 0; t < parent.size(); ++t) parent[t] = t;
  auto find = [&](std::size_t t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  auto convex = [&](std::size_t in, std::size_t out) {  // corner from half-edge `in` to `out`
    return CGAL::orientation(point[origin[in]], point[origin[out]], point[origin[next[out]]]) != CGAL::RIGHT_TURN;
  };
  for (std::size_t h = 0; h < halves; ++h) {
    const auto twin = half_of.find({origin[next[h]], origin[h]});
    if (twin == half_of.end()) continue;
    const std::size_t t = twin->second;
    if (t < h || !alive[h] || !alive[t] || find(h / 3) == find(t / 3)) continue;
    // h runs a -> b in piece P, t runs b -> a in piece Q. Merged: ... prev[h] -> a -> next[t]
    // ... prev[t] -> b -> next[h] ...
    if (!convex(prev[t], next[h]) || !convex(prev[h], next[t])) continue;
    next[prev[h]] = next[t];
    prev[next[t]] = prev[h];
    next[prev[t]] = next[h];
    prev[next[h]] = prev[t];
    alive[h] = alive[t] = 0;
    parent[find(h / 3)] = find(t / 3);
  }
  std::vector<Polygon2> out;
  std::vector<char> done(triangles.size(), 0);
  for (std::size_t h = 0; h < halves; ++h) {
    if (!alive[h]) continue;
    const std::size_t piece = find(h / 3);
    if (done[piece]) continue;
    done[piece] = 1;
    Polygon2 cell;
    std::size_t e = h;
    do {
      cell.push_back(point[origin[e]]);
      e = next[e];
    } while (e != h && cell.size() <= halves);
    out.push_back(std::move(cell));
  }
  return out;
}

/// Triangles (counter-clockwise) tiling a region with holes: a constrained Delaunay
/// triangulation of its boundaries, faces at odd nesting depth. CGAL's
/// Polygon_triangulation_decomposition_2 uses a constrained triangulation that is not Delaunay,
/// whose constraint insertion is quadratic on combs (docs/benchmarks.md). The vertices are inserted in spatial order (CGAL's spatial_sort: a
/// Hilbert order over rounds of a deterministic shuffle), then the boundaries' edges as
/// constraints: inserted along the boundaries instead, a long comb-like boundary (the shadows
/// of a low sun) made each insertion flip many edges (80% of the plane shadow's time spent in
/// the flips at 5 degrees).
inline void triangulate_region(const PolygonWithHoles2& region, std::vector<Polygon2>& triangles) {
  using Fbi = CGAL::Triangulation_face_base_with_info_2<int, Kernel>;
  using Fb = CGAL::Constrained_triangulation_face_base_2<Kernel, Fbi>;
  using Tds = CGAL::Triangulation_data_structure_2<CGAL::Triangulation_vertex_base_2<Kernel>, Fb>;
  using CDT = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::No_constraint_intersection_requiring_constructions_tag>;
  CDT cdt;
  std::vector<Point2> points;
  std::vector<std::size_t> ends;  // one past each boundary's last point
  auto gather = [&](const Polygon2& boundary) {
    points.insert(points.end(), boundary.vertices_begin(), boundary.vertices_end());
    ends.push_back(points.size());
  };
  gather(region.outer_boundary());
  for (auto h = region.holes_begin(); h != region.holes_end(); ++h) gather(*h);
  // Every exact value first: CGAL walks to a point with doubles from the lazy points'
  // intervals, which an exact evaluation narrows, and the walk decides which faces the
  // triangulation's containers hold first, so the cells would depend on what was evaluated
  // before. Evaluated, the cells depend on the region alone (and its area needs them anyway).
  for (const Point2& p : points) CGAL::exact(p);
  std::vector<std::size_t> order(points.size());
  for (std::size_t a = 0; a < order.size(); ++a) order[a] = a;
  using Map = CGAL::Pointer_property_map<Point2>::type;
  CGAL::spatial_sort(order.begin(), order.end(),
                     CGAL::Spatial_sort_traits_adapter_2<Kernel, Map>(CGAL::make_property_map(points)));
  std::vector<typename CDT::Vertex_handle> handles(points.size());
  typename CDT::Face_handle hint;
  for (std::size_t a : order) {
    handles[a] = cdt.insert(points[a], hint);  // a point met before gives its vertex
    hint = handles[a]->face();
  }
  std::size_t first = 0;
  for (std::size_t end : ends) {
    for (std::size_t a = first; a < end; ++a) {
      const auto& from = handles[a];
      const auto& to = handles[a + 1 < end ? a + 1 : first];
      if (from != to) cdt.insert_constraint(from, to);
    }
    first = end;
  }
  // Nesting depth: 0 outside, +1 across each constrained edge; the region is at odd depth.
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::vector<typename CDT::Face_handle> level{cdt.infinite_face()}, next_level;
  for (int depth = 0; !level.empty(); ++depth) {
    next_level.clear();
    while (!level.empty()) {
      const typename CDT::Face_handle f = level.back();
      level.pop_back();
      if (f->info() >= 0) continue;
      f->info() = depth;
      for (int e = 0; e < 3; ++e) {
        const typename CDT::Face_handle g = f->neighbor(e);
        if (g->info() >= 0) continue;
        (f->is_constrained(e) ? next_level : level).push_back(g);
      }
    }
    level.swap(next_level);
  }
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->info() % 2 == 1) {
      Polygon2 t;
      for (int k = 0; k < 3; ++k) t.push_back(f->vertex(k)->point());
      triangles.push_back(std::move(t));
    }
}

/// Splits a region into simple polygons: the region itself when its boundary is simple, else
/// convex pieces (a triangulation merged back into convex polygons). Boolean operations return
/// outer boundaries that are only relatively simple (a hole touching the boundary at a vertex is
/// merged into it, and the vertex repeats), so a region without holes is not necessarily simple
/// either.
inline void append_simple_cells(const PolygonWithHoles2& region, std::vector<Polygon2>& cells) {
  if (region.number_of_holes() == 0 && !has_repeated_vertex(region.outer_boundary())) {
    cells.push_back(region.outer_boundary());
    return;
  }
  std::vector<Polygon2> triangles;
  triangulate_region(region, triangles);
  for (Polygon2& cell : merge_into_convex(triangles)) cells.push_back(std::move(cell));
}

}  // namespace shadow::exact
