// SPDX-License-Identifier: GPL-3.0-or-later
// Plain GMP rational points with filtered predicates: the exact engine's areas-only route keeps
// its casts in these instead of lazy Epeck points. Every first exact() of a lazy number runs a
// std::call_once, whose slow path ends in a futex system call; the areas-only route needs the
// exact value of nearly every vertex, and those calls were a fifth of its time. Here the exact
// values are the numbers themselves (mostly integers: the route works in a scaled chart,
// exact/scaled_chart.hpp), and each point carries its filter intervals, made once.
// Include only from src/exact/*.cpp or tests (CGAL).
#pragma once

#include "exact/fixed_width.hpp"
#include "exact/kernel.hpp"
#include "geometry/clip_convex.hpp"

#include <CGAL/Interval_nt.h>

#include <gmpxx.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

namespace shadow::exact {

/// The exact rationals of the kernel (GMP's mpq_class in this build).
using EQ = FT::Exact_type;
static_assert(std::is_same_v<EQ, mpq_class>, "rational_points.hpp expects Epeck over mpq_class");

using IA = CGAL::Interval_nt<false>;  ///< only under CGAL::Protect_FPU_rounding

/// 2^e for e in [-1022, 1023] (a normal double), made from its bits: a product with it is
/// ldexp's exact result wherever that is normal, without ldexp's library call (a projection's
/// point takes two conversions: a per-cent of the exact path).
inline double power_of_two(int e) {
  assert(e >= -1022 && e <= 1023);
  const std::uint64_t bits = static_cast<std::uint64_t>(1023 + e) << 52;
  double p;
  std::memcpy(&p, &bits, sizeof p);
  return p;
}

/// An interval around q: the value itself when it is a double (a dyadic numerator of at most 53
/// bits), else the quotient of intervals around the numerator's and the denominator's leading
/// bits (mpz_get_d_2exp truncates toward zero: one ulp each, on the far side from zero; none
/// for a denominator that is a power of two), scaled back by their exponents. This
/// reads only the top limbs; mpq_get_d divides the whole numbers. kSetRounding false: the
/// caller holds a CGAL::Protect_FPU_rounding<true> (the rest is exact under any rounding mode:
/// GMP's conversions truncate bit by bit; nextafter, and products by powers of two into the
/// normal range, are exact).
template <bool kSetRounding = true>
inline IA interval_of(const EQ& q) {
  const mpq_srcptr r = q.get_mpq_t();
  const mpz_srcptr num = mpq_numref(r), den = mpq_denref(r);
  if (mpz_sgn(num) == 0) return IA(0.0);
  long en = 0, ed = 0;
  const double n = mpz_get_d_2exp(&en, num);  // |n| in [0.5, 1), num ~ n 2^en
  const double d = mpz_get_d_2exp(&ed, den);
  if (mpz_popcount(den) == 1 && mpz_sizeinbase(num, 2) <= 53) {
    // q = n 2^x exactly (den = 2^(ed - 1)), a double when it is in the normal range: with |n| in
    // [0.5, 1) that is x in [-1021, 1024]. Decided on x, not on the product: a value just
    // below the least normal double would round up to it and pass for exact.
    const long x = en - ed + 1;
    if (x >= -1021 && x <= 1024) return IA((2 * n) * power_of_two(static_cast<int>(x - 1)));  // exactly
  }
  const long shift = en - ed;
  if (shift > 900 || shift < -900) {  // out of a safe exponent range: the slow, exact way
    constexpr double inf = std::numeric_limits<double>::infinity();
    const double t = mpq_get_d(r);
    return IA(std::nextafter(t, -inf), std::nextafter(t, inf));
  }
  constexpr double inf = std::numeric_limits<double>::infinity();
  CGAL::Protect_FPU_rounding<kSetRounding> guard;
  // Truncation is toward zero: |num| lies in [|n|, |n| + ulp) 2^en, one ulp on n's far side; a
  // power of two (an integer's 1, a dyadic's 2^k) is exact.
  const IA in = n > 0 ? IA(n, std::nextafter(n, inf)) : IA(std::nextafter(n, -inf), n);
  const IA id = mpz_popcount(den) == 1 ? IA(d) : IA(d, std::nextafter(d, inf));
  const IA quotient = in / id;  // in (-2.1, 2.1), away from under- and overflow
  const double scale = power_of_two(static_cast<int>(shift));  // |shift| <= 900: products stay normal
  return IA(quotient.inf() * scale, quotient.sup() * scale);
}

/// interval_of of the integer v, from its fixed-width value: the same interval (v itself below
/// 2^53; else its top 53 bits truncated toward zero, T, and [T, T + ulp] on the far side from
/// zero, as mpz_get_d_2exp's truncation gives), without GMP's conversions. Exact under any
/// rounding mode (53-bit integers and powers of two).
inline IA interval_of_integer(fixed::i128 v) {
  if (v == 0) return IA(0.0);
  const fixed::u128 m = fixed::magnitude(v);
  const int drop = fixed::bit_width(m) - 53;
  if (drop <= 0) return IA(static_cast<double>(v));
  const double t = static_cast<double>(static_cast<std::uint64_t>(m >> drop));
  const double scale = power_of_two(drop);  // drop in [1, 75]: t and t + 1 (at most 2^53) scale exactly
  const double lo = t * scale, hi = (t + 1) * scale;
  return v > 0 ? IA(lo, hi) : IA(-hi, -lo);
}

/// A point's intervals.
struct IPoint2 {
  IA x, y;
};

/// A point with exact rational coordinates, and intervals around them for the filters. In a
/// scaled chart (exact/scaled_chart.hpp) x and y are the scaled coordinates and the intervals are
/// around the unscaled ones (x / K): every predicate here is invariant under a positive scale,
/// and a coordinate that is a double unscaled (a point on the receiver's plane, a cut at a chart
/// bound) keeps an interval that is that point, so that its ties (boxes' shared coordinates)
/// are decided without GMP. Made from coordinates alone, the intervals are around them (K = 1).
/// Invariant: an interval that is a point is the exact unscaled coordinate (the clip relies on
/// it). Default-made, the intervals are the whole line (every filter then defers to the exact
/// values) until set.
struct QPoint2 {
  EQ x, y;
  IPoint2 i{IA::largest(), IA::largest()};

