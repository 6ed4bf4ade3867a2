// SPDX-License-Identifier: GPL-3.0-or-later
// cut_openings (exact/face_shape.hpp): a wall minus its windows and doors, exactly. The openings
// and the wall are charted on one axis and subtracted as exact polygon sets; the rings that come
// out are made of input points only (openings lie inside the wall and do not cross each other),
// so each chart point is mapped back to the 3D input vertex it came from.
#include "exact/face_shape.hpp"

#include "exact/kernel.hpp"
#include "geometry/newell_normal.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <list>
#include <map>
#include <utility>

namespace shadow::detail {
namespace {

using shadow::exact::Point2;
using shadow::exact::Polygon2;
using shadow::exact::PolygonSet2;
using shadow::exact::PolygonWithHoles2;

int dominant_axis(const glm::dvec3& surface_first, const std::vector<glm::dvec3>& surface) {
  std::vector<glm::dvec3> ring = surface;
  const glm::dvec3 n = geometry::newell_normal(ring, surface_first);
  const glm::dvec3 a(std::abs(n.x), std::abs(n.y), std::abs(n.z));
  if (a.x >= a.y && a.x >= a.z) return 0;
  return a.y >= a.z ? 1 : 2;
}

std::pair<double, double> chart_of(const glm::dvec3& v, int k) {
  switch (k) {
    case 0: return {v.y, v.z};
    case 1: return {v.z, v.x};
    default: return {v.x, v.y};
  }
}

/// The ring as a counter-clockwise chart polygon; false when it has zero area or is not simple.
bool chart_polygon(const std::vector<glm::dvec3>& ring, int k, Polygon2& out, bool& was_clockwise) {
  out.clear();
  for (const glm::dvec3& v : ring) {
    const auto [i, j] = chart_of(v, k);
    out.push_back(Point2(i, j));
  }
  if (out.size() < 3 || !out.is_simple()) return false;
  const CGAL::Orientation orientation = out.orientation();
  if (orientation == CGAL::COLLINEAR) return false;
  was_clockwise = orientation == CGAL::CLOCKWISE;
  if (was_clockwise) out.reverse_orientation();
  return true;
}

/// Every piece of `set` is a sliver no thicker than `tolerance` on average: twice its area over
/// its perimeter (the width of a long thin strip) is at most `tolerance`. In doubles: a slack
/// test of thickness, not a predicate.
bool thin(const PolygonSet2& set, double tolerance) {
  std::list<PolygonWithHoles2> parts;
  set.polygons_with_holes(std::back_inserter(parts));
  auto perimeter = [](const Polygon2& ring) {
    double sum = 0.0;
    for (auto e = ring.edges_begin(); e != ring.edges_end(); ++e)
      sum += std::sqrt(CGAL::to_double(e->squared_length()));
    return sum;
  };
  for (const PolygonWithHoles2& part : parts) {
    double area = CGAL::to_double(part.outer_boundary().area());
    double length = perimeter(part.outer_boundary());
    for (auto hole = part.holes_begin(); hole != part.holes_end(); ++hole) {
      area -= std::abs(CGAL::to_double(hole->area()));
      length += perimeter(*hole);
    }
    if (!(2.0 * area <= tolerance * length)) return false;
  }
  return true;
}

}  // namespace

OpeningsCut cut_openings(const std::vector<glm::dvec3>& surface,
                         const std::vector<std::vector<glm::dvec3>>& openings, double tolerance) {
  OpeningsCut cut;
  if (surface.size() < 3) {
    cut.surface_not_simple = true;
    return cut;
  }
  const int k = dominant_axis(surface.front(), surface);
  Polygon2 outer;
  bool surface_clockwise = false;
  if (!chart_polygon(surface, k, outer, surface_clockwise)) {
    cut.surface_not_simple = true;
    return cut;
  }
  std::vector<Polygon2> holes(openings.size());
  for (std::size_t o = 0; o < openings.size(); ++o) {
    bool ignored = false;
    if (!chart_polygon(openings[o], k, holes[o], ignored)) {
      cut.not_simple = static_cast<int>(o);
      return cut;
    }
  }
  // Inside: nothing of the opening is left once the surface is taken away (touching is fine).
  for (std::size_t o = 0; o < holes.size(); ++o) {
    PolygonSet2 rest(holes[o]);
    rest.difference(outer);
    if (!rest.is_empty()) {
      if (tolerance > 0 && thin(rest, tolerance)) {
        cut.within_tolerance = true;
        continue;
      }
      cut.outside = static_cast<int>(o);
      return cut;
    }
  }
  // Regularised intersections: openings that only share edges or corners do not overlap.
  for (std::size_t a = 0; a < holes.size(); ++a)
    for (std::size_t b = a + 1; b < holes.size(); ++b) {
      PolygonSet2 both(holes[a]);
      both.intersection(holes[b]);
      if (!both.is_empty()) {
        if (tolerance > 0 && thin(both, tolerance)) {
          cut.within_tolerance = true;
          continue;
        }
        cut.overlap_first = static_cast<int>(a);
        cut.overlap_second = static_cast<int>(b);
        return cut;
      }
    }
  PolygonSet2 left(outer);
  for (const Polygon2& hole : holes) left.difference(hole);

  // Chart point -> input vertex (the surface's own vertices win over the openings' copies).
  std::map<std::pair<double, double>, glm::dvec3> vertex_of;
  for (const glm::dvec3& v : surface) vertex_of.emplace(chart_of(v, k), v);
  for (const auto& opening : openings)
    for (const glm::dvec3& v : opening) vertex_of.emplace(chart_of(v, k), v);
  // A point that is not an input point cannot arise from openings inside the surface that do not
  // cross; should one appear anyway, it is put on the surface's plane in doubles.
  const glm::dvec3 origin = surface.front();
  const glm::dvec3 normal = geometry::newell_normal(surface, origin);
  auto to_3d = [&](const Point2& p) {
    const std::pair<double, double> key(CGAL::to_double(p.x()), CGAL::to_double(p.y()));
    const auto found = vertex_of.find(key);
    if (found != vertex_of.end()) return found->second;
    glm::dvec3 v(0.0);
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    v[i] = key.first;
    v[j] = key.second;
    v[k] = origin[k] - (normal[i] * (v[i] - origin[i]) + normal[j] * (v[j] - origin[j])) / normal[k];
    return v;
  };
  auto ring_3d = [&](const Polygon2& ring, bool reverse) {
    std::vector<glm::dvec3> out;
    for (auto p = ring.vertices_begin(); p != ring.vertices_end(); ++p) out.push_back(to_3d(*p));
    if (reverse) std::reverse(out.begin(), out.end());
    return out;
  };
  std::list<PolygonWithHoles2> regions;
  left.polygons_with_holes(std::back_inserter(regions));
  for (const PolygonWithHoles2& region : regions) {
    std::vector<std::vector<glm::dvec3>> rings;
    // CGAL gives outer boundaries counter-clockwise and holes clockwise in the chart; a surface
    // that runs clockwise in the chart gets every ring reversed, so it keeps facing its way.
    rings.push_back(ring_3d(region.outer_boundary(), surface_clockwise));
    for (auto hole = region.holes_begin(); hole != region.holes_end(); ++hole)
      rings.push_back(ring_3d(*hole, surface_clockwise));
    cut.regions.push_back(std::move(rings));
  }
  return cut;
}

}  // namespace shadow::detail
