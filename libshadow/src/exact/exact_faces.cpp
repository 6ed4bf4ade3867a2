// SPDX-License-Identifier: GPL-3.0-or-later
// Exact face preparation: planes, charts, convex pieces, and the exact checks of validation.
#include "exact/exact_faces.hpp"

#include "exact/exact_checks.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Partition_traits_2.h>
#include <CGAL/partition_2.h>

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>

namespace shadow::exact {
namespace {

/// 2 x the signed area vector of a closed polygon (Newell's method), exact.
Vector3 exact_newell_normal(const std::vector<Point3>& p) {
  FT nx = 0, ny = 0, nz = 0;
  const std::size_t n = p.size();
  for (std::size_t a = 0; a < n; ++a) {
    const Point3& u = p[a];
    const Point3& v = p[(a + 1) % n];
    nx += (u.y() - v.y()) * (u.z() + v.z());
    ny += (u.z() - v.z()) * (u.x() + v.x());
    nz += (u.x() - v.x()) * (u.y() + v.y());
  }
  return Vector3(nx, ny, nz);
}

int dominant_axis(const Vector3& n) {
  const FT ax = CGAL::abs(n.x()), ay = CGAL::abs(n.y()), az = CGAL::abs(n.z());
  if (ax >= ay && ax >= az) return 0;
  if (ay >= az) return 1;
  return 2;
}

std::vector<Point3> exact_points(const std::vector<glm::dvec3>& vertices) {
  std::vector<Point3> points;
  points.reserve(vertices.size());
  for (const glm::dvec3& v : vertices) points.push_back(to_exact(v));
  return points;
}

/// Removes vertices exactly collinear with their neighbours, repeatedly, so that every
/// remaining vertex is a real turn (the faces are simple: validated before).
template <class Point>
std::vector<int> drop_collinear(std::vector<int> ring, const std::vector<Point>& chart) {
  bool changed = true;
  while (changed && ring.size() >= 3) {
    changed = false;
    for (std::size_t a = 0; a < ring.size() && ring.size() >= 3; ++a) {
      const std::size_t n = ring.size();
      const Point& prev = chart[ring[(a + n - 1) % n]];
      const Point& cur = chart[ring[a]];
      const Point& next = chart[ring[(a + 1) % n]];
      // On a simple polygon a collinear vertex is "straight on": it adds no area.
      if (CGAL::collinear(prev, cur, next)) {
        ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(a));
        changed = true;
        --a;
      }
    }
  }
  return ring;
}

template <class Point>
bool is_strictly_convex_ccw(const std::vector<int>& ring, const std::vector<Point>& chart) {
  const std::size_t n = ring.size();
  for (std::size_t a = 0; a < n; ++a) {
    if (CGAL::orientation(chart[ring[a]], chart[ring[(a + 1) % n]], chart[ring[(a + 2) % n]]) !=
        CGAL::LEFT_TURN)
      return false;
  }
  return true;
}

}  // namespace

