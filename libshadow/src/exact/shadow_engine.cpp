// SPDX-License-Identifier: GPL-3.0-or-later
// The exact shadow engine (Atherton-Weiler-Greenberg, made exact).
//
// For a receiving face P that faces the light, a point X of P is in shadow exactly when the
// open segment from X to the light meets another face. That segment lies in the open slab
// between P's plane and the light, so
//
//   shadow(P) = P  intersected with  union over Q of  project_P(Q  clipped to that slab),
//
// where project_P is the projection from the light onto P's plane (Blinn's matrix for P's
// plane). No depth order is needed; cyclic overlap and interpenetration need no special case.
// Clipping Q also to the pyramid (point light) or prism (directional light) over P's chart
// bounding box keeps the projection finite and the union small. Everything is done with exact
// rationals (Epeck) in P's 2D chart; doubles appear only in culling (conservatively) and at
// the output.
#include "exact/exact_faces.hpp"
#include "exact/parallel.hpp"

#include <shadow/shadows.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_triangulation_decomposition_2.h>
#include <CGAL/convex_hull_2.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <map>
#include <optional>
#include <set>
#include <tuple>
#include <stdexcept>
#include <string>

namespace shadow {

const FaceLighting* ShadowResult::find(std::size_t face_id, std::size_t light_id) const {
  // `lighting` is sorted by (face_id, light_id).
  auto it = std::lower_bound(lighting.begin(), lighting.end(), std::make_pair(face_id, light_id),
                             [](const FaceLighting& l, const std::pair<std::size_t, std::size_t>& key) {
                               return std::make_pair(l.face_id, l.light_id) < key;
                             });
  if (it == lighting.end() || it->face_id != face_id || it->light_id != light_id) return nullptr;
  return &*it;
}

namespace exact {
namespace {

// ---------------------------------------------------------------------------------------------
// Culling in double precision. Every test here is conservative: it rejects an occluder only
// when it is certainly (by a margin far above rounding error) outside the receiver's slab,
// prism or pyramid. Whatever passes is decided exactly.
// ---------------------------------------------------------------------------------------------

/// A face in a local frame (scene centre subtracted) with a unit normal, for culling.
struct CullFace {
  std::size_t first = 0, count = 0;  ///< range in CullScene::vertices
  glm::dvec3 normal{0.0};            ///< unit normal (front side)
  double offset = 0.0;               ///< plane: normal . p + offset = 0 (local frame)
};

struct CullScene {
  glm::dvec3 origin{0.0};
  double diameter = 1.0;
  std::vector<glm::dvec3> vertices;  ///< local frame
  std::vector<CullFace> faces;
};

/// A unit vector along v for any finite non-zero v, even when |v|^2 under- or overflows
/// (to_light = (1e-200, 0, 1e-200) is a valid direction).
glm::dvec3 unit(glm::dvec3 v) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  return glm::normalize(v / m);
}

/// An affine function on local-frame points with the margin below which its sign is unsure.
struct DoubleAffine {
  glm::dvec3 a{0.0};
  double b = 0.0;
  double tolerance = 0.0;
  [[nodiscard]] double operator()(const glm::dvec3& p) const { return glm::dot(a, p) + b; }
};

/// Uniform grid over the faces' bounding boxes in light space (the plane orthogonal to a
/// directional light): faces whose boxes do not overlap cannot shadow each other.
class LightSpaceGrid {
 public:
  LightSpaceGrid(const CullScene& scene, const std::vector<FacePrep>& prep, glm::dvec3 to_light) {
    const glm::dvec3 d = unit(to_light);
    const glm::dvec3 helper = std::abs(d.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    u_ = glm::normalize(glm::cross(d, helper));
    v_ = glm::cross(d, u_);
    const std::size_t n = scene.faces.size();
    boxes_.assign(n, Box{});
    Box all{};
    bool any = false;
    for (std::size_t f = 0; f < n; ++f) {
      if (prep[f].degenerate) continue;
      boxes_[f] = box_of(scene, scene.faces[f]);
      all = any ? merge(all, boxes_[f]) : boxes_[f];
      any = true;
    }
    margin_ = 1e-9 * scene.diameter;
    origin_ = {all[0] - margin_, all[1] - margin_};
    const double width = std::max(all[2] - all[0], 0.0) + 2 * margin_;
    const double height = std::max(all[3] - all[1], 0.0) + 2 * margin_;
    // About one cell per face, so that a typical query touches a handful of cells.
    const double cells_wanted = std::max<double>(1.0, static_cast<double>(n));
    cell_ = std::max(std::sqrt(width * height / cells_wanted), 1e-300);
    nu_ = static_cast<int>(std::clamp(std::ceil(width / cell_), 1.0, 2048.0));
    nv_ = static_cast<int>(std::clamp(std::ceil(height / cell_), 1.0, 2048.0));
    cell_u_ = width / nu_;
    cell_v_ = height / nv_;
    // Compressed rows: count, prefix sum, fill.
    start_.assign(static_cast<std::size_t>(nu_) * nv_ + 1, 0);
    for (std::size_t f = 0; f < n; ++f)
      if (!prep[f].degenerate) for_cells(boxes_[f], [&](std::size_t c) { ++start_[c + 1]; });
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    entries_.resize(start_.back());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t f = 0; f < n; ++f)
      if (!prep[f].degenerate)
        for_cells(boxes_[f], [&](std::size_t c) { entries_[fill[c]++] = static_cast<std::uint32_t>(f); });
  }

  /// Calls visit(face) for every face whose light-space box overlaps `face`'s (with repeats).
  template <class Visit>
  void query(std::size_t face, Visit&& visit) const {
    const Box& b = boxes_[face];
    for_cells(b, [&](std::size_t c) {
      for (std::uint32_t e = start_[c]; e < start_[c + 1]; ++e) {
        const Box& o = boxes_[entries_[e]];
        if (o[0] <= b[2] + margin_ && b[0] <= o[2] + margin_ && o[1] <= b[3] + margin_ &&
            b[1] <= o[3] + margin_)
          visit(entries_[e]);
      }
    });
  }

 private:
  using Box = std::array<double, 4>;  // umin, vmin, umax, vmax
  static Box merge(const Box& a, const Box& b) {
    return {std::min(a[0], b[0]), std::min(a[1], b[1]), std::max(a[2], b[2]), std::max(a[3], b[3])};
  }
  Box box_of(const CullScene& scene, const CullFace& face) const {
    Box b{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest()};
    for (std::size_t k = face.first; k < face.first + face.count; ++k) {
      const double u = glm::dot(u_, scene.vertices[k]), v = glm::dot(v_, scene.vertices[k]);
      b = {std::min(b[0], u), std::min(b[1], v), std::max(b[2], u), std::max(b[3], v)};
    }
    return b;
  }
  template <class Visit>
  void for_cells(const Box& b, Visit&& visit) const {
    auto cell_index = [](double x, double origin, double size, int count) {
      return std::clamp(static_cast<int>(std::floor((x - origin) / size)), 0, count - 1);
    };
    const int u0 = cell_index(b[0] - margin_, origin_[0], cell_u_, nu_);
    const int u1 = cell_index(b[2] + margin_, origin_[0], cell_u_, nu_);
    const int v0 = cell_index(b[1] - margin_, origin_[1], cell_v_, nv_);
    const int v1 = cell_index(b[3] + margin_, origin_[1], cell_v_, nv_);
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u) visit(static_cast<std::size_t>(v) * nu_ + u);
  }

