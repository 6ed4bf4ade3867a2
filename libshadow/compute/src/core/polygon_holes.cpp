// SPDX-License-Identifier: GPL-3.0-or-later
// split_polygon_with_holes (core/polygon_holes.hpp): a polygon with holes into convex pieces made of
// its own vertices. Exact predicates on the doubles only (CGAL Epick, as core/clean_polygon.cpp and
// fast/ use it); no CGAL type leaves this file. The merge of triangles into convex pieces is the
// Hertel-Mehlhorn pass of exact/exact_faces.cpp, generalised from one ring to several: every ring
// runs with the polygon's inside on its left (outer ring counter-clockwise, holes clockwise in
// the chart), so "the fan of a vertex from its next to its previous vertex" is the same rule.
#include "core/polygon_holes.hpp"

#include "geometry/newell_normal.hpp"

#include <glm/common.hpp>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <new>
#include <unordered_map>
#include <utility>

namespace shadow::core {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_2;

std::string ring_name(int ring) { return ring < 0 ? "the outer ring" : "hole " + std::to_string(ring); }

/// The ring without consecutive repeats and without a closing copy of its first vertex.
std::vector<glm::dvec3> cleaned(const std::vector<glm::dvec3>& ring, int which) {
  std::vector<glm::dvec3> out;
  out.reserve(ring.size());
  for (std::size_t a = 0; a < ring.size(); ++a) {
    const glm::dvec3& v = ring[a];
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      throw PolygonHolesError(which, static_cast<int>(a), ring_name(which) + " has a coordinate that is not finite");
    if (out.empty() || v != out.back()) out.push_back(v);
  }
  while (out.size() > 1 && out.back() == out.front()) out.pop_back();
  if (out.size() < 3)
    throw PolygonHolesError(which, -1, ring_name(which) + " has fewer than 3 distinct vertices");
  return out;
}

bool segments_meet(const Point& a, const Point& b, const Point& c, const Point& d) {
  // Bounding boxes first: the exact test is cheap but there may be many pairs.
  if (std::max(a.x(), b.x()) < std::min(c.x(), d.x()) || std::max(c.x(), d.x()) < std::min(a.x(), b.x()) ||
      std::max(a.y(), b.y()) < std::min(c.y(), d.y()) || std::max(c.y(), d.y()) < std::min(a.y(), b.y()))
    return false;
  return CGAL::do_intersect(K::Segment_2(a, b), K::Segment_2(c, d));
}

/// True when some edge of ring `r` meets some edge of ring `s` (touching counts).
bool rings_meet(const std::vector<Point>& r, const std::vector<Point>& s) {
  for (std::size_t a = 0; a < r.size(); ++a)
    for (std::size_t b = 0; b < s.size(); ++b)
      if (segments_meet(r[a], r[(a + 1) % r.size()], s[b], s[(b + 1) % s.size()])) return true;
  return false;
}

/// Convex pieces (global vertex indices, counter-clockwise in the chart) of the polygon whose
/// rings are given by next/prev links over `chart`, each ring with the inside on its left.
std::vector<std::vector<int>> convex_pieces_of(const std::vector<Point>& chart, const std::vector<int>& next,
                                               const std::vector<int>& prev, bool merge) {
  using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, K>;
  using Fbi = CGAL::Triangulation_face_base_with_info_2<int, K>;
  using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
  using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::No_constraint_intersection_tag>;
  const std::size_t n = chart.size();
  CDT cdt;
  std::vector<std::pair<Point, int>> points;
  points.reserve(n);
  for (std::size_t a = 0; a < n; ++a) points.emplace_back(chart[a], static_cast<int>(a));
  cdt.insert(points.begin(), points.end());
  std::vector<CDT::Vertex_handle> handle(n);
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) handle[v->info()] = v;
  for (std::size_t a = 0; a < n; ++a) cdt.insert_constraint(handle[a], handle[next[a]]);
  // Inside triangles: left of every ring edge, then across unconstrained edges.
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::vector<CDT::Face_handle> stack, triangles;
  for (std::size_t a = 0; a < n; ++a) {
    CDT::Face_handle f;
    int i;
    if (!cdt.is_edge(handle[a], handle[next[a]], f, i)) continue;
    if (f->vertex(CDT::ccw(i)) != handle[a]) f = f->neighbor(i);
    stack.push_back(f);
  }
  while (!stack.empty()) {
    const CDT::Face_handle f = stack.back();
    stack.pop_back();
    if (f->info() >= 0 || cdt.is_infinite(f)) continue;
    f->info() = static_cast<int>(triangles.size());
    triangles.push_back(f);
    for (int e = 0; e < 3; ++e)
      if (!f->is_constrained(e) && f->neighbor(e)->info() < 0) stack.push_back(f->neighbor(e));
  }
  // Each vertex's fan of inside edges, counter-clockwise from its next to its previous vertex.
  std::vector<std::vector<int>> fan(n);
  for (std::size_t a = 0; a < n; ++a) {
    std::vector<int> around;
    auto c = cdt.incident_vertices(handle[a]), done = c;
    do {
      if (!cdt.is_infinite(c)) around.push_back(c->info());
    } while (++c != done);
    const auto start = std::find(around.begin(), around.end(), next[a]);
    std::rotate(around.begin(), start, around.end());
    around.resize(static_cast<std::size_t>(std::find(around.begin(), around.end(), prev[a]) - around.begin()) + 1);
    fan[a] = std::move(around);
  }
  std::vector<std::size_t> first(n + 1, 0);
  for (std::size_t a = 0; a < n; ++a) first[a + 1] = first[a] + fan[a].size();
  std::vector<std::size_t> lprev(first[n]), lnext(first[n]);
  std::unordered_map<std::uint64_t, std::size_t> position;
  auto key = [n](std::size_t a, std::size_t b) { return static_cast<std::uint64_t>(a) * n + b; };
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t k = 0; k < fan[a].size(); ++k) {
      lprev[first[a] + k] = first[a] + k - (k > 0 ? 1 : 0);
      lnext[first[a] + k] = first[a] + k + (k + 1 < fan[a].size() ? 1 : 0);
      if (k > 0 && k + 1 < fan[a].size()) position.emplace(key(a, static_cast<std::size_t>(fan[a][k])), first[a] + k);
    }
  auto vertex_of = [&](std::size_t a, std::size_t slot) { return fan[a][slot - first[a]]; };
  auto convex_without = [&](std::size_t a, std::size_t slot) {
    const int before = vertex_of(a, lprev[slot]), after = vertex_of(a, lnext[slot]);
    return CGAL::orientation(chart[after], chart[a], chart[before]) == CGAL::LEFT_TURN;
  };
  std::vector<int> parent(triangles.size());
  for (std::size_t t = 0; t < parent.size(); ++t) parent[t] = static_cast<int>(t);
  auto find = [&](int t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  for (const auto& f : triangles)
    for (int e = 0; e < 3; ++e) {
      if (!merge || f->is_constrained(e)) continue;
      const auto g = f->neighbor(e);
      if (g->info() < f->info()) continue;  // each diagonal once
      const std::size_t a = static_cast<std::size_t>(f->vertex(CDT::ccw(e))->info());
      const std::size_t b = static_cast<std::size_t>(f->vertex(CDT::cw(e))->info());
      const std::size_t pa = position.at(key(a, b)), pb = position.at(key(b, a));
      if (!convex_without(a, pa) || !convex_without(b, pb)) continue;
      lnext[lprev[pa]] = lnext[pa];
      lprev[lnext[pa]] = lprev[pa];
      lnext[lprev[pb]] = lnext[pb];
      lprev[lnext[pb]] = lprev[pb];
      parent[find(f->info())] = find(g->info());
    }
  // A piece is convex (every corner strictly convex), so it cannot wrap around a hole: a hole has
  // corners that are reflex from outside. Its boundary is one cycle of half-edges.
  std::unordered_map<std::uint64_t, int> successor;
  std::vector<int> roots, start_of(triangles.size(), -1);
  for (const auto& f : triangles) {
    const int r = find(f->info());
    for (int e = 0; e < 3; ++e) {
      const auto g = f->neighbor(e);
      if (!f->is_constrained(e) && find(g->info()) == r) continue;
      const int a = f->vertex(CDT::ccw(e))->info(), b = f->vertex(CDT::cw(e))->info();
      successor.emplace(static_cast<std::uint64_t>(r) * n + static_cast<std::uint64_t>(a), b);
      if (start_of[r] < 0) {
        start_of[r] = a;
        roots.push_back(r);
      }
    }
  }
  std::sort(roots.begin(), roots.end());
  std::vector<std::vector<int>> pieces;
  for (int r : roots) {
    std::vector<int> piece;
    int v = start_of[r];
    do {
      piece.push_back(v);
      v = successor.at(static_cast<std::uint64_t>(r) * n + static_cast<std::uint64_t>(v));
    } while (v != start_of[r] && piece.size() <= n);
    pieces.push_back(std::move(piece));
  }
  return pieces;
}

}  // namespace