FacePrep prepare_face(const std::vector<glm::dvec3>& vertices) {
  // Everything here is decided with Epick's exact predicates on the input doubles (static and
  // interval filters, then an exact fallback): far cheaper than Epeck's lazy constructions,
  // which would have to evaluate exactly every test that comes out zero (planarity tests do).
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  FacePrep prep;
  const std::size_t count = vertices.size();
  glm::dvec3 newell(0.0);
  for (std::size_t a = 0; a < count; ++a) {
    const glm::dvec3 u = vertices[a] - vertices[0], v = vertices[(a + 1) % count] - vertices[0];
    newell += glm::dvec3((u.y - v.y) * (u.z + v.z), (u.z - v.z) * (u.x + v.x), (u.x - v.x) * (u.y + v.y));
  }
  // The dominant axis only needs to be a good chart direction, not exact: its component is at
  // least |n| / sqrt(3), far above rounding error for any face validation accepts.
  const glm::dvec3 an = glm::abs(newell);
  int k = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
  if (!(an[k] > 0) || !std::isfinite(an[k])) {
    // Under- or overflow (coordinates beyond 1e+-150): decide exactly.
    const Vector3 exact_normal = exact_newell_normal(exact_points(vertices));
    if (exact_normal == CGAL::NULL_VECTOR) {
      prep.degenerate = true;
      return prep;
    }
    k = dominant_axis(exact_normal);
  }
  prep.axis = k;
  const int i = chart_i(k), j = chart_j(k);
  std::vector<K::Point_2> chart;
  chart.reserve(count);
  for (const glm::dvec3& v : vertices) chart.emplace_back(v[i], v[j]);

  std::vector<int> ring(count);
  for (std::size_t a = 0; a < count; ++a) ring[a] = static_cast<int>(a);
  ring = drop_collinear(std::move(ring), chart);
  if (ring.size() < 3) {
    prep.degenerate = true;
    return prep;
  }
  // The lexicographically smallest vertex of a simple polygon is a strict convex corner: its
  // turn gives the polygon's orientation in the chart, i.e. the exact sign of n_k.
  std::size_t n = ring.size();
  std::size_t lowest = 0;
  for (std::size_t a = 1; a < n; ++a)
    if (CGAL::compare_xy(chart[ring[a]], chart[ring[lowest]]) == CGAL::SMALLER) lowest = a;
  const CGAL::Orientation turn =
      CGAL::orientation(chart[ring[(lowest + n - 1) % n]], chart[ring[lowest]], chart[ring[(lowest + 1) % n]]);
  prep.flipped = turn == CGAL::RIGHT_TURN;
  if (prep.flipped) {
    std::reverse(ring.begin(), ring.end());
    lowest = n - 1 - lowest;
  }
  prep.chart_ring = ring;
  prep.corner = {ring[(lowest + n - 1) % n], ring[lowest], ring[(lowest + 1) % n]};

  auto point3 = [&](int v) { return K::Point_3(vertices[v].x, vertices[v].y, vertices[v].z); };
  const K::Point_3 c0 = point3(prep.corner[1]), c1 = point3(prep.corner[2]), c2 = point3(prep.corner[0]);
  prep.exactly_planar = true;
  for (std::size_t v = 0; v < count && prep.exactly_planar; ++v)
    prep.exactly_planar = CGAL::orientation(c0, c1, c2, point3(static_cast<int>(v))) == CGAL::COPLANAR;

  // Chart bounding box: chart coordinates are input doubles, so this box is exact.
  prep.chart_min = {vertices[ring[0]][i], vertices[ring[0]][j]};
  prep.chart_max = prep.chart_min;
  for (int v : ring) {
    prep.chart_min[0] = std::min(prep.chart_min[0], vertices[v][i]);
    prep.chart_min[1] = std::min(prep.chart_min[1], vertices[v][j]);
    prep.chart_max[0] = std::max(prep.chart_max[0], vertices[v][i]);
    prep.chart_max[1] = std::max(prep.chart_max[1], vertices[v][j]);
  }
  if (n == 4) {
    prep.chart_is_box = std::all_of(ring.begin(), ring.end(), [&](int v) {
      const bool on_x = vertices[v][i] == prep.chart_min[0] || vertices[v][i] == prep.chart_max[0];
      const bool on_y = vertices[v][j] == prep.chart_min[1] || vertices[v][j] == prep.chart_max[1];
      return on_x && on_y;
    });
  }

  if (is_strictly_convex_ccw(ring, chart)) {
    prep.convex_pieces.push_back(ring);
  } else {
    // Hertel-Mehlhorn partition: diagonals only, so pieces reuse the face's own vertices.
    using Traits = CGAL::Partition_traits_2<K>;
    std::vector<Traits::Point_2> ring_points;
    std::map<std::pair<double, double>, int> index_of;
    for (int v : ring) {
      ring_points.push_back(chart[v]);
      index_of.emplace(std::make_pair(chart[v].x(), chart[v].y()), v);
    }
    std::vector<Traits::Polygon_2> pieces;
    CGAL::approx_convex_partition_2(ring_points.begin(), ring_points.end(),
                                    std::back_inserter(pieces), Traits());
    for (const Traits::Polygon_2& piece : pieces) {
      std::vector<int> indices;
      for (auto it = piece.vertices_begin(); it != piece.vertices_end(); ++it)
        indices.push_back(index_of.at({it->x(), it->y()}));
      prep.convex_pieces.push_back(std::move(indices));
    }
  }
  return prep;
}

