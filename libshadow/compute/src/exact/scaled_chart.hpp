// SPDX-License-Identifier: GPL-3.0-or-later
// The areas-only route's chart, scaled so that a directional light's projections are integers.
// Include only from src/exact/*.cpp or tests (GMP, CGAL).
//
// Every coordinate of the scene is an integer times 2^e, e the least set bit of them all
// (PreparedScene::chart_least_bit), and the light's direction d is an integer vector D times
// 2^f. Let c be the receiver's corner, u and v its edges from c, Y = y 2^-e, C = c 2^-e, and
// N = (u x v) 2^-2e / g (negated for a face wound the other way; g the gcd of its components),
// O = -N.C, L = N.D, all integers. A point y in front of the receiver goes along d to
//
//   x = y - s(y) d / (n.d),    s(y) = n.(y - c),
//
// and with S = N.Y + O (s(y) = g 2^3e S) its chart coordinates i, j satisfy
//
//   x_i K = Y_i L - S D_i,     K = L 2^-e    (L > 0: D's sign is chosen so),
//
// an integer. In the chart scaled by K every projected vertex is an integer, a point on the
// receiver's plane is Y_i L, and a crossing of the plane is L (S_a B_i - S_b A_i) / (S_a - S_b):
// none of the rationals of LeafProjector's unscaled route is made, whose normalisation by L's
// odd part (gcds of numbers of a hundred bits and more) was a quarter of the route's time. N is
// primitive (S, L and K scale with it, the chart does not), which keeps the integers short: a
// ground's N is (0, 0, 1). The scaling is a similarity
// with a positive factor, so every sign and comparison is the same as unscaled, and an area of
// the scaled chart is the unscaled one times K^2: the receiver's shadow is divided once.
//
// The points carry intervals around their unscaled coordinates (QPoint2), so the filters see the
// same magnitudes as unscaled; the scaled values meet doubles in interval_of, whose results
// must stay finite.
// Scenes whose coordinates span more than core::kChartSpanBits bits, and light directions
// spanning more than kDirectionSpanBits, keep the unscaled route (K = 1, LeafProjector's
// rationals): with those bounds the integers stay below 2^430, and K within 2^+-600.
#pragma once

#include "core/dyadic.hpp"
#include "core/face_prep.hpp"
#include "exact/fixed_width.hpp"
#include "exact/leaf_projector.hpp"
#include "exact/rational_points.hpp"

#include <gmp.h>
#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <optional>
#include <vector>

namespace shadow::exact {

/// The widest span of a light direction's components with integer charts (with
/// core::kChartSpanBits for the scene's coordinates).
constexpr int kDirectionSpanBits = 120;

/// A receiver's chart scaled by K (see the top of this file) for the areas-only route under a
/// directional light: projections of input points, the chart box's bounds, and the way back.
class ScaledChart {
 public:
  /// `prep`: the receiver's (or its tile's) FacePrep; `least_bit`: PreparedScene::chart_least_bit.
  ScaledChart(const std::vector<glm::dvec3>& receiver, const core::FacePrep& prep, const Light& light,
              std::optional<int> least_bit) {
    if (least_bit) integer_ = make_integer(receiver, prep, light.to_light, *least_bit);
    if (!integer_) {
      rational_.emplace(receiver, prep, light);
      scale_ = 1;
    }
    iscale_ = interval_of(scale_);
    for (int c = 0; c < 2; ++c) {
      scaled(prep.chart_min[c], lo_[c]);
      scaled(prep.chart_max[c], hi_[c]);
      ilo_[c] = IA(prep.chart_min[c]);  // intervals are of the unscaled chart (QPoint2)
      ihi_[c] = IA(prep.chart_max[c]);
    }
    if (integer_ && small_) box_fixed_ = box_bounds_fixed(prep);
  }

  /// Whether projections are integers (false: the unscaled rationals, K = 1).
  [[nodiscard]] bool integer() const { return integer_; }
  /// K.
  [[nodiscard]] const EQ& scale() const { return scale_; }
  /// Points made so far in fixed width and by GMP (the fallback) in an integer chart (tests).
  [[nodiscard]] std::size_t fixed_steps() const { return fixed_steps_; }
  [[nodiscard]] std::size_t gmp_steps() const { return gmp_steps_; }
  /// Whether make_integer decided in fixed width (tests): with integer(), N, O, D and L were
  /// made there; without it, that there is no integer chart was found there.
  [[nodiscard]] bool fixed_setup() const { return fixed_setup_; }
  /// An interval around K (clip_convex_2d's `scale`).
  [[nodiscard]] const IA& scale_interval() const { return iscale_; }
  /// The chart box's bounds in coordinate c, scaled, and their intervals (unscaled: the bounds).
  [[nodiscard]] const EQ& lo(int c) const { return lo_[c]; }
  [[nodiscard]] const EQ& hi(int c) const { return hi_[c]; }
  [[nodiscard]] const IA& ilo(int c) const { return ilo_[c]; }
  [[nodiscard]] const IA& ihi(int c) const { return ihi_[c]; }