  glm::dvec3 u_{0.0}, v_{0.0};
  std::vector<Box> boxes_;
  std::array<double, 2> origin_{0, 0};
  double margin_ = 0, cell_ = 1, cell_u_ = 1, cell_v_ = 1;
  int nu_ = 1, nv_ = 1;
  std::vector<std::uint32_t> start_;
  std::vector<std::uint32_t> entries_;
};

// ---------------------------------------------------------------------------------------------
// Exact geometry.
// ---------------------------------------------------------------------------------------------

/// A light in homogeneous form l = (x, y, z, w): (L, 1) for a point light, (d, 0) for a
/// directional light with d pointing toward it. Exact (the input doubles are exact rationals).
struct ExactLight {
  std::array<FT, 4> l;
  [[nodiscard]] bool is_point() const { return !CGAL::is_zero(l[3]); }
};

/// s~(l) = n . l_xyz + offset * l_w: positive when the light is on the front side of the plane.
FT plane_at_light(const ExactFace& face, const ExactLight& light) {
  return face.normal.x() * light.l[0] + face.normal.y() * light.l[1] +
         face.normal.z() * light.l[2] + face.offset * light.l[3];
}

/// Sutherland-Hodgman clip of a convex polygon to f >= 0. Vertices exactly on f = 0 are kept;
/// intersection points are made only where f changes sign strictly, so no duplicates arise.
void clip_convex(std::vector<Point3>& poly, const Affine3& f, std::vector<Point3>& scratch) {
  if (poly.empty()) return;
  const std::size_t n = poly.size();
  std::vector<FT> value(n);
  bool any_out = false, any_in = false;
  for (std::size_t a = 0; a < n; ++a) {
    value[a] = f(poly[a]);
    const CGAL::Sign s = CGAL::sign(value[a]);
    any_out |= s == CGAL::NEGATIVE;
    any_in |= s == CGAL::POSITIVE;
  }
  if (!any_out) return;  // wholly inside (or on the plane)
  if (!any_in) {         // nothing strictly inside: the closure has no area
    poly.clear();
    return;
  }
  scratch.clear();
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t b = (a + 1) % n;
    const CGAL::Sign sa = CGAL::sign(value[a]), sb = CGAL::sign(value[b]);
    if (sa != CGAL::NEGATIVE) scratch.push_back(poly[a]);
    if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) ||
        (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE)) {
      const FT t = value[a] / (value[a] - value[b]);
      scratch.push_back(poly[a] + t * (poly[b] - poly[a]));
    }
  }
  poly.swap(scratch);
}

/// Clip of a convex polygon to the front of the receiver's plane (s >= 0) when the exact signs of
/// s at its vertices are already known; s is evaluated (lazily) only on edges that cross.
void clip_front(std::vector<Point3>& poly, const std::vector<CGAL::Sign>& sign, const Affine3& s,
                std::vector<Point3>& scratch) {
  const std::size_t n = poly.size();
  scratch.clear();
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t b = (a + 1) % n;
    if (sign[a] != CGAL::NEGATIVE) scratch.push_back(poly[a]);
    if ((sign[a] == CGAL::POSITIVE && sign[b] == CGAL::NEGATIVE) ||
        (sign[a] == CGAL::NEGATIVE && sign[b] == CGAL::POSITIVE)) {
      const FT sa = s(poly[a]), sb = s(poly[b]);
      scratch.push_back(poly[a] + (sa / (sa - sb)) * (poly[b] - poly[a]));
    }
  }
  poly.swap(scratch);
}

/// Sutherland-Hodgman clip of a convex 2D polygon to x_c >= m (keep_greater) or x_c <= m.
void clip_convex_2d(std::vector<Point2>& poly, int c, double m, bool keep_greater,
                    std::vector<Point2>& scratch) {
  if (poly.empty()) return;
  const std::size_t n = poly.size();
  auto side = [&](const Point2& p) {
    const CGAL::Comparison_result r = CGAL::compare(p[c], FT(m));
    return keep_greater ? static_cast<int>(r) : -static_cast<int>(r);  // +1 inside, -1 outside
  };
  std::vector<int> in(n);
  bool any_out = false, any_in = false;
  for (std::size_t a = 0; a < n; ++a) {
    in[a] = side(poly[a]);
    any_out |= in[a] < 0;
    any_in |= in[a] > 0;
  }
  if (!any_out) return;
  if (!any_in) {
    poly.clear();
    return;
  }
  scratch.clear();
  const int o = 1 - c;
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t b = (a + 1) % n;
    if (in[a] >= 0) scratch.push_back(poly[a]);
    if (in[a] * in[b] < 0) {
      const Point2& pa = poly[a];
      const Point2& pb = poly[b];
      const FT other = pa[o] + (FT(m) - pa[c]) * (pb[o] - pa[o]) / (pb[c] - pa[c]);
      scratch.push_back(c == 0 ? Point2(FT(m), other) : Point2(other, FT(m)));
    }
  }
  poly.swap(scratch);
}

/// The set of half-spaces a caster is clipped to for one receiver, and the projection.
struct ReceiverFrame {
  int axis = 2;
  FT light_side;                  ///< s~(l) > 0
  Affine3 front;                  ///< s(p) >= 0: in front of the receiver's plane
  std::array<Affine3, 4> sides;   ///< the prism/pyramid over the chart bounding box
  std::array<FT, 2> shift;        ///< directional: l_c / s~(l) for the chart axes c = i, j
};

ReceiverFrame make_frame(const ExactFace& face, const FacePrep& prep, const ExactLight& light,
                         const FT& light_side) {
  ReceiverFrame frame;
  const int k = prep.axis;
  frame.axis = k;
  frame.light_side = light_side;
  frame.front = Affine3{face.normal, face.offset};
  // For a chart bound x_c >= m (c = i or j), the plane through the bound's line on the
  // receiver's plane and the light is  s~(l) (x_c - m) - (l_c - m l_w) s(p) = 0 : it vanishes on
  // that line (s = 0, x_c = m) and at the light. Inside is >= 0. Upper bounds flip signs.
  const int axes[2] = {chart_i(k), chart_j(k)};
  for (int c = 0; c < 2 && light.is_point(); ++c) {  // directional: clipped in 2D instead
    const int ax = axes[c];
    Vector3 e(ax == 0 ? 1 : 0, ax == 1 ? 1 : 0, ax == 2 ? 1 : 0);
    for (int upper = 0; upper < 2; ++upper) {
      const FT m = upper ? prep.chart_max[c] : prep.chart_min[c];
      const FT coef = light.l[ax] - m * light.l[3];
      Affine3 f{light_side * e - coef * face.normal, -light_side * m - coef * face.offset};
      if (upper) f = Affine3{-f.a, -f.b};
      frame.sides[c * 2 + upper] = f;
    }
  }
  if (!light.is_point()) {
    frame.shift = {light.l[chart_i(k)] / light_side, light.l[chart_j(k)] / light_side};
  }
  return frame;
}