namespace {

/// split_polygon_with_holes (convex pieces) or triangulate_polygon_with_holes (triangles, no
/// planarity check of the holes).
std::vector<std::vector<glm::dvec3>> split(const std::vector<glm::dvec3>& outer_in,
                                          const std::vector<std::vector<glm::dvec3>>& holes_in,
                                          double planarity_tolerance, bool triangles) {
  std::vector<std::vector<glm::dvec3>> rings;  // rings[0]: outer, rings[1 + h]: hole h
  rings.push_back(cleaned(outer_in, -1));
  for (std::size_t h = 0; h < holes_in.size(); ++h) rings.push_back(cleaned(holes_in[h], static_cast<int>(h)));
  const std::vector<glm::dvec3>& outer = rings[0];

  // The chart: drop the dominant axis of the outer ring's normal.
  const glm::dvec3 normal = geometry::newell_normal(outer, outer[0]);
  const glm::dvec3 magnitude = glm::abs(normal);
  const int k = magnitude.x >= magnitude.y && magnitude.x >= magnitude.z ? 0 : (magnitude.y >= magnitude.z ? 1 : 2);
  if (!(magnitude[k] > 0)) throw PolygonHolesError(-1, -1, "the outer ring has zero area");
  const int ci = (k + 1) % 3, cj = (k + 2) % 3;

  // Holes must lie in the outer ring's plane (the pieces are checked for planarity later, but a
  // hole off the plane would be cut out along its shadow in the chart, silently).
  if (rings.size() > 1 && !triangles) {
    glm::dvec3 low = outer[0], high = outer[0];
    for (const glm::dvec3& v : outer) {
      low = glm::min(low, v);
      high = glm::max(high, v);
    }
    const glm::dvec3 extent = high - low;
    const double diameter = std::max({extent.x, extent.y, extent.z});
    const double largest = std::max({std::abs(low.x), std::abs(low.y), std::abs(low.z), std::abs(high.x),
                                     std::abs(high.y), std::abs(high.z)});
    const double allowed = std::max(planarity_tolerance * diameter, 8 * std::numeric_limits<double>::epsilon() * largest);
    const glm::dvec3 unit = normal / std::sqrt(normal.x * normal.x + normal.y * normal.y + normal.z * normal.z);
    for (std::size_t r = 1; r < rings.size(); ++r)
      for (std::size_t a = 0; a < rings[r].size(); ++a) {
        const glm::dvec3 d = rings[r][a] - outer[0];
        if (std::abs(d.x * unit.x + d.y * unit.y + d.z * unit.z) > allowed)
          throw PolygonHolesError(static_cast<int>(r) - 1, static_cast<int>(a),
                                  ring_name(static_cast<int>(r) - 1) + " is not in the plane of the outer ring (vertex " +
                                      std::to_string(a) + ")");
      }
  }

  std::vector<std::vector<Point>> chart(rings.size());
  for (std::size_t r = 0; r < rings.size(); ++r) {
    const int which = static_cast<int>(r) - 1;
    for (const glm::dvec3& v : rings[r]) chart[r].emplace_back(v[ci], v[cj]);
    CGAL::Polygon_2<K> polygon(chart[r].begin(), chart[r].end());
    if (!polygon.is_simple())
      throw PolygonHolesError(which, -1, ring_name(which) + " is not simple (its edges cross or touch)");
    if (polygon.orientation() == CGAL::COLLINEAR) throw PolygonHolesError(which, -1, ring_name(which) + " has zero area");
  }
  const bool outer_ccw = CGAL::Polygon_2<K>(chart[0].begin(), chart[0].end()).orientation() == CGAL::COUNTERCLOCKWISE;
  if (!outer_ccw) {
    std::reverse(rings[0].begin(), rings[0].end());
    std::reverse(chart[0].begin(), chart[0].end());
  }

  // Holes strictly inside the outer ring, apart from each other.
  const CGAL::Polygon_2<K> outer_polygon(chart[0].begin(), chart[0].end());
  for (std::size_t r = 1; r < rings.size(); ++r) {
    const int which = static_cast<int>(r) - 1;
    for (std::size_t a = 0; a < chart[r].size(); ++a) {
      const CGAL::Bounded_side side = outer_polygon.bounded_side(chart[r][a]);
      if (side == CGAL::ON_UNBOUNDED_SIDE)
        throw PolygonHolesError(which, static_cast<int>(a), ring_name(which) + " is outside the outer ring (vertex " + std::to_string(a) + ")");
      if (side == CGAL::ON_BOUNDARY)
        throw PolygonHolesError(which, static_cast<int>(a), ring_name(which) + " touches the outer ring (vertex " + std::to_string(a) + ")");
    }
    if (rings_meet(chart[r], chart[0]))
      throw PolygonHolesError(which, -1, ring_name(which) + " crosses or touches the outer ring");
    const CGAL::Polygon_2<K> hole(chart[r].begin(), chart[r].end());
    for (std::size_t s = 1; s < r; ++s) {
      const CGAL::Polygon_2<K> other(chart[s].begin(), chart[s].end());
      if (rings_meet(chart[r], chart[s]) || other.bounded_side(chart[r][0]) != CGAL::ON_UNBOUNDED_SIDE ||
          hole.bounded_side(chart[s][0]) != CGAL::ON_UNBOUNDED_SIDE)
        throw PolygonHolesError(which, -1, ring_name(which) + " and " + ring_name(static_cast<int>(s) - 1) + " overlap or touch");
    }
    if (hole.orientation() == CGAL::COUNTERCLOCKWISE) {
      std::reverse(rings[r].begin(), rings[r].end());
      std::reverse(chart[r].begin(), chart[r].end());
    }
  }

  std::vector<std::vector<glm::dvec3>> result;
  if (rings.size() == 1 && outer_polygon.is_convex() && (!triangles || rings[0].size() == 3)) {
    // Already one convex piece (collinear corners allowed): the cleaned ring as given.
    result.push_back(rings[0]);
    if (!outer_ccw) std::reverse(result[0].begin(), result[0].end());
    return result;
  }

  std::vector<Point> points;
  std::vector<glm::dvec3> vertices;
  std::vector<int> next, prev;
  for (std::size_t r = 0; r < rings.size(); ++r) {
    const int base = static_cast<int>(points.size()), count = static_cast<int>(chart[r].size());
    for (int a = 0; a < count; ++a) {
      points.push_back(chart[r][a]);
      vertices.push_back(rings[r][a]);
      next.push_back(base + (a + 1) % count);
      prev.push_back(base + (a + count - 1) % count);
    }
  }
  std::vector<std::vector<int>> pieces;
  try {
    pieces = convex_pieces_of(points, next, prev, !triangles);
  } catch (const std::bad_alloc&) {
    throw;  // out of memory is not a fault of the rings
  } catch (const std::exception&) {
    // Only reachable if the checks above missed an intersection of constraints.
    throw PolygonHolesError(-1, -1, "the rings intersect");
  }
  for (const std::vector<int>& piece : pieces) {
    std::vector<glm::dvec3> polygon;
    polygon.reserve(piece.size());
    for (int v : piece) polygon.push_back(vertices[v]);
    if (!outer_ccw) std::reverse(polygon.begin(), polygon.end());
    result.push_back(std::move(polygon));
  }
  return result;
}

}  // namespace

