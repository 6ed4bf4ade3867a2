// SPDX-License-Identifier: GPL-3.0-or-later
// A face's boundaries as curves, its strips, and the exact sums of its cells' areas
// (face_overlay.hpp): what the overlay of one strip needs before and after it.
#include "sunmap/face_overlay.hpp"

#include "exact/lazy_geometry.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

namespace shadow::sunmap {

using namespace exact;

namespace {

/// Interval bounds of a curve's x range.
std::pair<double, double> x_range(const Curve& c) {
  const auto a = CGAL::to_interval(c.source().x()), b = CGAL::to_interval(c.target().x());
  return {std::min(a.first, b.first), std::max(a.second, b.second)};
}

}  // namespace

void add_boundary(const Polygon2& polygon, long instant, std::vector<Curve>& curves) {
  const std::size_t n = polygon.size();
  for (std::size_t a = 0; a < n; ++a) {
    const Point2& p = polygon[a];
    const Point2& q = polygon[(a + 1) % n];
    if (p == q) continue;
    const long tag = CGAL::compare_xy(p, q) == CGAL::SMALLER ? instant + 1 : -(instant + 1);
    curves.emplace_back(Kernel::Segment_2(p, q), tag);
  }
}

void add_segment(const Point2& from, const Point2& to, bool left, long instant, std::vector<Curve>& curves) {
  curves.emplace_back(Kernel::Segment_2(from, to), left ? instant + 1 : -(instant + 1));
}

double area_3d_mpq(const mpq_class& chart_area, const mpq_class& scale) {
  // sqrt(chart_area^2 x scale), the rational rounded to 256 bits before the root as
  // sqrt_to_double does, so the result is area_3d's bit for bit.
  if (sgn(chart_area) == 0) return 0.0;
  const mpq_class squared = chart_area * chart_area * scale;
  return exact::sqrt_mpq_to_double(squared.get_mpq_t());
}

double area_3d_of_sum(const std::vector<const std::vector<mpq_class>*>& parts, const mpq_class& scale) {
  std::size_t count = 0;
  long top = LONG_MIN;  // the largest term's binary exponent
  for (const std::vector<mpq_class>* part : parts)
    for (const mpq_class& t : *part) {
      if (sgn(t) == 0) continue;
      ++count;
      long e = 0;
      mpf_class approx(t, 64);
      mpf_get_d_2exp(&e, approx.get_mpf_t());
      top = std::max(top, e);
    }
  if (count == 0) return 0.0;
  // Fixed point with `shift` bits: each term truncated loses < 2^-shift, so the total lies in
  // [S, S + count] x 2^-shift, a bracket about 2^-60 of the total's last bit wide (the terms are
  // non-negative, so the total is at least the largest term).
  long bits = 0;
  while ((std::size_t{1} << bits) < count) ++bits;
  const long shift = 53 + 60 + bits - top;
  mpz_class sum(0), term;
  for (const std::vector<mpq_class>* part : parts)
    for (const mpq_class& t : *part) {
      if (shift >= 0) {
        mpz_mul_2exp(term.get_mpz_t(), t.get_num_mpz_t(), static_cast<mp_bitcnt_t>(shift));
        mpz_fdiv_q(term.get_mpz_t(), term.get_mpz_t(), t.get_den_mpz_t());
      } else {
        mpz_mul_2exp(term.get_mpz_t(), t.get_den_mpz_t(), static_cast<mp_bitcnt_t>(-shift));
        mpz_fdiv_q(term.get_mpz_t(), t.get_num_mpz_t(), term.get_mpz_t());
      }
      sum += term;
    }
  mpz_class unit(1);
  mpq_class lo, hi;
  if (shift >= 0) {
    mpz_mul_2exp(unit.get_mpz_t(), unit.get_mpz_t(), static_cast<mp_bitcnt_t>(shift));
    lo = mpq_class(sum, unit);
    hi = mpq_class(sum + count, unit);
  } else {
    mpz_mul_2exp(unit.get_mpz_t(), unit.get_mpz_t(), static_cast<mp_bitcnt_t>(-shift));
    lo = mpq_class(sum * unit);
    hi = mpq_class((sum + count) * unit);
  }
  lo.canonicalize();
  hi.canonicalize();
  const double a = area_3d_mpq(lo, scale), b = area_3d_mpq(hi, scale);
  if (a == b) return a;
  // Too close to a tie to tell: the exact sum, pairwise (balanced) to keep the operands small.
  std::vector<mpq_class> terms;
  for (const std::vector<mpq_class>* part : parts) terms.insert(terms.end(), part->begin(), part->end());
  while (terms.size() > 1) {
    std::vector<mpq_class> next;
    for (std::size_t k = 0; k + 1 < terms.size(); k += 2) next.push_back(terms[k] + terms[k + 1]);
    if (terms.size() % 2 == 1) next.push_back(terms.back());
    terms.swap(next);
  }
  return area_3d_mpq(terms.front(), scale);
}

std::vector<Strip> choose_strips(const std::vector<Curve>& curves, std::size_t expected, const Polygon2& chart,
                                 std::size_t strip_edges) {
  const std::size_t count = curves.size();
  if (strip_edges == 0 || expected <= strip_edges || count == 0) return {Strip{}};
  double xmin = HUGE_VAL, xmax = -HUGE_VAL, ymin = HUGE_VAL, ymax = -HUGE_VAL;
  for (auto v = chart.vertices_begin(); v != chart.vertices_end(); ++v) {
    const auto x = CGAL::to_interval(v->x()), y = CGAL::to_interval(v->y());
    xmin = std::min(xmin, x.first), xmax = std::max(xmax, x.second);
    ymin = std::min(ymin, y.first), ymax = std::max(ymax, y.second);
  }
  // Sides at quantiles of the segments' middles, strictly inside the chart's x range; the
  // outer sides and the bottom and top a unit beyond it (every lit region lies in the chart).
  std::vector<double> mids(count);
  for (std::size_t c = 0; c < count; ++c) {
    const auto [lo, hi] = x_range(curves[c]);
    mids[c] = 0.5 * (lo + hi);
  }
  const std::size_t k = std::min<std::size_t>((expected + strip_edges - 1) / strip_edges, 4096);
  std::vector<double> sides{std::floor(xmin) - 1.0};
  for (std::size_t s = 1; s < k; ++s) {
    auto nth = mids.begin() + static_cast<std::ptrdiff_t>(s * count / k);
    std::nth_element(mids.begin(), nth, mids.end());
    const double x = *nth;
    if (x > sides.back() && x > xmin && x < xmax) sides.push_back(x);
  }
  sides.push_back(std::ceil(xmax) + 1.0);
  std::vector<Strip> strips;
  for (std::size_t s = 0; s + 1 < sides.size(); ++s)
    strips.push_back(Strip{false, sides[s], sides[s + 1], std::floor(ymin) - 1.0, std::ceil(ymax) + 1.0});
  return strips;
}

std::vector<std::vector<std::size_t>> bucket_curves(const std::vector<Curve>& curves, const std::vector<Strip>& strips) {
  std::vector<std::vector<std::size_t>> out(strips.size());
  if (strips.size() == 1 && strips[0].whole) {
    out[0].resize(curves.size());
    for (std::size_t c = 0; c < curves.size(); ++c) out[0][c] = c;
    return out;
  }
  std::vector<double> lefts(strips.size());
  for (std::size_t s = 0; s < strips.size(); ++s) lefts[s] = strips[s].x0;
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const auto [lo, hi] = x_range(curves[c]);
    // The strips whose [x0, x1] meets [lo, hi]: from the last whose x0 <= lo on.
    auto first = std::upper_bound(lefts.begin(), lefts.end(), lo);
    std::size_t s = first == lefts.begin() ? 0 : static_cast<std::size_t>(first - lefts.begin()) - 1;
    for (; s < strips.size() && strips[s].x0 <= hi; ++s) out[s].push_back(c);
  }
  return out;
}

}  // namespace shadow::sunmap
