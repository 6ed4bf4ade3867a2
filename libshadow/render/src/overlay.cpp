// SPDX-License-Identifier: GPL-3.0-or-later
// The overlay of every light's fragments on a face, exactly: the fragments (ShadowResult, the
// exact cells rounded once) are triangulated and intersected with rational arithmetic (GMP), and
// the resulting cells are rounded once. The double-precision overlay this replaces lost or
// doubled pieces where rounding hid an ear or a clip went the wrong way: pinholes in the
// picture (tests/render/test_render.cpp, EveryGroundPixelHasTheColourOfItsExactFragments).
//
// Every cell edge lies on the line of a fragment edge, whose two end points are doubles. A
// vertex is kept as the intersection of two such lines, so its rationals stay a few hundred bits
// however many lights clip it. After rounding, each cell gets every vertex of the face's other
// cells that lies on one of its edges: cells meet vertex to vertex (no T-junctions), which is
// what lets the rasteriser fill the face without cracks.
#include <shadow/render/shaded_mesh.hpp>

#include "geometry/newell_normal.hpp"

#include <gmpxx.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace shadow::render {
namespace {

using Q = mpq_class;

struct QPoint {
  Q x, y;
};

/// A line through two points given in doubles (exact).
struct Line {
  glm::dvec2 a, b;
};

QPoint exact(const glm::dvec2& p) { return {Q(p.x), Q(p.y)}; }

/// Sign of the turn a -> b -> p (> 0: p left of a->b), exact.
int orient(const glm::dvec2& a, const glm::dvec2& b, const QPoint& p) {
  const Q abx = Q(b.x) - Q(a.x), aby = Q(b.y) - Q(a.y);
  const Q det = abx * (p.y - Q(a.y)) - aby * (p.x - Q(a.x));
  return sgn(det);
}

/// The same with `approx`, p rounded to doubles: decided in doubles when the rounding of p and
/// of the arithmetic cannot change the sign, exactly otherwise.
int orient(const glm::dvec2& a, const glm::dvec2& b, const QPoint& p, const glm::dvec2& approx) {
  const double abx = b.x - a.x, aby = b.y - a.y;
  const double l = abx * (approx.y - a.y), r = aby * (approx.x - a.x);
  const double det = l - r;
  const double bound = 1e-14 * (std::abs(l) + std::abs(r) +
                                (std::abs(abx) + std::abs(aby)) * (std::abs(approx.x) + std::abs(approx.y)));
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return orient(a, b, p);
}

/// Sign of the turn a -> b -> c for doubles, exact: a filtered double first, GMP when close.
int orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  const double l = (b.x - a.x) * (c.y - a.y), r = (b.y - a.y) * (c.x - a.x);
  const double det = l - r;
  const double bound = 1e-15 * (std::abs(l) + std::abs(r));
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return orient(a, b, exact(c));
}

/// Where lines `m` and `n` cross (they are not parallel).
QPoint intersection(const Line& m, const Line& n) {
  const QPoint p = exact(m.a), p2 = exact(m.b), q = exact(n.a), q2 = exact(n.b);
  const Q dx = p2.x - p.x, dy = p2.y - p.y, ex = q2.x - q.x, ey = q2.y - q.y;
  const Q denominator = dx * ey - dy * ex;
  const Q t = ((q.x - p.x) * ey - (q.y - p.y) * ex) / denominator;
  return {p.x + t * dx, p.y + t * dy};
}

/// A convex cell: vertex i runs to vertex i + 1 along line edges[i].
struct Cell {
  std::vector<QPoint> vertices;
  std::vector<Line> edges;
  std::vector<glm::dvec2> approx;  // the vertices rounded, for filters
  std::vector<bool> lit;
  glm::dvec2 lo, hi;  // bounding box, rounded outward enough for a filter
};

void bound(Cell& cell) {
  cell.lo = glm::dvec2(1e300);
  cell.hi = glm::dvec2(-1e300);
  cell.approx.clear();
  for (const QPoint& p : cell.vertices) {
    const glm::dvec2 d(p.x.get_d(), p.y.get_d());
    cell.approx.push_back(d);
    cell.lo = glm::min(cell.lo, d);
    cell.hi = glm::max(cell.hi, d);
  }
  const double pad = 1e-9 * std::max({1.0, std::abs(cell.lo.x), std::abs(cell.lo.y), std::abs(cell.hi.x),
                                      std::abs(cell.hi.y)});
  cell.lo -= pad;
  cell.hi += pad;
}