/// Projects a point (strictly between the receiver's plane and the light) from the light onto
/// the receiver's plane and returns its chart coordinates:  X = (s~ Y - s(Y) l) / (s~ - s(Y) l_w).
Point2 project_to_chart(const Point3& y, const ReceiverFrame& frame, const ExactLight& light) {
  const FT s = frame.front(y);
  const int i = chart_i(frame.axis), j = chart_j(frame.axis);
  if (!light.is_point()) return Point2(y[i] - s * frame.shift[0], y[j] - s * frame.shift[1]);
  const FT w = frame.light_side - s;
  return Point2((frame.light_side * y[i] - s * light.l[i]) / w,
                (frame.light_side * y[j] - s * light.l[j]) / w);
}

/// Where edge a-b (s(a) and s(b) of strictly opposite signs) crosses the receiver's plane, in
/// chart coordinates. Points on the plane are their own projection: computing them through the
/// projection formula would give the same value, but through an s that is exactly zero with an
/// interval around it, and every later comparison of such points would need exact arithmetic.
Point2 crossing_in_chart(const Point3& a, const Point3& b, const ReceiverFrame& frame) {
  const FT sa = frame.front(a), sb = frame.front(b);
  const FT t = sa / (sa - sb);
  const int i = chart_i(frame.axis), j = chart_j(frame.axis);
  return Point2(a[i] + t * (b[i] - a[i]), a[j] + t * (b[j] - a[j]));
}

/// Projects the part of a convex polygon in front of the receiver (s >= 0, exact signs given)
/// into the chart, in order: vertices in front are projected, vertices on the plane and
/// crossings of the plane are their own chart points.
void project_front_part(const std::vector<Point3>& poly, const std::vector<CGAL::Sign>& sign,
                        const ReceiverFrame& frame, const ExactLight& light, std::vector<Point2>& out) {
  const std::size_t n = poly.size();
  out.clear();
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t b = (a + 1) % n;
    if (sign[a] == CGAL::POSITIVE) out.push_back(project_to_chart(poly[a], frame, light));
    if (sign[a] == CGAL::ZERO) out.push_back(to_chart(poly[a], frame.axis));
    if ((sign[a] == CGAL::POSITIVE && sign[b] == CGAL::NEGATIVE) ||
        (sign[a] == CGAL::NEGATIVE && sign[b] == CGAL::POSITIVE))
      out.push_back(crossing_in_chart(poly[a], poly[b], frame));
  }
}

/// Parallel projection onto an exactly planar receiver, computed directly in GMP rationals from
/// the input doubles. The results enter CGAL as exact leaves: their exact values are known and
/// their intervals are tight, so when the union or the final area rounding needs exact values
/// (ties between coordinates are common: boxes have parallel edges) nothing is left to evaluate.
/// The lazy formula gives the same numbers through a tree of lazy nodes, each evaluated on
/// demand; that evaluation dominated the time.
class LeafProjector {
 public:
  LeafProjector(const std::vector<glm::dvec3>& receiver, const FacePrep& prep, const Light& light)
      : i_(chart_i(prep.axis)), j_(chart_j(prep.axis)), point_(light.type == LightType::Point) {
    const glm::dvec3& c = receiver[prep.corner[1]];
    const glm::dvec3& next = receiver[prep.corner[2]];
    const glm::dvec3& prev = receiver[prep.corner[0]];
    mpq_class u[3], v[3];
    for (int a = 0; a < 3; ++a) {
      u[a] = mpq_class(next[a]) - mpq_class(c[a]);
      v[a] = mpq_class(prev[a]) - mpq_class(c[a]);
    }
    n_[0] = u[1] * v[2] - u[2] * v[1];
    n_[1] = u[2] * v[0] - u[0] * v[2];
    n_[2] = u[0] * v[1] - u[1] * v[0];
    if (prep.flipped)
      for (mpq_class& x : n_) x = -x;
    offset_ = -(n_[0] * c.x + n_[1] * c.y + n_[2] * c.z);
    if (!point_) {
      const glm::dvec3& d = light.to_light;
      const mpq_class light_side = n_[0] * d.x + n_[1] * d.y + n_[2] * d.z;
      shift_i_ = mpq_class(d[i_]) / light_side;
      shift_j_ = mpq_class(d[j_]) / light_side;
      return;
    }
    for (int a = 0; a < 3; ++a) light_[a] = light.position[a];
    light_side_ = n_[0] * light_[0] + n_[1] * light_[1] + n_[2] * light_[2] + offset_;
    // The pyramid over the chart box: for a bound x_c >= m the plane through the bound's line
    // on the receiver and the light is  s~ (x_c - m) - (L_c - m) s(p) = 0  (inside >= 0).
    const int axes[2] = {i_, j_};
    for (int c2 = 0; c2 < 2; ++c2) {
      for (int upper = 0; upper < 2; ++upper) {
        const mpq_class m(upper ? prep.chart_max[c2] : prep.chart_min[c2]);
        const mpq_class coef = light_[axes[c2]] - m;
        Side& side = sides_[c2 * 2 + upper];
        for (int a = 0; a < 3; ++a) side.a[a] = -coef * n_[a];
        side.a[axes[c2]] += light_side_;
        side.b = -light_side_ * m - coef * offset_;
        if (upper) {
          for (mpq_class& x : side.a) x = -x;
          side.b = -side.b;
        }
      }
    }
  }

  /// Projects the part of a convex piece of a caster (input doubles, with the exact signs of
  /// the receiver's plane at its vertices) in front of the receiver into the chart. For a point
  /// light the piece is first clipped to the pyramid over the chart box, which keeps the
  /// central projection finite; a directional light's piece is clipped in 2D by the caller.
  void project_piece(const std::vector<glm::dvec3>& vertices, const std::vector<int>& piece,
                     const std::vector<CGAL::Sign>& sign, std::vector<Point2>& out) {
    if (!point_) {
      project_piece_parallel(vertices, piece, sign, out);
      return;
    }
    poly_.clear();
    const std::size_t n = piece.size();
    for (std::size_t a = 0; a < n; ++a) {
      const std::size_t b = (a + 1) % n;
      const glm::dvec3& va = vertices[piece[a]];
      if (sign[a] != CGAL::NEGATIVE) poly_.push_back({{mpq_class(va.x), mpq_class(va.y), mpq_class(va.z)}, sign[a] == CGAL::ZERO});
      if ((sign[a] == CGAL::POSITIVE && sign[b] == CGAL::NEGATIVE) ||
          (sign[a] == CGAL::NEGATIVE && sign[b] == CGAL::POSITIVE)) {
        const glm::dvec3& vb = vertices[piece[b]];
        plane_value(va, s_);
        plane_value(vb, t_);
        t_ = s_ / (s_ - t_);
        QPoint p;
        for (int c = 0; c < 3; ++c) p.v[c] = mpq_class(va[c]) + t_ * (mpq_class(vb[c]) - mpq_class(va[c]));
        p.on_plane = true;
        poly_.push_back(std::move(p));
      }
    }
    for (const Side& side : sides_) clip(side);
    out.clear();
    for (const QPoint& p : poly_) {
      if (p.on_plane) {
        out.emplace_back(FT(p.v[i_]), FT(p.v[j_]));
        continue;
      }
      s_ = offset_;
      for (int c = 0; c < 3; ++c) s_ += n_[c] * p.v[c];
      t_ = light_side_ - s_;
      x_ = (light_side_ * p.v[i_] - s_ * light_[i_]) / t_;
      z_ = (light_side_ * p.v[j_] - s_ * light_[j_]) / t_;
      out.emplace_back(FT(x_), FT(z_));
    }
  }