ExactFace make_exact_face(const std::vector<glm::dvec3>& vertices, const FacePrep& prep) {
  ExactFace face;
  const int k = prep.axis;
  face.vertices = exact_points(vertices);
  if (prep.exactly_planar) {
    const auto [prev, corner, next] = prep.corner;
    // Counter-clockwise in the chart: this cross product has a positive k component.
    Vector3 n = CGAL::cross_product(face.vertices[next] - face.vertices[corner],
                                    face.vertices[prev] - face.vertices[corner]);
    face.normal = prep.flipped ? -n : n;
    face.offset = -(face.normal * (face.vertices[corner] - CGAL::ORIGIN));
  } else {
    // Within the planarity tolerance but not exact: use the plane through the centroid with
    // the Newell normal and lift every vertex onto it along the chart axis. The chart
    // coordinates stay the input doubles (docs/numeric-contract.md).
    face.normal = exact_newell_normal(face.vertices);
    FT sx = 0, sy = 0, sz = 0;
    for (const Point3& p : face.vertices) {
      sx += p.x();
      sy += p.y();
      sz += p.z();
    }
    const FT count = static_cast<int>(face.vertices.size());
    face.offset = -(face.normal.x() * sx + face.normal.y() * sy + face.normal.z() * sz) / count;
    for (Point3& p : face.vertices) p = lift(to_chart(p, k), face, k);
  }
  for (int v : prep.chart_ring) face.chart.push_back(to_chart(face.vertices[v], k));
  face.chart_area = face.chart.area();
  const FT nk = face.normal[k];
  face.area_scale_squared = face.normal.squared_length() / (nk * nk);
  return face;
}

Point3 lift(const Point2& c, const ExactFace& face, int k) {
  const int i = chart_i(k), j = chart_j(k);
  const FT xk = -(face.offset + face.normal[i] * c.x() + face.normal[j] * c.y()) / face.normal[k];
  FT xyz[3];
  xyz[i] = c.x();
  xyz[j] = c.y();
  xyz[k] = xk;
  return Point3(xyz[0], xyz[1], xyz[2]);
}

double area_3d(const FT& chart_area, const FT& area_scale_squared) {
  if (CGAL::is_zero(chart_area)) return 0.0;
  return sqrt_to_double(chart_area * chart_area * area_scale_squared);
}

}  // namespace shadow::exact

namespace shadow::detail {

FaceShape classify_face_shape(const std::vector<glm::dvec3>& vertices) {
  using namespace shadow::exact;
  std::vector<Point3> points;
  for (const glm::dvec3& v : vertices) points.push_back(to_exact(v));
  bool all_collinear = true;
  for (std::size_t a = 2; a < points.size() && all_collinear; ++a)
    all_collinear = CGAL::collinear(points[0], points[1], points[a]);
  if (all_collinear) return FaceShape::ZeroArea;
  const Vector3 normal = exact_newell_normal(points);
  if (normal == CGAL::NULL_VECTOR) return FaceShape::SelfIntersecting;  // e.g. a symmetric bow-tie
  const int k = dominant_axis(normal);
  Polygon2 chart;
  for (const Point3& p : points) chart.push_back(to_chart(p, k));
  return chart.is_simple() ? FaceShape::Simple : FaceShape::SelfIntersecting;
}

}  // namespace shadow::detail