/// Twice the signed area, exact.
Q twice_area(const std::vector<QPoint>& polygon) {
  Q sum = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const QPoint& p = polygon[i];
    const QPoint& q = polygon[(i + 1) % polygon.size()];
    sum += p.x * q.y - p.y * q.x;
  }
  return sum;
}

/// True when the cell's area is positive: decided in doubles when clear, exactly otherwise.
bool positive_area(const Cell& cell) {
  double sum = 0.0, magnitude = 0.0;
  for (std::size_t i = 0; i < cell.approx.size(); ++i) {
    const glm::dvec2& p = cell.approx[i];
    const glm::dvec2& q = cell.approx[(i + 1) % cell.approx.size()];
    sum += p.x * q.y - p.y * q.x;
    magnitude += std::abs(p.x * q.y) + std::abs(p.y * q.x);
  }
  if (sum > 1e-12 * magnitude) return true;
  if (sum < -1e-12 * magnitude) return false;
  return sgn(twice_area(cell.vertices)) > 0;
}

/// The part of `cell` left of line `line` (exact Sutherland–Hodgman step).
void clip(Cell& cell, const Line& line) {
  const std::size_t n = cell.vertices.size();
  std::vector<int> side(n);
  bool any_out = false;
  for (std::size_t i = 0; i < n; ++i) {
    side[i] = orient(line.a, line.b, cell.vertices[i], cell.approx[i]);
    any_out = any_out || side[i] < 0;
  }
  if (!any_out) return;
  Cell out;
  std::vector<char> on_line;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    if (side[i] >= 0) {
      out.vertices.push_back(cell.vertices[i]);
      out.edges.push_back(cell.edges[i]);  // the edge from here keeps its line...
      on_line.push_back(side[i] == 0);
    }
    if ((side[i] > 0 && side[j] < 0) || (side[i] < 0 && side[j] > 0)) {
      out.vertices.push_back(intersection(cell.edges[i], line));
      out.edges.push_back(side[i] > 0 ? line : cell.edges[i]);
      on_line.push_back(1);
    }
  }
  // ...unless it runs from a point on the line to the next one: then it runs along the line.
  for (std::size_t i = 0; i < out.vertices.size(); ++i)
    if (on_line[i] && on_line[(i + 1) % out.vertices.size()]) out.edges[i] = line;
  cell.vertices = std::move(out.vertices);
  cell.edges = std::move(out.edges);
  cell.approx.clear();
  for (const QPoint& p : cell.vertices) cell.approx.emplace_back(p.x.get_d(), p.y.get_d());
}

/// Ear clipping of a simple polygon (doubles, counter-clockwise in the chart) with exact turns.
/// Collinear corners are dropped; if no ear is found (a polygon made non-simple by rounding),
/// the rest is fanned.
std::vector<std::array<glm::dvec2, 3>> triangulate(std::vector<glm::dvec2> p) {
  std::vector<std::array<glm::dvec2, 3>> out;
  // A vertex in the closed triangle, its boundary included, spoils the ear: one on the
  // diagonal would leave the rest of the polygon touching itself, and a later ear could then
  // cover part of the outside (seen on the default scene's lamp-lit ground).
  auto in_closed = [](const glm::dvec2& q, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    return orient(a, b, q) >= 0 && orient(b, c, q) >= 0 && orient(c, a, q) >= 0;
  };
  while (p.size() > 3) {
    const std::size_t n = p.size();
    bool clipped = false;
    for (std::size_t i = 0; i < n && !clipped; ++i) {
      const glm::dvec2 a = p[(i + n - 1) % n], b = p[i], c = p[(i + 1) % n];
      const int turn = orient(a, b, c);
      if (turn < 0) continue;  // reflex corner
      if (turn > 0) {
        bool empty = true;
        for (std::size_t j = 0; j < n && empty; ++j) {
          if (j == i || j == (i + n - 1) % n || j == (i + 1) % n) continue;
          if (p[j] == a || p[j] == b || p[j] == c) continue;
          if (in_closed(p[j], a, b, c)) empty = false;
        }
        if (!empty) continue;
        out.push_back({a, b, c});
      }
      p.erase(p.begin() + static_cast<std::ptrdiff_t>(i));  // an ear, or a collinear corner
      clipped = true;
    }
    if (!clipped) break;
  }
  for (std::size_t i = 1; i + 1 < p.size(); ++i)
    if (orient(p[0], p[i], p[i + 1]) > 0) out.push_back({p[0], p[i], p[i + 1]});
  return out;
}