  /// The projection of an input point in front of (or on) the receiver's plane.
  Point2 project(const glm::dvec3& y) {
    plane_value(y, s_);
    x_ = y[i_];
    x_ -= s_ * shift_i_;
    z_ = y[j_];
    z_ -= s_ * shift_j_;
    return Point2(FT(x_), FT(z_));
  }

  /// Where segment a-b crosses the receiver's plane (s(a), s(b) of strictly opposite signs).
  Point2 crossing(const glm::dvec3& a, const glm::dvec3& b) {
    plane_value(a, s_);
    plane_value(b, t_);
    t_ = s_ / (s_ - t_);
    x_ = b[i_];
    x_ -= a[i_];
    x_ *= t_;
    x_ += a[i_];
    z_ = b[j_];
    z_ -= a[j_];
    z_ *= t_;
    z_ += a[j_];
    return Point2(FT(x_), FT(z_));
  }

  Point2 chart(const glm::dvec3& y) const { return Point2(y[i_], y[j_]); }

  /// Directional light: the part of a convex piece in front of the receiver (exact signs of
  /// its plane given), projected in order. No pyramid is needed: the caller clips in 2D.
  void project_piece_parallel(const std::vector<glm::dvec3>& vertices, const std::vector<int>& piece,
                              const std::vector<CGAL::Sign>& sign, std::vector<Point2>& out) {
    out.clear();
    const std::size_t m = piece.size();
    for (std::size_t a = 0; a < m; ++a) {
      const glm::dvec3& va = vertices[piece[a]];
      const CGAL::Sign sa = sign[a], sb = sign[(a + 1) % m];
      if (sa == CGAL::POSITIVE) out.push_back(project(va));
      if (sa == CGAL::ZERO) out.push_back(chart(va));
      if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE))
        out.push_back(crossing(va, vertices[piece[(a + 1) % m]]));
    }
  }

 private:
  void plane_value(const glm::dvec3& y, mpq_class& out) {
    out = offset_;
    for (int a = 0; a < 3; ++a) {
      term_ = y[a];
      term_ *= n_[a];
      out += term_;
    }
  }

  struct QPoint {
    mpq_class v[3];
    bool on_plane = false;  ///< on the receiver's plane: its own projection
  };
  struct Side {
    mpq_class a[3], b;
  };

  /// Sutherland-Hodgman clip of poly_ to side(p) >= 0; crossings only on strict sign changes.
  void clip(const Side& side) {
    const std::size_t n = poly_.size();
    if (n == 0) return;
    value_.resize(n);
    bool any_out = false, any_in = false;
    for (std::size_t a = 0; a < n; ++a) {
      value_[a] = side.b;
      for (int c = 0; c < 3; ++c) value_[a] += side.a[c] * poly_[a].v[c];
      any_out |= sgn(value_[a]) < 0;
      any_in |= sgn(value_[a]) > 0;
    }
    if (!any_out) return;
    if (!any_in) {
      poly_.clear();
      return;
    }
    next_.clear();
    for (std::size_t a = 0; a < n; ++a) {
      const std::size_t b = (a + 1) % n;
      const int sa = sgn(value_[a]), sb = sgn(value_[b]);
      if (sa >= 0) next_.push_back(poly_[a]);
      if (sa * sb < 0) {
        t_ = value_[a] / (value_[a] - value_[b]);
        QPoint p;
        for (int c = 0; c < 3; ++c) p.v[c] = poly_[a].v[c] + t_ * (poly_[b].v[c] - poly_[a].v[c]);
        p.on_plane = poly_[a].on_plane && poly_[b].on_plane;
        next_.push_back(std::move(p));
      }
    }
    poly_.swap(next_);
  }

  int i_, j_;
  bool point_;
  mpq_class n_[3], offset_, shift_i_, shift_j_;
  mpq_class light_[3], light_side_;
  std::array<Side, 4> sides_;
  std::vector<QPoint> poly_, next_;
  std::vector<mpq_class> value_;
  mpq_class s_, t_, x_, z_, term_;  // scratch, to avoid reallocating limbs
};

/// Splits a polygon with holes into simple polygons (triangles where there are holes).
void append_simple_cells(const PolygonWithHoles2& region, std::vector<Polygon2>& cells) {
  if (region.number_of_holes() == 0) {
    cells.push_back(region.outer_boundary());
    return;
  }
  CGAL::Polygon_triangulation_decomposition_2<Kernel> triangulate;
  triangulate(region, std::back_inserter(cells));
}

FT region_area(const PolygonWithHoles2& region) {
  FT area = region.outer_boundary().area();
  for (auto h = region.holes_begin(); h != region.holes_end(); ++h) area -= CGAL::abs(h->area());
  return area;
}

}  // namespace
}  // namespace exact

// =============================================================================================

struct ShadowEngine::Impl {
  const Scene* scene = nullptr;
  std::vector<exact::FacePrep> prep;
  std::vector<double> face_area;
  exact::CullScene cull;

  /// A closed convex polyhedron made of scene faces (a box, say), fronts outward. Whatever a
  /// ray crosses it through, it crosses its boundary, so the solid can cast as one polygon: the
  /// convex hull of its projected vertices (clipped to the receiver's front), instead of one
  /// polygon per face whose projections share edges and make the union expensive.
  struct ConvexSolid {
    std::vector<glm::dvec3> vertices;         ///< unique vertices
    std::vector<std::array<int, 2>> edges;    ///< unique edges (indices into vertices)
  };
  std::vector<ConvexSolid> solids;
  std::vector<int> solid_of;  ///< per face: index into solids, or -1
  void find_convex_solids();

  /// Per-thread exact state. Epeck objects are never shared between threads.
  struct Worker {
    std::vector<std::unique_ptr<exact::ExactFace>> faces;  // built on first use
    std::vector<std::uint32_t> seen;                       // candidate de-duplication stamps
    std::vector<std::uint32_t> solid_seen;                 // same, for convex solids
    std::uint32_t stamp = 0;
    ShadowStats stats;
    std::vector<std::size_t> candidates;
    std::vector<exact::Point3> poly, scratch;
    std::vector<exact::Point2> poly2, scratch2;
    std::vector<CGAL::Sign> vertex_sign, piece_sign;
  };

  const exact::ExactFace& exact_face(Worker& w, std::size_t f) const {
    if (!w.faces[f])
      w.faces[f] = std::make_unique<exact::ExactFace>(
          exact::make_exact_face(scene->faces[f].vertices, prep[f]));
    return *w.faces[f];
  }

  /// Result for one receiving face under one light.
  struct Item {
    FaceLighting lighting;
    std::vector<Fragment> fragments;  // fragment_id local to the item
  };

  void compute_light(const Light& light, std::size_t light_id, const ShadowOptions& options,
                     std::vector<Worker>& workers, const std::vector<std::size_t>& receivers,
                     std::vector<Item>& items, std::size_t progress_base, std::size_t progress_total) const;