  QPoint2() = default;
  QPoint2(EQ x_, EQ y_) : x(std::move(x_)), y(std::move(y_)) { update_intervals(); }
  QPoint2(EQ x_, EQ y_, const IPoint2& i_) : x(std::move(x_)), y(std::move(y_)), i(i_) {}
  /// The intervals around x and y (after setting them in an unscaled chart).
  void update_intervals() { i = {interval_of(x), interval_of(y)}; }
};

/// Swaps two points without allocating: std::swap moves through a temporary, and a moved-from
/// mpq_class is made again with mpq_init, which allocates its denominator (found by ADL:
/// std::reverse and std::iter_swap use it).
inline void swap(QPoint2& a, QPoint2& b) noexcept {
  mpq_swap(a.x.get_mpq_t(), b.x.get_mpq_t());
  mpq_swap(a.y.get_mpq_t(), b.y.get_mpq_t());
  std::swap(a.i, b.i);
}

/// A list of points whose slots outlive clear(): the next point written into a slot reuses its
/// GMP limbs. A std::vector<QPoint2> frees four limb arrays per point on clear() and allocates
/// them again when the next cast is projected, copied or clipped; the areas route does that
/// for every vertex of every cast, and the allocator was a sixth of its time (docs/benchmarks.md,
/// "Eighth look"). The subset of std::vector's interface the route uses.
class QPointList {
 public:
  [[nodiscard]] std::size_t size() const { return n_; }
  [[nodiscard]] bool empty() const { return n_ == 0; }
  void clear() { n_ = 0; }
  /// A new last point: a slot with stale coordinates (the caller sets both) and intervals that
  /// are the whole line, as a default-made QPoint2's.
  QPoint2& emplace_back() {
    if (n_ == slots_.size()) slots_.emplace_back();
    QPoint2& p = slots_[n_++];
    p.i = {IA::largest(), IA::largest()};
    return p;
  }
  /// Appends a copy of p (into the slot's limbs: no allocation once they are large enough).
  void push_back(const QPoint2& p) {
    QPoint2& slot = emplace_back();
    slot.x = p.x;
    slot.y = p.y;
    slot.i = p.i;
  }
  /// Appends p by swapping it in (p is left with the slot's stale values).
  void push_back_swap(QPoint2& p) { exact::swap(emplace_back(), p); }
  void pop_back() { --n_; }
  [[nodiscard]] QPoint2& back() { return slots_[n_ - 1]; }
  [[nodiscard]] const QPoint2& back() const { return slots_[n_ - 1]; }
  [[nodiscard]] QPoint2& operator[](std::size_t k) { return slots_[k]; }
  [[nodiscard]] const QPoint2& operator[](std::size_t k) const { return slots_[k]; }
  [[nodiscard]] QPoint2* data() { return slots_.data(); }
  [[nodiscard]] const QPoint2* data() const { return slots_.data(); }
  [[nodiscard]] QPoint2* begin() { return slots_.data(); }
  [[nodiscard]] QPoint2* end() { return slots_.data() + n_; }
  [[nodiscard]] const QPoint2* begin() const { return slots_.data(); }
  [[nodiscard]] const QPoint2* end() const { return slots_.data() + n_; }
  void swap(QPointList& other) noexcept {
    slots_.swap(other.slots_);
    std::swap(n_, other.n_);
  }