/// The face's chart: two of x, y, z (the normal's largest component dropped), in the order
/// that keeps the face's front counter-clockwise, and the plane to lift points back.
struct Chart {
  int axis = 2;
  int u = 0, v = 1;
  glm::dvec3 normal{0.0, 0.0, 1.0};
  double offset = 0.0;  // normal . x on the plane

  glm::dvec2 flat(const glm::dvec3& p) const { return {p[u], p[v]}; }
  glm::dvec3 lift(const glm::dvec2& q) const {
    glm::dvec3 p(0.0);
    p[u] = q.x;
    p[v] = q.y;
    p[axis] = (offset - normal[u] * q.x - normal[v] * q.y) / normal[axis];
    return p;
  }
};

Chart chart_of(const Face& face) {
  Chart chart;
  const glm::dvec3 n = geometry::newell_normal(face.vertices);
  const glm::dvec3 a = glm::abs(n);
  chart.axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  chart.u = (chart.axis + 1) % 3;
  chart.v = (chart.axis + 2) % 3;
  if (n[chart.axis] < 0) std::swap(chart.u, chart.v);  // keep the front counter-clockwise
  chart.normal = n;
  glm::dvec3 mean(0.0);
  for (const glm::dvec3& p : face.vertices) mean += p / static_cast<double>(face.vertices.size());
  chart.offset = glm::dot(n, mean);
  return chart;
}

struct Less2 {
  bool operator()(const glm::dvec2& a, const glm::dvec2& b) const { return a.x < b.x || (a.x == b.x && a.y < b.y); }
};

/// Inserts into each cell's edges the vertices of the face's other cells that lie on them
/// (within rounding), so that neighbouring cells share their boundary points.
void close_t_junctions(std::vector<std::vector<glm::dvec2>>& cells) {
  std::vector<glm::dvec2> points;
  for (const auto& cell : cells) points.insert(points.end(), cell.begin(), cell.end());
  std::sort(points.begin(), points.end(), Less2{});
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.empty()) return;
  // A uniform grid over the points' box for the look-ups.
  glm::dvec2 lo(1e300), hi(-1e300);
  for (const glm::dvec2& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const int side = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(points.size()))));
  const glm::dvec2 size = glm::max(hi - lo, glm::dvec2(1e-300));
  auto cell_of = [&](double t, double l, double s) {
    return std::clamp(static_cast<int>((t - l) / s * side), 0, side - 1);
  };
  std::vector<std::vector<std::size_t>> grid(static_cast<std::size_t>(side) * static_cast<std::size_t>(side));
  for (std::size_t i = 0; i < points.size(); ++i)
    grid[static_cast<std::size_t>(cell_of(points[i].y, lo.y, size.y)) * side +
         static_cast<std::size_t>(cell_of(points[i].x, lo.x, size.x))]
        .push_back(i);
  const double scale = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(hi.x), std::abs(hi.y), 1e-300});

  for (auto& cell : cells) {
    std::vector<glm::dvec2> out;
    for (std::size_t i = 0; i < cell.size(); ++i) {
      const glm::dvec2 a = cell[i], b = cell[(i + 1) % cell.size()];
      out.push_back(a);
      const glm::dvec2 d = b - a;
      const double length2 = glm::dot(d, d);
      if (!(length2 > 0.0)) continue;
      // Off the line by no more than the rounding of a vertex (a few ulps of the coordinates).
      const double tolerance = 64.0 * 2.2e-16 * scale;
      std::vector<std::pair<double, glm::dvec2>> on_edge;
      const int x0 = cell_of(std::min(a.x, b.x) - tolerance, lo.x, size.x);
      const int x1 = cell_of(std::max(a.x, b.x) + tolerance, lo.x, size.x);
      const int y0 = cell_of(std::min(a.y, b.y) - tolerance, lo.y, size.y);
      const int y1 = cell_of(std::max(a.y, b.y) + tolerance, lo.y, size.y);
      for (int gy = y0; gy <= y1; ++gy)
        for (int gx = x0; gx <= x1; ++gx)
          for (std::size_t k : grid[static_cast<std::size_t>(gy) * side + static_cast<std::size_t>(gx)]) {
            const glm::dvec2& p = points[k];
            if (p == a || p == b) continue;
            const double t = glm::dot(p - a, d) / length2;
            if (!(t > 0.0 && t < 1.0)) continue;
            const double off = std::abs(d.x * (p.y - a.y) - d.y * (p.x - a.x)) / std::sqrt(length2);
            if (off <= tolerance) on_edge.emplace_back(t, p);
          }
      std::sort(on_edge.begin(), on_edge.end(), [](const auto& m, const auto& n) { return m.first < n.first; });
      for (const auto& [t, p] : on_edge) out.push_back(p);
    }
    cell.swap(out);
  }
}

}  // namespace