  /// Computes `lights` (reported as `light_ids`) on every receiving face.
  ShadowResult run(const std::vector<const Light*>& lights, const std::vector<std::size_t>& light_ids,
                   const ShadowOptions& options) const;

  static ShadowResult assemble(std::vector<std::vector<Item>>& per_light,
                               const std::vector<Worker>& workers);

  Item compute_receiver(Worker& w, std::size_t face_id, std::size_t light_id,
                        const exact::ExactLight& light, int facing, const Light& light_in,
                        const exact::LightSpaceGrid* grid, bool polygons) const;
};

namespace {

exact::CullScene make_cull_scene(const Scene& scene, const std::vector<exact::FacePrep>& prep) {
  exact::CullScene cull;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const Face& f : scene.faces)
    for (const glm::dvec3& v : f.vertices) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  if (scene.faces.empty()) lo = hi = glm::dvec3(0.0);
  cull.origin = 0.5 * (lo + hi);
  cull.diameter = std::max(glm::length(hi - lo), 1e-300);
  cull.faces.resize(scene.faces.size());
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    exact::CullFace& cf = cull.faces[f];
    cf.first = cull.vertices.size();
    cf.count = scene.faces[f].vertices.size();
    glm::dvec3 n(0.0);
    for (std::size_t a = 0; a < cf.count; ++a) {
      const glm::dvec3 u = scene.faces[f].vertices[a] - cull.origin;
      const glm::dvec3 v = scene.faces[f].vertices[(a + 1) % cf.count] - cull.origin;
      cull.vertices.push_back(u);
      n += glm::dvec3((u.y - v.y) * (u.z + v.z), (u.z - v.z) * (u.x + v.x), (u.x - v.x) * (u.y + v.y));
    }
    const double len = glm::length(n);
    if (prep[f].degenerate || !(len > 0)) continue;
    cf.normal = n / len;
    glm::dvec3 centroid(0.0);
    for (std::size_t a = 0; a < cf.count; ++a) centroid += cull.vertices[cf.first + a];
    cf.offset = -glm::dot(cf.normal, centroid / static_cast<double>(cf.count));
  }
  return cull;
}

}  // namespace

/// Finds the closed convex solids among each mesh's faces: faces joined by shared edges (equal
/// vertex coordinates), every edge used exactly twice in opposite directions, and every vertex
/// of the solid on or behind every face's plane (Epick's exact orientation test).
void ShadowEngine::Impl::find_convex_solids() {
  const Scene& scene = *this->scene;
  using EK = CGAL::Exact_predicates_inexact_constructions_kernel;
  const std::size_t n = scene.faces.size();
  solid_of.assign(n, -1);
  // Vertex ids by exact coordinates (+0.0 folds -0.0 into 0.0).
  std::map<std::array<double, 3>, int> vertex_id;
  std::vector<std::vector<int>> face_vertices(n);
  std::vector<glm::dvec3> vertex_position;
  for (std::size_t f = 0; f < n; ++f) {
    if (prep[f].degenerate || !prep[f].exactly_planar) continue;
    for (const glm::dvec3& v : scene.faces[f].vertices) {
      const std::array<double, 3> key{v.x + 0.0, v.y + 0.0, v.z + 0.0};
      auto [it, inserted] = vertex_id.emplace(key, static_cast<int>(vertex_position.size()));
      if (inserted) vertex_position.push_back(v);
      face_vertices[f].push_back(it->second);
    }
  }
  // Undirected edge -> uses (face, forward). Within one mesh only.
  struct Use {
    std::size_t face;
    bool forward;
  };
  std::map<std::tuple<std::size_t, int, int>, std::vector<Use>> edge_uses;
  for (std::size_t f = 0; f < n; ++f) {
    const std::vector<int>& fv = face_vertices[f];
    for (std::size_t a = 0; a < fv.size(); ++a) {
      const int u = fv[a], v = fv[(a + 1) % fv.size()];
      edge_uses[{scene.faces[f].mesh, std::min(u, v), std::max(u, v)}].push_back({f, u < v});
    }
  }
  std::vector<std::size_t> parent(n);
  for (std::size_t f = 0; f < n; ++f) parent[f] = f;
  auto find = [&](std::size_t f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  std::vector<bool> open(n, false);  // touches an edge that is not shared exactly twice, oppositely
  for (const auto& [edge, uses] : edge_uses) {
    const bool manifold = uses.size() == 2 && uses[0].forward != uses[1].forward;
    if (manifold) {
      parent[find(uses[0].face)] = find(uses[1].face);
    } else {
      for (const Use& u : uses) open[u.face] = true;
    }
  }
  std::map<std::size_t, std::vector<std::size_t>> components;
  for (std::size_t f = 0; f < n; ++f)
    if (!face_vertices[f].empty()) components[find(f)].push_back(f);
  for (const auto& [root, faces] : components) {
    if (faces.size() < 4) continue;
    if (std::any_of(faces.begin(), faces.end(), [&](std::size_t f) { return open[f]; })) continue;
    std::map<int, int> local;
    ConvexSolid solid;
    for (std::size_t f : faces)
      for (int v : face_vertices[f])
        if (local.emplace(v, static_cast<int>(solid.vertices.size())).second)
          solid.vertices.push_back(vertex_position[v]);
    bool convex = true;
    for (std::size_t f : faces) {
      const std::vector<glm::dvec3>& fv = scene.faces[f].vertices;
      const exact::FacePrep& fp = prep[f];
      auto p3 = [](const glm::dvec3& v) { return EK::Point_3(v.x, v.y, v.z); };
      const EK::Point_3 c0 = p3(fv[fp.corner[1]]), c1 = p3(fv[fp.corner[2]]), c2 = p3(fv[fp.corner[0]]);
      const CGAL::Orientation front = fp.flipped ? CGAL::NEGATIVE : CGAL::POSITIVE;
      for (const glm::dvec3& v : solid.vertices)
        if (CGAL::orientation(c0, c1, c2, p3(v)) == front) {
          convex = false;
          break;
        }
      if (!convex) break;
    }
    if (!convex) continue;
    std::set<std::pair<int, int>> edges;
    for (std::size_t f : faces) {
      const std::vector<int>& fv = face_vertices[f];
      for (std::size_t a = 0; a < fv.size(); ++a) {
        const int u = local[fv[a]], v = local[fv[(a + 1) % fv.size()]];
        edges.emplace(std::min(u, v), std::max(u, v));
      }
    }
    for (const auto& [u, v] : edges) solid.edges.push_back({u, v});
    for (std::size_t f : faces) solid_of[f] = static_cast<int>(solids.size());
    solids.push_back(std::move(solid));
  }
}

ShadowEngine::ShadowEngine(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  impl_->scene = &scene;
  const std::size_t n = scene.faces.size();
  impl_->prep.resize(n);
  impl_->face_area.assign(n, 0.0);
  const unsigned threads = exact::resolve_threads(0);
  exact::parallel_for(n, threads, [&](unsigned, std::size_t f) {
    const Face& face = scene.faces[f];
    exact::FacePrep& prep = impl_->prep[f];
    if (face.degenerate || face.vertices.size() < 3) {
      prep.degenerate = true;
      return;
    }
    prep = exact::prepare_face(face.vertices);
    if (prep.degenerate) return;
    const exact::ExactFace ef = exact::make_exact_face(face.vertices, prep);
    impl_->face_area[f] = exact::area_3d(ef.chart_area, ef.area_scale_squared);
  });
  impl_->cull = make_cull_scene(scene, impl_->prep);
  impl_->find_convex_solids();
}

ShadowEngine::~ShadowEngine() = default;
ShadowEngine::ShadowEngine(ShadowEngine&&) noexcept = default;
ShadowEngine& ShadowEngine::operator=(ShadowEngine&&) noexcept = default;

double ShadowEngine::face_area(std::size_t face_id) const { return impl_->face_area.at(face_id); }

namespace {

void check_light(const Light& light, std::size_t light_id) {
  auto finite = [](const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  const std::string place = "lights[" + std::to_string(light_id) + "]";
  if (light.type == LightType::Directional) {
    if (!finite(light.to_light)) throw InputError({"", place + ".to_light"}, "not a finite vector");
    if (light.to_light == glm::dvec3(0.0))
      throw InputError({"", place + ".to_light"}, "zero direction vector");
  } else if (!finite(light.position)) {
    throw InputError({"", place + ".position"}, "not a finite point");
  }
}

exact::ExactLight to_exact_light(const Light& light) {
  using exact::FT;
  if (light.type == LightType::Point)
    return {{FT(light.position.x), FT(light.position.y), FT(light.position.z), FT(1)}};
  return {{FT(light.to_light.x), FT(light.to_light.y), FT(light.to_light.z), FT(0)}};
}

/// The face's own outline as one fragment (wholly lit or wholly in shadow).
Fragment whole_face_fragment(const Face& face, std::size_t face_id, std::size_t light_id, bool lit,
                             double area, const exact::FacePrep& prep, const exact::ExactFace* ef) {
  Fragment fragment;
  fragment.face_id = face_id;
  fragment.light_id = light_id;
  fragment.lit = lit;
  fragment.area = area;
  if (prep.exactly_planar || ef == nullptr) {
    fragment.polygon = face.vertices;
  } else {
    for (const exact::Point3& p : ef->vertices)
      fragment.polygon.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()),
                                    CGAL::to_double(p.z()));
  }
  return fragment;
}

}  // namespace