 private:
  std::vector<QPoint2> slots_;
  std::size_t n_ = 0;
};

/// A point's intervals (QPoint2::i).
inline const IPoint2& interval_of(const QPoint2& p) {
  assert(p.i.x.inf() <= p.i.x.sup() && p.i.y.inf() <= p.i.y.sup());
  return p.i;
}

/// Scratch rationals for the exact fallbacks (no allocation once grown), and integers for their
/// integer paths.
struct QScratch {
  EQ a, b, c, d;
  mpz_class za, zb, zc, zd, ze, zf;
};

/// Whether q is an integer. The areas route's points mostly are (exact/scaled_chart.hpp), and
/// GMP's rational sums multiply by both denominators and take a gcd even when they are 1: on
/// integers the exact steps below use integer arithmetic, with the same results.
inline bool is_integer(const EQ& q) { return mpz_cmp_ui(mpq_denref(q.get_mpq_t()), 1) == 0; }
inline bool is_integer(const QPoint2& p) { return is_integer(p.x) && is_integer(p.y); }
inline mpz_srcptr num(const EQ& q) { return mpq_numref(q.get_mpq_t()); }
inline mpz_srcptr den(const EQ& q) { return mpq_denref(q.get_mpq_t()); }

/// acc += cross(p, q) for integer points p and q (a shoelace term).
inline void add_integer_cross(mpz_class& acc, const QPoint2& p, const QPoint2& q) {
  mpz_addmul(acc.get_mpz_t(), num(p.x), num(q.y));
  mpz_submul(acc.get_mpz_t(), num(p.y), num(q.x));
}

/// x1 - x0 as the fraction n / e with e > 0, not normalised (no gcd).
inline void difference_fraction(const EQ& x1, const EQ& x0, mpz_ptr n, mpz_ptr e) {
  const mpz_srcptr n1 = mpq_numref(x1.get_mpq_t()), e1 = mpq_denref(x1.get_mpq_t());
  const mpz_srcptr n0 = mpq_numref(x0.get_mpq_t()), e0 = mpq_denref(x0.get_mpq_t());
  mpz_mul(n, n1, e0);
  mpz_submul(n, n0, e1);
  mpz_mul(e, e0, e1);
}

/// crossing_parameter's integers, kept by the caller (their limbs reused).
struct ParameterScratch {
  mpz_class f[12], z;
};

/// Where the line through u and u2 crosses the line through s and s2, as the parameter of
/// s + t (s2 - s): t = cross(u2 - u, u - s) / cross(u2 - u, s2 - s) = tn / td with td > 0, not
/// normalised (no gcd: the caller compares and subtracts such fractions, and normalises only
/// what it keeps). In integers when the four points are (the scaled charts' points), else over
/// the differences' denominators. The lines must not be parallel (td != 0).
inline void crossing_parameter(const QPoint2& s, const QPoint2& s2, const QPoint2& u, const QPoint2& u2, mpz_ptr tn,
                               mpz_ptr td, QScratch& scratch, ParameterScratch& ps) {
  if (is_integer(s) && is_integer(s2) && is_integer(u) && is_integer(u2)) {
    mpz_ptr fx = scratch.za.get_mpz_t();
    mpz_ptr fy = scratch.zb.get_mpz_t();
    mpz_ptr z = scratch.zc.get_mpz_t();
    mpz_sub(fx, num(u2.x), num(u.x));
    mpz_sub(fy, num(u2.y), num(u.y));
    mpz_sub(z, num(u.y), num(s.y));
    mpz_mul(tn, fx, z);
    mpz_sub(z, num(u.x), num(s.x));
    mpz_submul(tn, fy, z);
    mpz_sub(z, num(s2.y), num(s.y));
    mpz_mul(td, fx, z);
    mpz_sub(z, num(s2.x), num(s.x));
    mpz_submul(td, fy, z);
  } else {
    // The same with every difference a fraction (n / e, e > 0): N1 / D1 = cross(f, u - s) and
    // N2 / D2 = cross(f, s2 - s) share f's denominators, so t = N1 e_dx e_dy / (N2 e_ux e_uy).
    mpz_ptr f[12];
    for (int k = 0; k < 12; ++k) f[k] = ps.f[k].get_mpz_t();
    enum { nfx, efx, nfy, efy, nux, eux, nuy, euy, ndx, edx, ndy, edy };
    difference_fraction(u2.x, u.x, f[nfx], f[efx]);
    difference_fraction(u2.y, u.y, f[nfy], f[efy]);
    difference_fraction(u.x, s.x, f[nux], f[eux]);
    difference_fraction(u.y, s.y, f[nuy], f[euy]);
    difference_fraction(s2.x, s.x, f[ndx], f[edx]);
    difference_fraction(s2.y, s.y, f[ndy], f[edy]);
    mpz_ptr z = ps.z.get_mpz_t();
    // cross(f, v) over a common denominator, nfx nvy efy evx - nfy nvx efx evy, times m1 m2.
    const auto cross_with_f = [&](mpz_ptr out, mpz_srcptr nvx, mpz_srcptr evx, mpz_srcptr nvy, mpz_srcptr evy,
                                  mpz_srcptr m1, mpz_srcptr m2) {
      mpz_mul(out, f[nfx], nvy);
      mpz_mul(out, out, f[efy]);
      mpz_mul(out, out, evx);
      mpz_mul(z, f[nfy], nvx);
      mpz_mul(z, z, f[efx]);
      mpz_mul(z, z, evy);
      mpz_sub(out, out, z);
      mpz_mul(out, out, m1);
      mpz_mul(out, out, m2);
    };
    cross_with_f(tn, f[nux], f[eux], f[nuy], f[euy], f[edx], f[edy]);  // N1, times e_dx e_dy
    cross_with_f(td, f[ndx], f[edx], f[ndy], f[edy], f[eux], f[euy]);  // N2, times e_ux e_uy
  }
  if (mpz_sgn(td) < 0) {
    mpz_neg(tn, tn);
    mpz_neg(td, td);
  }
}

/// Sign of (a1 - a0)(b1 - b0) + k (c1 - c0)(d1 - d0), k = 1 or -1, exactly: in integers when
/// all eight are (GMP's rational steps would multiply by denominators of 1 and take gcds), else
/// in rationals. The filtered predicates' exact step.
[[gnu::noinline]] inline CGAL::Sign sign_of_products(const EQ& a1, const EQ& a0, const EQ& b1, const EQ& b0,
                                                     const EQ& c1, const EQ& c0, const EQ& d1, const EQ& d0, int k,
                                                     QScratch& s) {
  if (is_integer(a1) && is_integer(a0) && is_integer(b1) && is_integer(b0) && is_integer(c1) && is_integer(c0) &&
      is_integer(d1) && is_integer(d0)) {
    mpz_sub(s.zb.get_mpz_t(), num(a1), num(a0));
    mpz_sub(s.zc.get_mpz_t(), num(b1), num(b0));
    mpz_mul(s.za.get_mpz_t(), s.zb.get_mpz_t(), s.zc.get_mpz_t());
    mpz_sub(s.zb.get_mpz_t(), num(c1), num(c0));
    mpz_sub(s.zc.get_mpz_t(), num(d1), num(d0));
    if (k > 0)
      mpz_addmul(s.za.get_mpz_t(), s.zb.get_mpz_t(), s.zc.get_mpz_t());
    else
      mpz_submul(s.za.get_mpz_t(), s.zb.get_mpz_t(), s.zc.get_mpz_t());
    return static_cast<CGAL::Sign>(sgn(s.za));
  }
  // Rationals: x1 - x0 = (n1 e0 - n0 e1) / (e0 e1) with positive denominators e, so the sign is
  // that of nA nB eC eD + k nC nD eA eB, in integers: no gcd (GMP's rational steps take one
  // after every sum and product, and only the sign is wanted).
  mpz_ptr na = mpq_numref(s.a.get_mpq_t()), ea = mpq_denref(s.a.get_mpq_t());
  mpz_ptr nb = mpq_numref(s.b.get_mpq_t()), eb = mpq_denref(s.b.get_mpq_t());
  mpz_ptr nc = mpq_numref(s.c.get_mpq_t()), ec = mpq_denref(s.c.get_mpq_t());
  mpz_ptr nd = mpq_numref(s.d.get_mpq_t()), ed = mpq_denref(s.d.get_mpq_t());
  difference_fraction(a1, a0, na, ea);
  difference_fraction(b1, b0, nb, eb);
  difference_fraction(c1, c0, nc, ec);
  difference_fraction(d1, d0, nd, ed);
  mpz_mul(na, na, nb);  // nA nB
  mpz_mul(na, na, ec);
  mpz_mul(na, na, ed);
  mpz_mul(nc, nc, nd);  // nC nD
  mpz_mul(nc, nc, ea);
  mpz_mul(nc, nc, eb);
  if (k > 0)
    mpz_add(na, na, nc);
  else
    mpz_sub(na, na, nc);
  const int result = mpz_sgn(na);
  // The scratch rationals now hold non-canonical values: leave them canonical (zero) for the
  // next user of QScratch, which may read them as rationals.
  mpq_set_ui(s.a.get_mpq_t(), 0, 1);
  mpq_set_ui(s.b.get_mpq_t(), 0, 1);
  mpq_set_ui(s.c.get_mpq_t(), 0, 1);
  mpq_set_ui(s.d.get_mpq_t(), 0, 1);
  return static_cast<CGAL::Sign>(result);
}

/// Sign of cross(q - p, r - p): LEFT_TURN (positive) when p, q, r turn left. Filtered.
/// kSetRounding false: the caller already holds a CGAL::Protect_FPU_rounding<true> (the interval
/// filter needs rounding upward; setting it and back costs two MXCSR writes, a large share of a
/// filtered predicate in a loop). The exact fallback is integer arithmetic (GMP), which the
/// rounding mode does not touch.
template <bool kSetRounding = true>
inline CGAL::Sign orientation(const QPoint2& p, const IPoint2& ip, const QPoint2& q, const IPoint2& iq,
                              const QPoint2& r, const IPoint2& ir, QScratch& s) {
  {
    CGAL::Protect_FPU_rounding<kSetRounding> guard;
    const CGAL::Uncertain<CGAL::Sign> sign = CGAL::sign((iq.x - ip.x) * (ir.y - ip.y) - (iq.y - ip.y) * (ir.x - ip.x));
    if (CGAL::is_certain(sign)) return CGAL::get_certain(sign);
  }
  return sign_of_products(q.x, p.x, r.y, p.y, q.y, p.y, r.x, p.x, -1, s);
}

/// Sign of dot(q - p, s - r). Filtered (kSetRounding as for orientation).
template <bool kSetRounding = true>
inline CGAL::Sign dot_sign(const QPoint2& p, const IPoint2& ip, const QPoint2& q, const IPoint2& iq, const QPoint2& r,
                           const IPoint2& ir, const QPoint2& t, const IPoint2& it, QScratch& s) {
  {
    CGAL::Protect_FPU_rounding<kSetRounding> guard;
    const CGAL::Uncertain<CGAL::Sign> sign = CGAL::sign((iq.x - ip.x) * (it.x - ir.x) + (iq.y - ip.y) * (it.y - ir.y));
    if (CGAL::is_certain(sign)) return CGAL::get_certain(sign);
  }
  return sign_of_products(q.x, p.x, t.x, r.x, q.y, p.y, t.y, r.y, 1, s);
}

/// Compares two rationals with their intervals.
inline int compare(const EQ& a, const IA& ia, const EQ& b, const IA& ib) {
  if (ia.sup() < ib.inf()) return -1;
  if (ia.inf() > ib.sup()) return 1;
  if (ia.is_point() && ib.is_point()) return ia.inf() < ib.inf() ? -1 : ia.inf() > ib.inf() ? 1 : 0;
  return cmp(a, b);
}

/// Twice the signed area of pts[begin, end), exactly (shoelace).
inline void twice_polygon_area(const QPoint2* begin, const QPoint2* end, EQ& out, QScratch& s) {
  out = 0;
  const std::size_t n = static_cast<std::size_t>(end - begin);
  if (std::all_of(begin, end, [](const QPoint2& p) { return is_integer(p); })) {
    s.za = 0;
    for (std::size_t a = 0; a < n; ++a) add_integer_cross(s.za, begin[a], begin[(a + 1) % n]);
    mpq_set_z(out.get_mpq_t(), s.za.get_mpz_t());
    return;
  }
  for (std::size_t a = 0; a < n; ++a) {
    const QPoint2& p = begin[a];
    const QPoint2& q = begin[(a + 1) % n];
    s.a = p.x * q.y;
    s.b = p.y * q.x;
    s.a -= s.b;
    out += s.a;
  }
}

/// Twice the signed area's sign of the polygon pts[0..n) (fan from the first vertex). Filtered;
/// `sum` receives twice the area when the filter cannot decide.
template <class Points>  // std::vector<QPoint2> or QPointList
CGAL::Sign area_sign(const Points& pts, QScratch& s, EQ& sum) {
  const std::size_t n = pts.size();
  if (n < 3) return CGAL::ZERO;
  {
    CGAL::Protect_FPU_rounding<true> guard;
    const IPoint2& i0 = pts[0].i;
    IA total(0);
    for (std::size_t a = 1; a + 1 < n; ++a) {
      const IPoint2& ia = pts[a].i;
      const IPoint2& ib = pts[a + 1].i;
      total += (ia.x - i0.x) * (ib.y - i0.y) - (ia.y - i0.y) * (ib.x - i0.x);
    }
    const CGAL::Uncertain<CGAL::Sign> sign = CGAL::sign(total);
    if (CGAL::is_certain(sign)) return CGAL::get_certain(sign);
  }
  twice_polygon_area(pts.data(), pts.data() + n, sum, s);
  return static_cast<CGAL::Sign>(sgn(sum));
}

/// The convex hull of `pts` (counter-clockwise, no collinear or repeated vertices) into `out`
/// (Andrew's monotone chain with filtered predicates; `Points`: std::vector<QPoint2> or QPointList).
template <class Points>
void convex_hull(Points& pts, Points& out, std::vector<std::size_t>& order, std::vector<std::size_t>& chain,
                 QScratch& s) {
  const std::size_t n = pts.size();
  out.clear();
  CGAL::Protect_FPU_rounding<true> guard;  // once for every filter below (GMP needs no mode)
  order.resize(n);
  for (std::size_t a = 0; a < n; ++a) order[a] = a;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const int cx = compare(pts[a].x, pts[a].i.x, pts[b].x, pts[b].i.x);
    if (cx != 0) return cx < 0;
    return compare(pts[a].y, pts[a].i.y, pts[b].y, pts[b].i.y) < 0;
  });
  if (n < 3) {
    for (std::size_t a : order) out.push_back(pts[a]);
    return;
  }
  chain.clear();
  auto turn = [&](std::size_t a, std::size_t b, std::size_t c) {
    return orientation<false>(pts[a], pts[a].i, pts[b], pts[b].i, pts[c], pts[c].i, s);
  };
  for (std::size_t k = 0; k < n; ++k) {  // lower hull
    while (chain.size() >= 2 && turn(chain[chain.size() - 2], chain.back(), order[k]) != CGAL::POSITIVE) chain.pop_back();
    chain.push_back(order[k]);
  }
  const std::size_t lower = chain.size() + 1;
  for (std::size_t k = n - 1; k-- > 0;) {  // upper hull
    while (chain.size() >= lower && turn(chain[chain.size() - 2], chain.back(), order[k]) != CGAL::POSITIVE) chain.pop_back();
    chain.push_back(order[k]);
  }
  chain.pop_back();  // the first point again
  for (std::size_t a : chain) out.push_back(pts[a]);
}

