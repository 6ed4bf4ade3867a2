// SPDX-License-Identifier: GPL-3.0-or-later
// Projection of casters straight from the input doubles into exact GMP rationals: the route for
// exactly planar faces (the common case). Include only from src/exact/*.cpp (CGAL).
#pragma once

#include "geometry/box_sides.hpp"
#include "geometry/clip_convex.hpp"
#include "exact/exact_faces.hpp"
#include "exact/rational_points.hpp"

#include <shadow/scene.hpp>

#include <gmpxx.h>

#include <CGAL/enum.h>

#include <array>
#include <cassert>
#include <vector>

namespace shadow::exact {

/// Projection onto an exactly planar receiver, computed directly in GMP rationals from the input
/// doubles: parallel for a directional light, central for a point light (project_piece picks;
/// project() and project_piece_parallel() are the directional light's only and assert it). The results enter CGAL as exact leaves: their exact values are known and
/// their intervals are tight, so when the union or the final area rounding needs exact values
/// (ties between coordinates are common: boxes have parallel edges) nothing is left to evaluate.
/// The lazy formula gives the same numbers through a tree of lazy nodes, each evaluated on
/// demand; that evaluation dominated the time.
class LeafProjector {
 public:
  LeafProjector(const std::vector<glm::dvec3>& receiver, const core::FacePrep& prep, const Light& light)
      : i_(core::chart_i(prep.axis)), j_(core::chart_j(prep.axis)), point_(light.type == LightType::Point) {
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
    const std::array<mpq_class, 4> plane{n_[0], n_[1], n_[2], offset_};
    const std::array<mpq_class, 4> light_h{light_[0], light_[1], light_[2], mpq_class(1)};
    const auto sides = geometry::box_sides(plane, light_h, light_side_, i_, j_, prep.chart_min.data(), prep.chart_max.data());
    for (int t = 0; t < 4; ++t) {
      for (int a = 0; a < 3; ++a) sides_[t].a[a] = sides[t][a];
      sides_[t].b = sides[t][3];
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

  /// Point light only: the central projection of an input point strictly between the
  /// receiver's plane and the light's level (0 < s(y) < s(light), s the receiver's plane) into
  /// `out`; false, `out` untouched, for any other point. The same exact values as project_piece
  /// gives such a point (its formula, on the point itself: no clip cuts a point inside the
  /// pyramid).
  bool project_central(const glm::dvec3& y, Point2& out) {
    assert(point_ && "LeafProjector::project_central is the central projection (point light)");
    plane_value(y, s_);
    if (sgn(s_) <= 0 || cmp(s_, light_side_) >= 0) return false;
    t_ = light_side_ - s_;
    x_ = (light_side_ * mpq_class(y[i_]) - s_ * light_[i_]) / t_;
    z_ = (light_side_ * mpq_class(y[j_]) - s_ * light_[j_]) / t_;
    out = Point2(FT(x_), FT(z_));
    return true;
  }

  /// project_central for an exact point that the caller knows lies strictly between the
  /// receiver's plane and the light's level (a point of a caster whose vertices all do).
  Point2 project_central(const mpq_class (&y)[3]) {
    assert(point_ && "LeafProjector::project_central is the central projection (point light)");
    s_ = offset_;
    for (int c = 0; c < 3; ++c) s_ += n_[c] * y[c];
    t_ = light_side_ - s_;
    x_ = (light_side_ * y[i_] - s_ * light_[i_]) / t_;
    z_ = (light_side_ * y[j_] - s_ * light_[j_]) / t_;
    return Point2(FT(x_), FT(z_));
  }

  /// A side of the pyramid over the chart box (point light): a . x + b >= 0 inside.
  struct Side {
    mpq_class a[3], b;
  };
  /// The pyramid's four sides (point light only).
  [[nodiscard]] const std::array<Side, 4>& pyramid_sides() const {
    assert(point_ && "LeafProjector::pyramid_sides needs a point light");
    return sides_;
  }

  /// The parallel projection of an input point in front of (or on) the receiver's plane.
  /// Directional lights only: the shift along the light is set for them alone (a point light's
  /// points go through project_piece's central projection).
  Point2 project(const glm::dvec3& y) {
    assert(!point_ && "LeafProjector::project is the parallel projection (directional light)");
    plane_value(y, s_);
    x_ = y[i_];
    x_ -= s_ * shift_i_;
    z_ = y[j_];
    z_ -= s_ * shift_j_;
    return Point2(FT(x_), FT(z_));
  }

  /// Where segment a-b crosses the receiver's plane (s(a), s(b) of strictly opposite signs), in
  /// the chart. A point on the plane is its own projection under any light, so this is right for
  /// both kinds; the engine calls it on the directional routes (the point light's crossings are
  /// made in project_piece, before the pyramid clip).
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

  // The same three as plain rational points of the unscaled chart (the areas-only route's
  // fallback, through ScaledChart: exact/scaled_chart.hpp).
  void project(const glm::dvec3& y, QPoint2& out) {
    assert(!point_ && "LeafProjector::project is the parallel projection (directional light)");
    plane_value(y, s_);
    out.x = y[i_];
    out.x -= s_ * shift_i_;
    out.y = y[j_];
    out.y -= s_ * shift_j_;
    out.update_intervals();
  }
  void crossing(const glm::dvec3& a, const glm::dvec3& b, QPoint2& out) {
    plane_value(a, s_);
    plane_value(b, t_);
    t_ = s_ / (s_ - t_);
    out.x = b[i_];
    out.x -= a[i_];
    out.x *= t_;
    out.x += a[i_];
    out.y = b[j_];
    out.y -= a[j_];
    out.y *= t_;
    out.y += a[j_];
    out.update_intervals();
  }
  void chart(const glm::dvec3& y, QPoint2& out) const {
    out.x = y[i_];
    out.y = y[j_];
    out.i = {IA(y[i_]), IA(y[j_])};
  }
  /// Directional light only: the part of a convex piece in front of the receiver (exact signs
  /// of its plane given), projected in order. No pyramid is needed: the caller clips in 2D.
  void project_piece_parallel(const std::vector<glm::dvec3>& vertices, const std::vector<int>& piece,
                              const std::vector<CGAL::Sign>& sign, std::vector<Point2>& out) {
    assert(!point_ && "LeafProjector::project_piece_parallel needs a directional light");
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
  /// Sutherland-Hodgman clip of poly_ to side(p) >= 0 (geometry/clip_convex.hpp); crossings
  /// only on strict sign changes.
  void clip(const Side& side) {
    const std::size_t n = poly_.size();
    if (n == 0) return;
    value_.resize(n);
    for (std::size_t a = 0; a < n; ++a) {
      value_[a] = side.b;
      for (int c = 0; c < 3; ++c) value_[a] += side.a[c] * poly_[a].v[c];
    }
    auto side_of = [&](std::size_t a) { return sgn(value_[a]); };
    switch (geometry::clip_case(n, side_of)) {
      case geometry::ClipCase::Inside: return;
      case geometry::ClipCase::Empty: poly_.clear(); return;
      case geometry::ClipCase::Cut: break;
    }
    geometry::clip_convex(poly_, side_of, [&](std::size_t a, std::size_t b) {
      t_ = value_[a] / (value_[a] - value_[b]);
      QPoint p;
      for (int c = 0; c < 3; ++c) p.v[c] = poly_[a].v[c] + t_ * (poly_[b].v[c] - poly_[a].v[c]);
      p.on_plane = poly_[a].on_plane && poly_[b].on_plane;
      return p;
    }, next_);
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

}  // namespace shadow::exact