ShadowEngine::Impl::Item ShadowEngine::Impl::compute_receiver(
    Worker& w, std::size_t face_id, std::size_t light_id, const exact::ExactLight& light,
    int facing, const Light& light_in, const exact::LightSpaceGrid* grid, bool polygons) const {
  using namespace exact;
  Item item;
  FaceLighting& out = item.lighting;
  out.face_id = face_id;
  out.light_id = light_id;
  out.area = face_area[face_id];
  ++w.stats.receivers;
  const Face& face = scene->faces[face_id];
  const FacePrep& fp = prep[face_id];
  if (fp.degenerate) return item;  // zero area: nothing to light

  if (facing <= 0) {  // attached shadow: the front looks away from the light (or edge-on)
    ++w.stats.back_facing;
    out.shadow_area = out.area;
    if (polygons)
      item.fragments.push_back(whole_face_fragment(face, face_id, light_id, false, out.area, fp,
                                                   fp.exactly_planar ? nullptr : &exact_face(w, face_id)));
    return item;
  }
  out.faces_light = true;

  // ---- culling in doubles -------------------------------------------------------------------
  const CullFace& cp = cull.faces[face_id];
  const double D = cull.diameter;
  glm::dvec3 lxyz;
  double lw;
  if (light_in.type == LightType::Point) {
    lxyz = light_in.position - cull.origin;
    lw = 1.0;
  } else {
    lxyz = unit(light_in.to_light);
    lw = 0.0;
  }
  const double light_side = glm::dot(cp.normal, lxyz) + cp.offset * lw;
  const double scale = D + (lw != 0.0 ? glm::length(lxyz) : 0.0);
  std::array<DoubleAffine, 5> tests;
  tests[0] = {cp.normal, cp.offset, 1e-9 * scale};
  {
    const int k = fp.axis;
    const int axes[2] = {chart_i(k), chart_j(k)};
    for (int c = 0; c < 2; ++c) {
      const int ax = axes[c];
      glm::dvec3 e(0.0);
      e[ax] = 1.0;
      for (int upper = 0; upper < 2; ++upper) {
        const double m = (upper ? fp.chart_max[c] : fp.chart_min[c]) - cull.origin[ax];
        const double coef = lxyz[ax] - m * lw;
        DoubleAffine f{light_side * e - coef * cp.normal, -light_side * m - coef * cp.offset,
                       1e-9 * (std::abs(light_side) + std::abs(coef)) * scale};
        if (upper) {
          f.a = -f.a;
          f.b = -f.b;
        }
        tests[1 + c * 2 + upper] = f;
      }
    }
  }
  auto may_cast = [&](std::size_t q) {
    const CullFace& cq = cull.faces[q];
    for (const DoubleAffine& f : tests) {
      bool all_out = true;
      for (std::size_t a = cq.first; a < cq.first + cq.count && all_out; ++a)
        all_out = f(cull.vertices[a]) < -f.tolerance;
      if (all_out) return false;
    }
    return true;
  };
  w.candidates.clear();
  if (++w.stamp == 0) {  // stamps wrapped: reset
    std::fill(w.seen.begin(), w.seen.end(), 0);
    std::fill(w.solid_seen.begin(), w.solid_seen.end(), 0);
    w.stamp = 1;
  }
  auto consider = [&](std::size_t q) {
    if (q == face_id || prep[q].degenerate || w.seen[q] == w.stamp) return;
    w.seen[q] = w.stamp;
    if (may_cast(q)) w.candidates.push_back(q);
  };
  if (grid) {
    grid->query(face_id, consider);
  } else {
    for (std::size_t q = 0; q < prep.size(); ++q) consider(q);
  }
  // Deterministic order whatever the grid's visiting order.
  std::sort(w.candidates.begin(), w.candidates.end());
  w.stats.candidate_pairs += w.candidates.size();

  // ---- exact clipping and projection ---------------------------------------------------------
  // The receiver's exact frame is built on first use: most receivers are decided by the
  // predicates below alone (nothing strictly in front of them).
  std::optional<ReceiverFrame> frame_storage;
  auto exact_frame = [&]() -> const ReceiverFrame& {
    if (!frame_storage) {
      const ExactFace& receiver = exact_face(w, face_id);
      frame_storage = make_frame(receiver, fp, light, plane_at_light(receiver, light));
    }
    return *frame_storage;
  };
  // Signs of s (the receiver's plane) at input vertices are decided by Epick's orientation
  // predicate on the doubles: exact, and cheap even when the answer is zero, which is common
  // (faces that share an edge with the receiver). Lazy Epeck arithmetic would have to
  // evaluate every zero exactly.
  using EK = CGAL::Exact_predicates_inexact_constructions_kernel;
  auto epick = [](const glm::dvec3& v) { return EK::Point_3(v.x, v.y, v.z); };
  const EK::Point_3 corner0 = epick(face.vertices[fp.corner[1]]);
  const EK::Point_3 corner1 = epick(face.vertices[fp.corner[2]]);
  const EK::Point_3 corner2 = epick(face.vertices[fp.corner[0]]);
  const bool point_light = light.is_point();
  std::optional<LeafProjector> projector_storage;
  auto leaf_projector = [&]() -> LeafProjector& {
    if (!projector_storage) projector_storage.emplace(face.vertices, fp, light_in);
    return *projector_storage;
  };
  std::vector<Polygon2> shadows;
  const int own_solid = solid_of[face_id];
  for (std::size_t q : w.candidates) {
    const int solid = solid_of[q];
    if (solid >= 0 && (solid == own_solid || w.solid_seen[solid] == w.stamp)) continue;
    if (solid >= 0 && !point_light && fp.exactly_planar) {
      // A convex solid casts the hull of its projection (see ConvexSolid).
      w.solid_seen[solid] = w.stamp;
      const ConvexSolid& cs = solids[solid];
      w.vertex_sign.resize(cs.vertices.size());
      bool any_front = false;
      for (std::size_t v = 0; v < cs.vertices.size(); ++v) {
        CGAL::Sign sv = CGAL::orientation(corner0, corner1, corner2, epick(cs.vertices[v]));
        if (fp.flipped) sv = CGAL::opposite(sv);
        w.vertex_sign[v] = sv;
        any_front |= sv == CGAL::POSITIVE;
      }
      if (!any_front) continue;
      LeafProjector& projector = leaf_projector();
      w.poly2.clear();
      for (std::size_t v = 0; v < cs.vertices.size(); ++v) {
        if (w.vertex_sign[v] == CGAL::POSITIVE) w.poly2.push_back(projector.project(cs.vertices[v]));
        if (w.vertex_sign[v] == CGAL::ZERO) w.poly2.push_back(projector.chart(cs.vertices[v]));
      }
      for (const auto& [a, b] : cs.edges) {
        const CGAL::Sign sa = w.vertex_sign[a], sb = w.vertex_sign[b];
        if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE))
          w.poly2.push_back(projector.crossing(cs.vertices[a], cs.vertices[b]));
      }
      w.scratch2.clear();
      CGAL::convex_hull_2(w.poly2.begin(), w.poly2.end(), std::back_inserter(w.scratch2), Kernel());
      w.poly2.swap(w.scratch2);
      for (int c = 0; c < 2; ++c) {
        clip_convex_2d(w.poly2, c, fp.chart_min[c], true, w.scratch2);
        clip_convex_2d(w.poly2, c, fp.chart_max[c], false, w.scratch2);
      }
      if (w.poly2.size() < 3) continue;
      Polygon2 projected(w.poly2.begin(), w.poly2.end());
      if (CGAL::sign(projected.area()) != CGAL::POSITIVE) continue;  // flat: edge-on solid
      shadows.push_back(std::move(projected));
      ++w.stats.casting_pairs;
      continue;
    }
    const FacePrep& qp = prep[q];
    const Face& qface = scene->faces[q];
    w.vertex_sign.resize(qface.vertices.size());
    bool any_front = false;
    if (point_light) {
      // A caster whose plane contains the light is edge-on to it and casts nothing; projecting
      // it would divide by zero where it touches the light.
      const bool edge_on =
          qp.exactly_planar
              ? CGAL::orientation(epick(qface.vertices[qp.corner[1]]), epick(qface.vertices[qp.corner[2]]),
                                  epick(qface.vertices[qp.corner[0]]), epick(light_in.position)) == CGAL::COPLANAR
              : CGAL::is_zero(plane_at_light(exact_face(w, q), light));
      if (edge_on) continue;
    }
    // Two routes to the same exact polygons: exact leaves straight from the input doubles when
    // both faces are exactly planar (the common case), lazy Epeck values for lifted faces.
    const bool leaves = fp.exactly_planar && qp.exactly_planar;
    const ExactFace* Q = nullptr;
    const ReceiverFrame* frame = nullptr;
    if (leaves) {
      for (std::size_t v = 0; v < qface.vertices.size(); ++v) {
        CGAL::Sign sv = CGAL::orientation(corner0, corner1, corner2, epick(qface.vertices[v]));
        if (fp.flipped) sv = CGAL::opposite(sv);
        w.vertex_sign[v] = sv;
        any_front |= sv == CGAL::POSITIVE;
      }
    } else {
      Q = &exact_face(w, q);
      frame = &exact_frame();
      for (std::size_t v = 0; v < Q->vertices.size(); ++v) {
        w.vertex_sign[v] = CGAL::sign(frame->front(Q->vertices[v]));
        any_front |= w.vertex_sign[v] == CGAL::POSITIVE;
      }
    }
    if (!any_front) continue;  // nothing strictly in front of the receiver
    bool cast = false;
    for (const std::vector<int>& piece : qp.convex_pieces) {
      w.piece_sign.clear();
      bool piece_front = false;
      for (int v : piece) {
        w.piece_sign.push_back(w.vertex_sign[v]);
        piece_front |= w.vertex_sign[v] == CGAL::POSITIVE;
      }
      if (!piece_front) continue;
      if (leaves) {
        leaf_projector().project_piece(qface.vertices, piece, w.piece_sign, w.poly2);
      } else {
        w.poly.clear();
        for (int v : piece) w.poly.push_back(Q->vertices[v]);
        if (point_light) {
          // The pyramid over the chart box keeps the central projection finite.
          clip_front(w.poly, w.piece_sign, frame->front, w.scratch);
          for (const Affine3& side : frame->sides) clip_convex(w.poly, side, w.scratch);
          w.poly2.clear();
          for (const Point3& y : w.poly) w.poly2.push_back(project_to_chart(y, *frame, light));
        } else {
          project_front_part(w.poly, w.piece_sign, *frame, light, w.poly2);
        }
      }
      if (!point_light) {  // parallel projection is affine: clip to the chart box in 2D
        for (int c = 0; c < 2; ++c) {
          clip_convex_2d(w.poly2, c, fp.chart_min[c], true, w.scratch2);
          clip_convex_2d(w.poly2, c, fp.chart_max[c], false, w.scratch2);
        }
      }
      if (w.poly2.size() < 3) continue;
      Polygon2 projected(w.poly2.begin(), w.poly2.end());
      const CGAL::Sign orientation = CGAL::sign(projected.area());
      if (orientation == CGAL::ZERO) continue;  // the caster is edge-on to the light
      if (orientation == CGAL::NEGATIVE) projected.reverse_orientation();
      shadows.push_back(std::move(projected));
      cast = true;
    }
    if (cast) ++w.stats.casting_pairs;
  }

  const ExactFace& P = exact_face(w, face_id);
  if (shadows.empty()) {  // nothing in front: wholly lit, no Boolean operation needed
    ++w.stats.unshadowed;
    out.lit_area = out.area;
    out.lit_fraction = 1.0;
    if (polygons) item.fragments.push_back(whole_face_fragment(face, face_id, light_id, true, out.area, fp, &P));
    return item;
  }

  std::vector<PolygonWithHoles2> shadow_regions, lit_regions;
  PolygonSet2 shadow_set;
  if (shadows.size() == 1 && fp.chart_is_box) {
    // One convex caster already clipped to a rectangular receiver: it is the shadow.
    shadow_regions.emplace_back(shadows.front());
    if (polygons) shadow_set.insert(shadows.front());
  } else {
    shadow_set.join(shadows.begin(), shadows.end());  // one aggregated union
    if (!fp.chart_is_box) shadow_set.intersection(P.chart);
    shadow_set.polygons_with_holes(std::back_inserter(shadow_regions));
  }
  FT shadow_chart_area = 0;
  for (const PolygonWithHoles2& r : shadow_regions) shadow_chart_area += region_area(r);
  const FT lit_chart_area = P.chart_area - shadow_chart_area;
  out.lit_area = area_3d(lit_chart_area, P.area_scale_squared);
  out.shadow_area = area_3d(shadow_chart_area, P.area_scale_squared);
  out.lit_fraction = round_to_double(lit_chart_area / P.chart_area);
  if (!polygons) return item;

  PolygonSet2 lit_set(P.chart);
  lit_set.difference(shadow_set);
  lit_set.polygons_with_holes(std::back_inserter(lit_regions));

  std::size_t fragment_id = 0;
  std::vector<Polygon2> cells;
  auto emit = [&](const std::vector<PolygonWithHoles2>& regions, bool lit) {
    for (const PolygonWithHoles2& region : regions) {
      cells.clear();
      append_simple_cells(region, cells);
      for (const Polygon2& cell : cells) {
        Fragment fragment;
        fragment.face_id = face_id;
        fragment.light_id = light_id;
        fragment.fragment_id = fragment_id;
        fragment.lit = lit;
        fragment.area = area_3d(CGAL::abs(cell.area()), P.area_scale_squared);
        for (auto v = cell.vertices_begin(); v != cell.vertices_end(); ++v) {
          const Point3 p = lift(*v, P, fp.axis);
          fragment.polygon.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()),
                                        CGAL::to_double(p.z()));
        }
        // The chart sees the face clockwise when flipped: restore the face's orientation.
        if (fp.flipped == CGAL::is_positive(cell.area()))
          std::reverse(fragment.polygon.begin(), fragment.polygon.end());
        item.fragments.push_back(std::move(fragment));
      }
      ++fragment_id;
    }
  };
  emit(lit_regions, true);
  emit(shadow_regions, false);
  return item;
}