/// Sutherland-Hodgman clip of a convex polygon to x_c >= m (keep_greater) or x_c <= m, with m
/// given exactly and as an interval (both as the points are: scaled and unscaled, QPoint2); the
/// crossings get m exactly in coordinate c. `scale`: an interval around the chart's scale K
/// (1 unscaled), for the crossings' other intervals. `Points`: std::vector<QPoint2> or
/// QPointList (whose slots keep their limbs: the kept vertices and the cuts are written into
/// `scratch`'s slots, not made anew).
template <class Points>
void clip_convex_2d(Points& poly, int c, const EQ& bound, const IA& ibound, bool keep_greater, Points& scratch,
                    std::vector<int>& in, const IA& scale) {
  if (poly.empty()) return;
  const std::size_t n = poly.size();
  in.resize(n);
  for (std::size_t a = 0; a < n; ++a) {
    const EQ& v = c == 0 ? poly[a].x : poly[a].y;
    const int r = compare(v, c == 0 ? poly[a].i.x : poly[a].i.y, bound, ibound);
    in[a] = keep_greater ? r : -r;
  }
  auto side = [&](std::size_t a) { return in[a]; };
  switch (geometry::clip_case(n, side)) {
    case geometry::ClipCase::Inside: return;
    case geometry::ClipCase::Empty: poly.clear(); return;
    case geometry::ClipCase::Cut: break;
  }
  const bool unscaled = scale.is_point() && scale.inf() == 1.0;
  const bool integer_bound = is_integer(bound);
  // The cut of edge a-b: bound in coordinate c, `other` (in the new slot) in the other one.
  auto cut = [&](std::size_t a, std::size_t b) {
    const QPoint2& pa = poly[a];
    const QPoint2& pb = poly[b];
    QPoint2& out = scratch.emplace_back();
    EQ& other = c == 0 ? out.y : out.x;
    EQ& at = c == 0 ? out.x : out.y;  // bound, set last: its limbs are fixed::cut's scratch first
    IA& iother = c == 0 ? out.i.y : out.i.x;
    (c == 0 ? out.i.x : out.i.y) = ibound;
    const EQ& ac = c == 0 ? pa.x : pa.y;
    const EQ& ao = c == 0 ? pa.y : pa.x;
    const EQ& bc = c == 0 ? pb.x : pb.y;
    const EQ& bo = c == 0 ? pb.y : pb.x;
    const IA& iao = c == 0 ? pa.i.y : pa.i.x;
    const IA& ibo = c == 0 ? pb.i.y : pb.i.x;
    if (iao.is_point() && ibo.is_point() && iao.inf() == ibo.inf()) {
      // Both ends at one exact double (an edge along the other bound): so is the cut, exactly.
      other = ao;
      iother = iao;
      at = bound;
      return;
    }
    fixed::i128 fao, fbo, fac, fbc, fm;
    if (integer_bound && is_integer(pa) && is_integer(pb) && fixed::to_i128(num(ao), fao) &&
        fixed::to_i128(num(bo), fbo) && fixed::to_i128(num(ac), fac) && fixed::to_i128(num(bc), fbc) &&
        fixed::to_i128(num(bound), fm) &&
        fixed::cut(fao, fbo, fac, fbc, fm, mpq_numref(other.get_mpq_t()), mpq_denref(other.get_mpq_t()),
                   mpq_numref(at.get_mpq_t()))) {
      // the canonical fraction in fixed width (exact/fixed_width.hpp), else GMP's below
    } else if (integer_bound && is_integer(pa) && is_integer(pb)) {
      // (ao (bc - m) + bo (m - ac)) / (bc - ac), one normalisation
      mpz_ptr on = mpq_numref(other.get_mpq_t());
      mpz_ptr od = mpq_denref(other.get_mpq_t());
      mpz_sub(od, num(bc), num(bound));
      mpz_mul(on, num(ao), od);
      mpz_sub(od, num(bound), num(ac));
      mpz_addmul(on, num(bo), od);
      mpz_sub(od, num(bc), num(ac));
      mpq_canonicalize(other.get_mpq_t());
    } else {
      // Fraction-free, one normalisation: with x = X / x' for each of ac, bc, ao, bo and m,
      // other = (Ao bo' ac' (Bc m' - M bc') + Bo ao' bc' (M ac' - Ac m')) / ((Bc ac' - Ac bc') ao' bo' m').
      mpz_ptr on = mpq_numref(other.get_mpq_t());
      mpz_ptr od = mpq_denref(other.get_mpq_t());
      mpz_ptr t = mpq_numref(at.get_mpq_t());  // scratch: at is set to the bound below
      mpz_mul(on, num(bc), den(bound));  // Bc m' - M bc'
      mpz_submul(on, num(bound), den(bc));
      mpz_mul(on, on, num(ao));
      mpz_mul(on, on, den(bo));
      mpz_mul(on, on, den(ac));
      mpz_mul(t, num(bound), den(ac));  // M ac' - Ac m'
      mpz_submul(t, num(ac), den(bound));
      mpz_mul(t, t, num(bo));
      mpz_mul(t, t, den(ao));
      mpz_mul(t, t, den(bc));
      mpz_add(on, on, t);
      mpz_mul(od, num(bc), den(ac));  // Bc ac' - Ac bc'
      mpz_submul(od, num(ac), den(bc));
      mpz_mul(od, od, den(ao));
      mpz_mul(od, od, den(bo));
      mpz_mul(od, od, den(bound));
      mpq_canonicalize(other.get_mpq_t());
    }
    at = bound;
    CGAL::Protect_FPU_rounding<true> guard;
    iother = interval_of<false>(other);
    if (!unscaled) iother = iother / scale;
  };
  // geometry::clip_convex's walk, writing into scratch's slots.
  scratch.clear();
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t b = (a + 1) % n;
    const int sa = side(a), sb = side(b);
    if (sa >= 0) scratch.push_back(poly[a]);
    if ((sa > 0 && sb < 0) || (sa < 0 && sb > 0)) cut(a, b);
  }
  poly.swap(scratch);
}