std::vector<OverlayCell> overlay_fragments(const Scene& scene, const ShadowResult& result) {
  const std::size_t light_count = scene.lights.size();
  // Triangles of every face, per light, in the face's chart.
  std::map<std::size_t, std::vector<std::vector<std::pair<std::array<glm::dvec2, 3>, bool>>>> by_face;
  std::map<std::size_t, Chart> charts;
  for (const Fragment& f : result.fragments) {
    if (f.face_id >= scene.faces.size() || f.light_id >= light_count || f.polygon.size() < 3) continue;
    auto& lights = by_face[f.face_id];
    if (lights.empty()) {
      lights.resize(light_count);
      charts[f.face_id] = chart_of(scene.faces[f.face_id]);
    }
    const Chart& chart = charts[f.face_id];
    std::vector<glm::dvec2> polygon;
    for (const glm::dvec3& p : f.polygon) polygon.push_back(chart.flat(p));
    for (const auto& t : triangulate(std::move(polygon))) lights[f.light_id].emplace_back(t, f.lit);
  }

  std::vector<OverlayCell> cells;
  for (auto& [face_id, lights] : by_face) {
    std::vector<Cell> current;
    for (std::size_t k = 0; k < light_count; ++k) {
      const auto& triangles = lights[k];
      if (k == 0) {
        for (const auto& [t, lit] : triangles) {
          Cell cell;
          for (int i = 0; i < 3; ++i) {
            cell.vertices.push_back(exact(t[i]));
            cell.edges.push_back({t[i], t[(i + 1) % 3]});
          }
          cell.lit.assign(light_count, false);
          cell.lit[0] = lit;
          bound(cell);
          current.push_back(std::move(cell));
        }
        continue;
      }
      std::vector<Cell> next;
      for (const Cell& cell : current) {
        for (const auto& [t, lit] : triangles) {
          const glm::dvec2 lo = glm::min(t[0], glm::min(t[1], t[2])), hi = glm::max(t[0], glm::max(t[1], t[2]));
          if (lo.x > cell.hi.x || hi.x < cell.lo.x || lo.y > cell.hi.y || hi.y < cell.lo.y) continue;
          // Whole cell outside an edge of the triangle: nothing in common.
          bool apart = false;
          for (int i = 0; i < 3 && !apart; ++i) {
            apart = true;
            for (std::size_t v = 0; v < cell.vertices.size() && apart; ++v)
              apart = orient(t[i], t[(i + 1) % 3], cell.vertices[v], cell.approx[v]) <= 0;
          }
          if (apart) continue;
          Cell piece = cell;
          for (int i = 0; i < 3 && piece.vertices.size() >= 3; ++i) clip(piece, {t[i], t[(i + 1) % 3]});
          if (piece.vertices.size() < 3 || !positive_area(piece)) continue;
          piece.lit[k] = lit;
          bound(piece);
          next.push_back(std::move(piece));
        }
      }
      current.swap(next);
    }

    // Round once, then let neighbours share their boundary points.
    const Chart& chart = charts[face_id];
    // The face's own corners stay exactly where they are (shared with the neighbouring faces).
    std::map<glm::dvec2, glm::dvec3, Less2> corners;
    for (const glm::dvec3& p : scene.faces[face_id].vertices) corners.emplace(chart.flat(p), p);
    std::vector<std::vector<glm::dvec2>> rounded;
    std::vector<const Cell*> kept;
    for (const Cell& cell : current) {
      std::vector<glm::dvec2> polygon;
      for (const QPoint& p : cell.vertices) {
        const glm::dvec2 d(p.x.get_d(), p.y.get_d());
        if (polygon.empty() || polygon.back() != d) polygon.push_back(d);
      }
      while (polygon.size() > 1 && polygon.back() == polygon.front()) polygon.pop_back();
      if (polygon.size() < 3) continue;
      rounded.push_back(std::move(polygon));
      kept.push_back(&cell);
    }
    close_t_junctions(rounded);
    for (std::size_t i = 0; i < rounded.size(); ++i) {
      OverlayCell cell;
      cell.face_id = face_id;
      for (const glm::dvec2& q : rounded[i]) {
        const auto corner = corners.find(q);
        cell.polygon.push_back(corner != corners.end() ? corner->second : chart.lift(q));
      }
      cell.lit = kept[i]->lit;
      cells.push_back(std::move(cell));
    }
  }
  return cells;
}

}  // namespace shadow::render