void ShadowEngine::Impl::compute_light(const Light& light_in, std::size_t light_id,
                                       const ShadowOptions& options, std::vector<Worker>& workers,
                                       const std::vector<std::size_t>& receivers,
                                       std::vector<Item>& items, std::size_t progress_base,
                                       std::size_t progress_total) const {
  using namespace exact;
  check_light(light_in, light_id);
  const unsigned threads = static_cast<unsigned>(workers.size());
  const std::size_t n = scene->faces.size();

  // Which side of each receiver the light is on: exact, per receiver.
  std::vector<std::int8_t> facing(receivers.size(), 0);
  std::optional<LightSpaceGrid> grid;
  if (light_in.type == LightType::Directional) grid.emplace(cull, prep, light_in.to_light);

  std::function<void(std::size_t)> report;
  if (options.progress)
    report = [&](std::size_t done) { options.progress(Progress{progress_base + done, progress_total}); };

  std::vector<std::optional<ExactLight>> lights(threads);
  parallel_for(
      receivers.size(), threads,
      [&](unsigned wi, std::size_t r) {
        Worker& w = workers[wi];
        if (!lights[wi]) lights[wi] = to_exact_light(light_in);
        const ExactLight& light = *lights[wi];
        const std::size_t f = receivers[r];
        int side = 0;
        if (!prep[f].degenerate) side = CGAL::sign(plane_at_light(exact_face(w, f), light));
        facing[r] = static_cast<std::int8_t>(side);
        items[r] = compute_receiver(w, f, light_id, light, side, light_in,
                                    grid ? &*grid : nullptr, options.polygons);
      },
      report);
  (void)n;
}