/// Where edge a-b crosses the line through p and q (a and b strictly on opposite sides), into
/// `out`: with s(u) = cross(q - p, u - p), the point (s(a) b - s(b) a) / (s(a) - s(b)). In
/// integers with one normalisation per coordinate when the window's corners are integers (a
/// scaled chart's receiver vertices), else in rationals; the same canonical values.
/// The intervals as clip_convex_2d's cuts get them (`scale` around K, of the unscaled chart).
inline void cut_by_line(const QPoint2& p, const QPoint2& q, const QPoint2& a, const QPoint2& b, QPoint2& out,
                        const IA& scale, QScratch& s) {
  if (is_integer(p) && is_integer(q)) {
    // Fraction-free: with a = (A_x / a_x, A_y / a_y) (and b alike) and integer p, q,
    // s(a) = S_a / (a_x a_y), S_a = dx (A_y - p_y a_y) a_x - dy (A_x - p_x a_x) a_y; with
    // U = S_a b_x b_y and V = S_b a_x a_y, x = (U B_x a_x - V A_x b_x) / ((U - V) a_x b_x) and y
    // alike: one normalisation per coordinate (GMP's rational steps take a gcd after each).
    // Integer points make every denominator 1.
    mpz_sub(s.zd.get_mpz_t(), num(q.x), num(p.x));  // dx
    mpz_sub(s.ze.get_mpz_t(), num(q.y), num(p.y));  // dy
    auto side = [&](const QPoint2& u, mpz_class& to) {
      mpz_mul(s.zf.get_mpz_t(), num(p.y), den(u.y));
      mpz_sub(s.zf.get_mpz_t(), num(u.y), s.zf.get_mpz_t());
      mpz_mul(to.get_mpz_t(), s.zd.get_mpz_t(), s.zf.get_mpz_t());
      mpz_mul(to.get_mpz_t(), to.get_mpz_t(), den(u.x));
      mpz_mul(s.zf.get_mpz_t(), num(p.x), den(u.x));
      mpz_sub(s.zf.get_mpz_t(), num(u.x), s.zf.get_mpz_t());
      mpz_mul(s.zf.get_mpz_t(), s.zf.get_mpz_t(), den(u.y));
      mpz_submul(to.get_mpz_t(), s.ze.get_mpz_t(), s.zf.get_mpz_t());
    };
    side(a, s.za);
    side(b, s.zb);
    mpz_mul(s.za.get_mpz_t(), s.za.get_mpz_t(), den(b.x));  // U
    mpz_mul(s.za.get_mpz_t(), s.za.get_mpz_t(), den(b.y));
    mpz_mul(s.zb.get_mpz_t(), s.zb.get_mpz_t(), den(a.x));  // V
    mpz_mul(s.zb.get_mpz_t(), s.zb.get_mpz_t(), den(a.y));
    mpz_sub(s.zc.get_mpz_t(), s.za.get_mpz_t(), s.zb.get_mpz_t());  // U - V, not zero
    auto coordinate = [&](const EQ& ac, const EQ& bc, EQ& to) {
      mpz_ptr n = mpq_numref(to.get_mpq_t());
      mpz_ptr d = mpq_denref(to.get_mpq_t());
      mpz_mul(n, s.za.get_mpz_t(), num(bc));
      mpz_mul(n, n, den(ac));
      mpz_mul(s.zf.get_mpz_t(), s.zb.get_mpz_t(), num(ac));
      mpz_mul(s.zf.get_mpz_t(), s.zf.get_mpz_t(), den(bc));
      mpz_sub(n, n, s.zf.get_mpz_t());
      mpz_mul(d, s.zc.get_mpz_t(), den(ac));
      mpz_mul(d, d, den(bc));
      mpq_canonicalize(to.get_mpq_t());
    };
    coordinate(a.x, b.x, out.x);
    coordinate(a.y, b.y, out.y);
  } else {
    auto side = [&](const QPoint2& u, EQ& to) {
      s.c = u.y - p.y;
      s.d = q.x - p.x;
      to = s.c * s.d;
      s.c = u.x - p.x;
      s.d = q.y - p.y;
      s.c *= s.d;
      to -= s.c;
    };
    side(a, s.a);
    side(b, s.b);
    s.b = s.a - s.b;
    s.a /= s.b;  // t = s(a) / (s(a) - s(b))
    out.x = b.x - a.x;
    out.x *= s.a;
    out.x += a.x;
    out.y = b.y - a.y;
    out.y *= s.a;
    out.y += a.y;
  }
  CGAL::Protect_FPU_rounding<true> guard;
  out.i = {interval_of<false>(out.x), interval_of<false>(out.y)};
  if (!(scale.is_point() && scale.inf() == 1.0)) out.i = {out.i.x / scale, out.i.y / scale};
}