  /// The parallel projection of an input point in front of (or on) the receiver's plane.
  void project(const glm::dvec3& y, QPoint2& out) {
    if (!integer_) return rational_->project(y, out);
    if (small_ && project_small(y, out)) {  // (its intervals from the fixed-width integers)
      ++fixed_steps_;
      return;
    }
    ++gmp_steps_;
    plane_value(y, s_);  // also sets y_
    set_integer(out.x, y_[i_], s_, d_[i_]);
    set_integer(out.y, y_[j_], s_, d_[j_]);
    set_intervals(out);
  }

  /// An input point on the receiver's plane.
  void chart(const glm::dvec3& y, QPoint2& out) {
    if (!integer_) return rational_->chart(y, out);
    if (small_ && chart_small(y, out)) {
      ++fixed_steps_;
      out.i = {IA(y[i_]), IA(y[j_])};  // exactly
      return;
    }
    ++gmp_steps_;
    exact::integer_of(y[i_], e_, a_[0].get_mpz_t());
    exact::integer_of(y[j_], e_, a_[1].get_mpz_t());
    mpz_mul(mpq_numref(out.x.get_mpq_t()), a_[0].get_mpz_t(), l_.get_mpz_t());
    mpz_set_ui(mpq_denref(out.x.get_mpq_t()), 1);
    mpz_mul(mpq_numref(out.y.get_mpq_t()), a_[1].get_mpz_t(), l_.get_mpz_t());
    mpz_set_ui(mpq_denref(out.y.get_mpq_t()), 1);
    out.i = {IA(y[i_]), IA(y[j_])};  // exactly
  }

  /// Where segment a-b crosses the receiver's plane (s(a), s(b) of strictly opposite signs).
  void crossing(const glm::dvec3& a, const glm::dvec3& b, QPoint2& out) {
    if (!integer_) return rational_->crossing(a, b, out);
    if (small_ && crossing_small(a, b, out)) {
      ++fixed_steps_;
      return set_intervals(out);
    }
    ++gmp_steps_;
    plane_value(a, s_);
    for (int k = 0; k < 3; ++k) mpz_swap(a_[k].get_mpz_t(), y_[k].get_mpz_t());  // a_ = A
    plane_value(b, t_);                                                      // y_ = B
    mpz_sub(den_.get_mpz_t(), s_.get_mpz_t(), t_.get_mpz_t());
    set_crossing(out.x, i_);
    set_crossing(out.y, j_);
    set_intervals(out);
  }