std::vector<std::vector<glm::dvec3>> split_polygon_with_holes(const std::vector<glm::dvec3>& outer,
                                                              const std::vector<std::vector<glm::dvec3>>& holes,
                                                              double planarity_tolerance) {
  return split(outer, holes, planarity_tolerance, false);
}

std::vector<std::vector<glm::dvec3>> triangulate_polygon_with_holes(const std::vector<glm::dvec3>& outer,
                                                                    const std::vector<std::vector<glm::dvec3>>& holes) {
  return split(outer, holes, 0.0, true);
}

PolygonHolesSplit split_polygon_with_holes_checked(const std::vector<glm::dvec3>& outer,
                                                   const std::vector<std::vector<glm::dvec3>>& holes,
                                                   double planarity_tolerance) {
  PolygonHolesSplit split;
  try {
    split.pieces = split_polygon_with_holes(outer, holes, planarity_tolerance);
  } catch (const PolygonHolesError& e) {
    split.error = e.what();
    split.ring = e.ring;
    split.vertex = e.vertex;
  }
  return split;
}

std::vector<std::vector<int>> convex_pieces(const std::vector<std::array<double, 2>>& chart,
                                            const std::vector<int>& next, const std::vector<int>& prev, bool merge) {
  std::vector<Point> points;
  points.reserve(chart.size());
  for (const std::array<double, 2>& c : chart) points.emplace_back(c[0], c[1]);
  return convex_pieces_of(points, next, prev, merge);
}

}  // namespace shadow::core