/// Sutherland-Hodgman clip of a convex polygon to the convex counter-clockwise polygon `window`
/// (each edge's closed left side), both in one chart (scaled or not, `scale` around its K): the
/// rational points' counterpart of lazy_geometry.hpp's clip_convex_to_window, the same exact
/// points. Sides by the filtered orientation; vertices on a window edge are kept. (The engine
/// measures casts in a window without clipping them, ConvexUnionArea::twice_area_in_window; the
/// tests check that measure against this clip followed by the plain union.)
template <class Points>
void clip_convex_to_window(Points& poly, const Points& window, Points& scratch, std::vector<int>& in,
                           const IA& scale, QScratch& s) {
  const std::size_t m = window.size();
  for (std::size_t e = 0; e < m && !poly.empty(); ++e) {
    const QPoint2& p = window[e];
    const QPoint2& q = window[e + 1 == m ? 0 : e + 1];
    const std::size_t n = poly.size();
    in.resize(n);
    {
      CGAL::Protect_FPU_rounding<true> guard;
      for (std::size_t a = 0; a < n; ++a) in[a] = static_cast<int>(orientation<false>(p, p.i, q, q.i, poly[a], poly[a].i, s));
    }
    auto side = [&](std::size_t a) { return in[a]; };
    switch (geometry::clip_case(n, side)) {
      case geometry::ClipCase::Inside: continue;
      case geometry::ClipCase::Empty: poly.clear(); continue;
      case geometry::ClipCase::Cut: break;
    }
    scratch.clear();
    for (std::size_t a = 0; a < n; ++a) {
      const std::size_t b = a + 1 == n ? 0 : a + 1;
      const int sa = in[a], sb = in[b];
      if (sa >= 0) scratch.push_back(poly[a]);
      if ((sa > 0 && sb < 0) || (sa < 0 && sb > 0)) cut_by_line(p, q, poly[a], poly[b], scratch.emplace_back(), scale, s);
    }
    poly.swap(scratch);
  }
}

/// The same for a bound m given as a double (the same values as clip_convex_2d's for Epeck
/// points); `bound` is scratch.
template <class Points>
void clip_convex_2d(Points& poly, int c, double m, bool keep_greater, Points& scratch, std::vector<int>& in, EQ& bound) {
  if (poly.empty()) return;
  bound = m;
  clip_convex_2d(poly, c, bound, IA(m), keep_greater, scratch, in, IA(1));
}

}  // namespace shadow::exact