  /// Whether the front part of a convex solid (its vertices, their exact sides of the receiver's
  /// plane, its edges) certainly projects wholly beyond one side of the chart box, so that its
  /// hull clipped to the box is empty: decided exactly, in fixed width (false where a value does
  /// not fit, or the chart is not an integer one). Front vertices are projected; a crossing of
  /// the plane lies between its edge's ends' own chart coordinates (a convex combination of
  /// them), so those ends stand for it, as a point on the plane stands for itself. A chart box
  /// whose bounds are not multiples of the scene's least bit (some tiles) is never decided here.
  bool misses_box(const std::vector<glm::dvec3>& vertices, const std::vector<CGAL::Sign>& sign,
                  const std::vector<std::array<int, 2>>& edges) const {
    if (!box_fixed_) return false;
    // The sides that every point so far lies strictly beyond (bits: x below, x above, y below,
    // y above); the test ends as soon as none is left. The crossing edges' ends come first (their
    // own chart coordinates need no plane value): most solids that reach the box show it there.
    constexpr unsigned kEverySide = 15;
    unsigned beyond = kEverySide;
    bool any = false;
    const auto add = [&](fixed::i128 x0, fixed::i128 x1) {
      any = true;
      beyond &= (x0 < box_lo_[0] ? 1u : 0u) | (box_hi_[0] < x0 ? 2u : 0u) | (x1 < box_lo_[1] ? 4u : 0u) |
                (box_hi_[1] < x1 ? 8u : 0u);
      return beyond != 0;
    };
    const auto own_chart_point = [&](const glm::dvec3& y) {
      fixed::i128 x0, x1;
      return own_chart_fixed(y, x0, x1) && add(x0, x1);
    };
    for (const auto& [a, b] : edges) {
      const CGAL::Sign sa = sign[a], sb = sign[b];
      if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE))
        if (!own_chart_point(vertices[a]) || !own_chart_point(vertices[b])) return false;
    }
    for (std::size_t v = 0; v < vertices.size(); ++v) {
      if (sign[v] == CGAL::POSITIVE) {
        fixed::i128 x0, x1;
        if (!projected_fixed(vertices[v], x0, x1) || !add(x0, x1)) return false;
      } else if (sign[v] == CGAL::ZERO && !own_chart_point(vertices[v])) {
        return false;
      }
    }
    return any;
  }

  /// The part of a convex piece in front of the receiver (exact signs of its plane given),
  /// projected in order (LeafProjector::project_piece_parallel's steps).
  template <class Points>  // std::vector<QPoint2> or QPointList
  void project_piece_parallel(const std::vector<glm::dvec3>& vertices, const std::vector<int>& piece,
                              const std::vector<CGAL::Sign>& sign, Points& out) {
    out.clear();
    const std::size_t m = piece.size();
    for (std::size_t a = 0; a < m; ++a) {
      const glm::dvec3& va = vertices[piece[a]];
      const CGAL::Sign sa = sign[a], sb = sign[(a + 1) % m];
      if (sa == CGAL::POSITIVE) project(va, out.emplace_back());
      if (sa == CGAL::ZERO) chart(va, out.emplace_back());
      if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE))
        crossing(va, vertices[piece[(a + 1) % m]], out.emplace_back());
    }
  }

  /// A point of the unscaled chart (its intervals are of it), scaled.
  void scale_point(QPoint2& p) const {
    if (!integer_) return;
    p.x *= scale_;
    p.y *= scale_;
  }

  /// An area of the scaled chart as an area of the chart (divided by K^2).
  void unscale_area(EQ& area) const {
    if (!integer_) return;
    area /= scale_;
    area /= scale_;
  }

 private:
  bool make_integer(const std::vector<glm::dvec3>& receiver, const core::FacePrep& prep, const glm::dvec3& d, int e) {
    core::BitSpan direction;
    for (int k = 0; k < 3; ++k) direction.add(d[k]);
    if (direction.empty() || direction.width() > kDirectionSpanBits) return false;
    e_ = e;
    i_ = core::chart_i(prep.axis);
    j_ = core::chart_j(prep.axis);
    const int fixed_width = make_integer_fixed(receiver, prep, d, direction.least);
    fixed_setup_ = fixed_width >= 0;
    if (fixed_width >= 0) return fixed_width == 1;
    const glm::dvec3& c = receiver[prep.corner[1]];
    const glm::dvec3& next = receiver[prep.corner[2]];
    const glm::dvec3& prev = receiver[prep.corner[0]];
    mpz_class u[3], v[3], corner[3];
    for (int k = 0; k < 3; ++k) {
      exact::integer_of(c[k], e_, corner[k].get_mpz_t());
      exact::integer_of(next[k], e_, u[k].get_mpz_t());
      exact::integer_of(prev[k], e_, v[k].get_mpz_t());
      u[k] -= corner[k];
      v[k] -= corner[k];
    }
    n_[0] = u[1] * v[2] - u[2] * v[1];
    n_[1] = u[2] * v[0] - u[0] * v[2];
    n_[2] = u[0] * v[1] - u[1] * v[0];
    if (prep.flipped)
      for (mpz_class& x : n_) x = -x;
    // Any positive multiple of N gives the same chart (S and L scale with it, x does not): the
    // primitive one keeps the integers short (a ground's N is (0, 0, 1), not its area 2^-2e).
    mpz_gcd(u[0].get_mpz_t(), n_[0].get_mpz_t(), n_[1].get_mpz_t());
    mpz_gcd(u[0].get_mpz_t(), u[0].get_mpz_t(), n_[2].get_mpz_t());
    if (sgn(u[0]) == 0) return false;  // a degenerate receiver (q mode never sees one)
    for (mpz_class& x : n_) mpz_divexact(x.get_mpz_t(), x.get_mpz_t(), u[0].get_mpz_t());
    offset_ = -(n_[0] * corner[0] + n_[1] * corner[1] + n_[2] * corner[2]);
    for (int k = 0; k < 3; ++k) exact::integer_of(d[k], direction.least, d_[k].get_mpz_t());
    l_ = n_[0] * d_[0] + n_[1] * d_[1] + n_[2] * d_[2];
    if (sgn(l_) == 0) return false;  // light along the plane: no receiver in q mode sees it so
    if (sgn(l_) < 0) {
      l_ = -l_;
      for (mpz_class& x : d_) x = -x;
    }
    // K within the doubles' range by far (its interval divides the points' ones).
    const long k_bits = static_cast<long>(mpz_sizeinbase(l_.get_mpz_t(), 2)) - e_;
    if (k_bits > 600 || k_bits < -600) return false;
    mpq_set_z(scale_.get_mpq_t(), l_.get_mpz_t());
    scale_by_power_of_two(scale_, -e_);
    // The fixed-width steps need N, O, L and D below 2^126 (each step then checks its own
    // products: exact/fixed_width.hpp).
    small_ = fixed::to_i128(offset_.get_mpz_t(), so_) && fixed::to_i128(l_.get_mpz_t(), sl_);
    for (int k = 0; k < 3 && small_; ++k)
      small_ = fixed::to_i128(n_[k].get_mpz_t(), sn_[k]) && fixed::to_i128(d_[k].get_mpz_t(), sd_[k]);
    return true;
  }

  /// make_integer's N, O, D, L, K and fixed-width copies made in __int128 (the same integers
  /// as its GMP steps: a chart's setup was a twentieth of the exact series' time in them):
  /// 1 made, 0 no integer chart (as make_integer's false), -1 some value would not fit (the
  /// GMP steps then). e_, i_ and j_ are set.
  int make_integer_fixed(const std::vector<glm::dvec3>& receiver, const core::FacePrep& prep, const glm::dvec3& d,
                         int direction_least) {
    using fixed::i128;
    const auto sub = [](i128 a, i128 b, i128& r) { return !__builtin_sub_overflow(a, b, &r); };
    const auto add = [](i128 a, i128 b, i128& r) { return !__builtin_add_overflow(a, b, &r); };
    const auto mul = [](i128 a, i128 b, i128& r) { return !__builtin_mul_overflow(a, b, &r); };
    const auto cross = [&](i128 a, i128 b, i128 c, i128 f, i128& r) {  // a b - c f
      i128 x = 0, y = 0;
      return mul(a, b, x) && mul(c, f, y) && sub(x, y, r);
    };
    const glm::dvec3& cp = receiver[prep.corner[1]];
    const glm::dvec3& next = receiver[prep.corner[2]];
    const glm::dvec3& prev = receiver[prep.corner[0]];
    i128 c[3], u[3], v[3], n[3], dd[3];
    for (int k = 0; k < 3; ++k) {
      if (!small_integer_at(cp[k], e_, c[k]) || !small_integer_at(next[k], e_, u[k]) ||
          !small_integer_at(prev[k], e_, v[k]) || !sub(u[k], c[k], u[k]) || !sub(v[k], c[k], v[k]))
        return -1;
    }
    if (!cross(u[1], v[2], u[2], v[1], n[0]) || !cross(u[2], v[0], u[0], v[2], n[1]) ||
        !cross(u[0], v[1], u[1], v[0], n[2]))
      return -1;
    for (i128& x : n) {
      if (fixed::bit_width(x) > 126) return -1;
      if (prep.flipped) x = -x;
    }
    const fixed::u128 g = fixed::gcd(fixed::gcd(fixed::magnitude(n[0]), fixed::magnitude(n[1])), fixed::magnitude(n[2]));
    if (g == 0) return 0;  // a degenerate receiver
    for (i128& x : n) x /= static_cast<i128>(g);
    i128 offset = 0, l = 0;
    for (int k = 0; k < 3; ++k) {
      i128 t = 0;
      if (!mul(n[k], c[k], t) || !sub(offset, t, offset)) return -1;
      if (!small_integer_at(d[k], direction_least, dd[k]) || !mul(n[k], dd[k], t) || !add(l, t, l)) return -1;
    }
    if (fixed::bit_width(offset) > 126 || fixed::bit_width(l) > 126) return -1;
    if (l == 0) return 0;  // light along the plane
    if (l < 0) {
      l = -l;
      for (i128& x : dd) x = -x;
    }
    const long k_bits = static_cast<long>(fixed::bit_width(l)) - e_;
    if (k_bits > 600 || k_bits < -600) return 0;
    for (int k = 0; k < 3; ++k) {
      fixed::set_mpz(n_[k].get_mpz_t(), n[k]);
      fixed::set_mpz(d_[k].get_mpz_t(), dd[k]);
      sn_[k] = n[k];
      sd_[k] = dd[k];
    }
    fixed::set_mpz(offset_.get_mpz_t(), offset);
    fixed::set_mpz(l_.get_mpz_t(), l);
    so_ = offset;
    sl_ = l;
    small_ = true;  // (every value below 2^126, as fixed::to_i128 asks)
    mpq_set_z(scale_.get_mpq_t(), l_.get_mpz_t());
    scale_by_power_of_two(scale_, -e_);
    return 1;
  }

  /// The chart box's bounds scaled (lo_, hi_) in fixed width for misses_box; false where they
  /// do not fit.
  bool box_bounds_fixed(const core::FacePrep& prep) {
    for (int c = 0; c < 2; ++c)
      if (!own_coordinate_fixed(prep.chart_min[c], box_lo_[c]) || !own_coordinate_fixed(prep.chart_max[c], box_hi_[c]))
        return false;
    return true;
  }

  /// v 2^-least as an __int128 (integer_of's value) when it is below 2^126 and v a multiple of
  /// 2^least.
  static bool small_integer_at(double v, int least, fixed::i128& out) {
    if (v == 0.0) {
      out = 0;
      return true;
    }
    const core::Dyadic q = core::dyadic(v);
    const int shift = q.exponent - least;
    if (shift < 0 || shift > 126 - 53) return false;  // (below the least bit: integer_of throws)
    out = static_cast<fixed::i128>(q.mantissa) * (fixed::i128{1} << shift);
    return true;
  }

  /// v 2^-e_ as an __int128 (integer_of's value) when it is below 2^126 and v a multiple of 2^e_.
  bool small_integer_of(double v, fixed::i128& out) const { return small_integer_at(v, e_, out); }

  /// Y and S = N.Y + O of an input point in fixed width.
  bool small_plane_value(const glm::dvec3& y, fixed::i128 (&yi)[3], fixed::i128& s) const {
    for (int k = 0; k < 3; ++k)
      if (!small_integer_of(y[k], yi[k])) return false;
    return fixed::plane_value(sn_, so_, yi, s);
  }

  /// project(), chart() and crossing() in fixed width; false (out untouched or to be set again)
  /// where a bound does not hold.
  /// The scaled chart coordinates of an input point's projection (Y_k L - S D_k), in fixed width.
  bool projected_fixed(const glm::dvec3& y, fixed::i128& x0, fixed::i128& x1) const {
    fixed::i128 yi[3], s;
    return small_plane_value(y, yi, s) && fixed::projection(yi[i_], sl_, s, sd_[i_], x0) &&
           fixed::projection(yi[j_], sl_, s, sd_[j_], x1);
  }
  /// The scaled chart coordinates of an input point itself (Y_k L: its place if it lies on the
  /// plane), in fixed width.
  bool own_chart_fixed(const glm::dvec3& y, fixed::i128& x0, fixed::i128& x1) const {
    return own_coordinate_fixed(y[i_], x0) && own_coordinate_fixed(y[j_], x1);
  }
  /// One chart coordinate m scaled (m 2^-e L), in fixed width.
  bool own_coordinate_fixed(double m, fixed::i128& out) const {
    fixed::i128 a;
    return small_integer_of(m, a) && fixed::projection(a, sl_, 0, 0, out);
  }

  bool project_small(const glm::dvec3& y, QPoint2& out) const {
    fixed::i128 x0, x1;
    if (!projected_fixed(y, x0, x1)) return false;
    set_small(out.x, x0);
    set_small(out.y, x1);
    CGAL::Protect_FPU_rounding<true> guard;  // set_intervals' intervals, read off x0 and x1
    out.i = {interval_of_integer(x0) / iscale_, interval_of_integer(x1) / iscale_};
    return true;
  }
  bool chart_small(const glm::dvec3& y, QPoint2& out) const {
    fixed::i128 x0, x1;
    if (!own_chart_fixed(y, x0, x1)) return false;
    set_small(out.x, x0);
    set_small(out.y, x1);
    return true;
  }
  bool crossing_small(const glm::dvec3& a, const glm::dvec3& b, QPoint2& out) const {
    fixed::i128 ai[3], bi[3], sa, sb;
    if (!small_plane_value(a, ai, sa) || !small_plane_value(b, bi, sb)) return false;
    return fixed::crossing(sl_, sa, sb, ai[i_], bi[i_], mpq_numref(out.x.get_mpq_t()), mpq_denref(out.x.get_mpq_t())) &&
           fixed::crossing(sl_, sa, sb, ai[j_], bi[j_], mpq_numref(out.y.get_mpq_t()), mpq_denref(out.y.get_mpq_t()));
  }
  static void set_small(EQ& out, fixed::i128 v) {
    fixed::set_mpz(mpq_numref(out.get_mpq_t()), v);
    mpz_set_ui(mpq_denref(out.get_mpq_t()), 1);
  }

  /// S = N.Y + O for input point y into `out`, with Y in y_.
  void plane_value(const glm::dvec3& y, mpz_class& out) {
    out = offset_;
    for (int k = 0; k < 3; ++k) {
      exact::integer_of(y[k], e_, y_[k].get_mpz_t());
      mpz_addmul(out.get_mpz_t(), n_[k].get_mpz_t(), y_[k].get_mpz_t());
    }
  }

  /// out = Y L - S D, an integer.
  void set_integer(EQ& out, const mpz_class& y, const mpz_class& s, const mpz_class& d) const {
    mpz_ptr num = mpq_numref(out.get_mpq_t());
    mpz_mul(num, y.get_mpz_t(), l_.get_mpz_t());
    mpz_submul(num, s.get_mpz_t(), d.get_mpz_t());
    mpz_set_ui(mpq_denref(out.get_mpq_t()), 1);
  }

  /// out = L (S_a B_k - S_b A_k) / (S_a - S_b) (a_ = A, y_ = B, s_ = S_a, t_ = S_b, den_).
  void set_crossing(EQ& out, int k) {
    mpz_ptr num = mpq_numref(out.get_mpq_t());
    mpz_mul(num, s_.get_mpz_t(), y_[k].get_mpz_t());
    mpz_submul(num, t_.get_mpz_t(), a_[k].get_mpz_t());
    mpz_mul(num, num, l_.get_mpz_t());
    mpz_set(mpq_denref(out.get_mpq_t()), den_.get_mpz_t());
    mpq_canonicalize(out.get_mpq_t());
  }

  /// The point's intervals: around its unscaled coordinates (QPoint2).
  void set_intervals(QPoint2& p) const {
    CGAL::Protect_FPU_rounding<true> guard;
    p.i = {interval_of<false>(p.x) / iscale_, interval_of<false>(p.y) / iscale_};
  }

  /// m K for a chart coordinate m.
  void scaled(double m, EQ& out) const {
    if (!integer_ || m == 0.0) {
      out = m;
      return;
    }
    // m = mantissa 2^exponent, K = L 2^-e: one product and a shift (no gcd: only twos cancel).
    const core::Dyadic q = core::dyadic(m);
    mpz_mul_si(mpq_numref(out.get_mpq_t()), l_.get_mpz_t(), static_cast<long>(q.mantissa));
    mpz_set_ui(mpq_denref(out.get_mpq_t()), 1);
    scale_by_power_of_two(out, static_cast<long>(q.exponent) - e_);
  }

  bool integer_ = false;
  std::optional<LeafProjector> rational_;  ///< the unscaled route (integer_ false)
  int e_ = 0, i_ = 0, j_ = 0;
  mpz_class n_[3], offset_, d_[3], l_;
  bool small_ = false;                          ///< N, O, L, D in fixed width too (below)
  bool fixed_setup_ = false;                    ///< fixed_setup()
  std::size_t fixed_steps_ = 0, gmp_steps_ = 0;  ///< fixed_steps(), gmp_steps()
  fixed::i128 sn_[3] = {}, so_ = 0, sl_ = 0, sd_[3] = {};
  bool box_fixed_ = false;                      ///< box_lo_ and box_hi_ made (box_bounds_fixed)
  fixed::i128 box_lo_[2] = {}, box_hi_[2] = {};  ///< lo_ and hi_ in fixed width
  EQ scale_;
  IA iscale_;
  EQ lo_[2], hi_[2];
  IA ilo_[2], ihi_[2];
  mpz_class y_[3], a_[3], s_, t_, den_;  // scratch, to avoid reallocating limbs
};

}  // namespace shadow::exact