ShadowResult ShadowEngine::Impl::assemble(std::vector<std::vector<Item>>& per_light,
                                          const std::vector<Worker>& workers) {
  ShadowResult result;
  const std::size_t lights = per_light.size();
  const std::size_t receivers = lights ? per_light[0].size() : 0;
  result.lighting.reserve(lights * receivers);
  std::size_t next_fragment_id = 0;
  for (std::size_t r = 0; r < receivers; ++r) {
    for (std::size_t li = 0; li < lights; ++li) {
      Item& item = per_light[li][r];
      result.lighting.push_back(item.lighting);
      std::size_t used = 0;
      for (Fragment& fragment : item.fragments) {
        used = std::max(used, fragment.fragment_id + 1);
        fragment.fragment_id += next_fragment_id;
        result.fragments.push_back(std::move(fragment));
      }
      next_fragment_id += used;
      item.fragments.clear();
      item.fragments.shrink_to_fit();
    }
  }
  for (const Worker& w : workers) {
    result.stats.receivers += w.stats.receivers;
    result.stats.back_facing += w.stats.back_facing;
    result.stats.candidate_pairs += w.stats.candidate_pairs;
    result.stats.casting_pairs += w.stats.casting_pairs;
    result.stats.unshadowed += w.stats.unshadowed;
  }
  return result;
}

ShadowResult ShadowEngine::Impl::run(const std::vector<const Light*>& lights,
                                     const std::vector<std::size_t>& light_ids,
                                     const ShadowOptions& options) const {
  std::vector<std::size_t> receivers;
  for (std::size_t f = 0; f < scene->faces.size(); ++f)
    if (scene->is_receiver(f)) receivers.push_back(f);
  std::vector<Worker> workers(exact::resolve_threads(options.threads));
  for (Worker& w : workers) {
    w.faces.resize(scene->faces.size());
    w.seen.assign(scene->faces.size(), 0);
    w.solid_seen.assign(solids.size(), 0);
  }
  std::vector<std::vector<Item>> per_light(lights.size(), std::vector<Item>(receivers.size()));
  const std::size_t total = lights.size() * receivers.size();
  for (std::size_t li = 0; li < lights.size(); ++li)
    compute_light(*lights[li], light_ids[li], options, workers, receivers, per_light[li],
                  li * receivers.size(), total);
  return assemble(per_light, workers);
}

ShadowResult ShadowEngine::compute(const ShadowOptions& options) const {
  const Scene& scene = *impl_->scene;
  std::vector<std::size_t> light_ids = options.lights;
  if (light_ids.empty())
    for (std::size_t l = 0; l < scene.lights.size(); ++l) light_ids.push_back(l);
  for (std::size_t l : light_ids)
    if (l >= scene.lights.size())
      throw std::out_of_range("ShadowOptions::lights: no light " + std::to_string(l));
  std::sort(light_ids.begin(), light_ids.end());
  light_ids.erase(std::unique(light_ids.begin(), light_ids.end()), light_ids.end());
  std::vector<const Light*> lights;
  for (std::size_t l : light_ids) lights.push_back(&scene.lights[l]);
  return impl_->run(lights, light_ids, options);
}

ShadowResult ShadowEngine::compute(const Light& light, std::size_t light_id,
                                   const ShadowOptions& options) const {
  return impl_->run({&light}, {light_id}, options);
}

ShadowResult compute_shadows(const Scene& scene, const ShadowOptions& options) {
  const ShadowEngine engine(scene);
  return engine.compute(options);
}

}  // namespace shadow
