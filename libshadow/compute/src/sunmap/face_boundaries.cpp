// SPDX-License-Identifier: GPL-3.0-or-later
// A face's boundaries as curves (and in doubles), its strips, clipping to a strip, a strip's
// plan from exact curves, the exact sums of its cells' areas, and a face's map assembled from its
// strips' (face_overlay.hpp): what the overlay of one strip needs before and after it.
#include "sunmap/face_overlay.hpp"
#include "sunmap/rough_segments.hpp"

#include "exact/lazy_geometry.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <map>
#include <numeric>
#include <cstdlib>
#include <utility>

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
    curves.emplace_back(SegmentTraits::Curve_2(p, q),
                        curve_tag(static_cast<std::size_t>(instant), CGAL::compare_xy(p, q) == CGAL::SMALLER));
  }
}

void add_segment(const Point2& from, const Point2& to, bool left, long instant, std::vector<Curve>& curves) {
  curves.emplace_back(SegmentTraits::Curve_2(from, to), curve_tag(static_cast<std::size_t>(instant), left));
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

namespace {

/// The strips of a chart from the middles of its segments' x ranges (choose_strips).
std::vector<Strip> strips_at_quantiles(std::vector<double> mids, std::size_t expected, const Polygon2& chart,
                                       std::size_t strip_edges) {
  const std::size_t count = mids.size();
  if (strip_edges == 0 || expected <= strip_edges || count == 0) return {Strip{}};
  double xmin = HUGE_VAL, xmax = -HUGE_VAL, ymin = HUGE_VAL, ymax = -HUGE_VAL;
  for (auto v = chart.vertices_begin(); v != chart.vertices_end(); ++v) {
    const auto x = CGAL::to_interval(v->x()), y = CGAL::to_interval(v->y());
    xmin = std::min(xmin, x.first), xmax = std::max(xmax, x.second);
    ymin = std::min(ymin, y.first), ymax = std::max(ymax, y.second);
  }
  // Sides at quantiles of the segments' middles, strictly inside the chart's x range; the
  // outer sides and the bottom and top a unit beyond it (every lit region lies in the chart).
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

/// The items whose x range [lo, hi] (range(item)) meets each strip's [x0, x1].
template <class Range>
std::vector<std::vector<std::size_t>> bucket_by_x(std::size_t count, const Range& range,
                                                  const std::vector<Strip>& strips) {
  std::vector<std::vector<std::size_t>> out(strips.size());
  if (strips.size() == 1 && strips[0].whole) {
    out[0].resize(count);
    for (std::size_t c = 0; c < count; ++c) out[0][c] = c;
    return out;
  }
  std::vector<double> lefts(strips.size());
  for (std::size_t s = 0; s < strips.size(); ++s) lefts[s] = strips[s].x0;
  for (std::size_t c = 0; c < count; ++c) {
    const auto [lo, hi] = range(c);
    // The strips whose [x0, x1] meets [lo, hi]: from the last whose x0 <= lo on.
    auto first = std::upper_bound(lefts.begin(), lefts.end(), lo);
    std::size_t s = first == lefts.begin() ? 0 : static_cast<std::size_t>(first - lefts.begin()) - 1;
    for (; s < strips.size() && strips[s].x0 <= hi; ++s) out[s].push_back(c);
  }
  return out;
}

}  // namespace

std::vector<Strip> choose_strips(const std::vector<Curve>& curves, std::size_t expected, const Polygon2& chart,
                                 std::size_t strip_edges) {
  std::vector<double> mids(curves.size());
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const auto [lo, hi] = x_range(curves[c]);
    mids[c] = 0.5 * (lo + hi);
  }
  return strips_at_quantiles(std::move(mids), expected, chart, strip_edges);
}

std::vector<Strip> choose_strips(const std::vector<RoughSegment>& segments, std::size_t expected,
                                 const Polygon2& chart, std::size_t strip_edges) {
  std::vector<double> mids(segments.size());
  for (std::size_t c = 0; c < segments.size(); ++c) mids[c] = 0.5 * (segments[c].xlo + segments[c].xhi);
  return strips_at_quantiles(std::move(mids), expected, chart, strip_edges);
}

std::vector<std::vector<std::size_t>> bucket_curves(const std::vector<Curve>& curves, const std::vector<Strip>& strips) {
  return bucket_by_x(curves.size(), [&](std::size_t c) { return x_range(curves[c]); }, strips);
}

std::vector<std::vector<std::size_t>> bucket_rough(const std::vector<RoughSegment>& segments,
                                                   const std::vector<Strip>& strips) {
  return bucket_by_x(
      segments.size(), [&](std::size_t c) { return std::pair<double, double>(segments[c].xlo, segments[c].xhi); },
      strips);
}

namespace {

/// The rough form of segment ab tagged `tag` (face_overlay.hpp's tags: its instant and side).
RoughSegment rough_of(const Point2& a, const Point2& b, long tag) {
  // The segment runs from its lexicographically smaller end (add_segment, add_boundary).
  const bool forward = CGAL::compare_xy(a, b) != CGAL::LARGER;
  const Point2 &from = forward ? a : b, &to = forward ? b : a;
  RoughSegment s;
  s.xa = CGAL::to_double(from.x()), s.ya = CGAL::to_double(from.y());
  s.xb = CGAL::to_double(to.x()), s.yb = CGAL::to_double(to.y());
  // x_range's bounds, exactly, so that bucket_rough gives a strip every curve bucket_curves does.
  const auto p = CGAL::to_interval(a.x()), q = CGAL::to_interval(b.x());
  s.xlo = std::min(p.first, q.first), s.xhi = std::max(p.second, q.second);
  s.instant = static_cast<std::uint32_t>(tag_instant(tag));
  s.left = tag_left(tag);
  return s;
}

}  // namespace

RoughSegment rough_segment(const Curve& curve) { return rough_of(curve.source(), curve.target(), curve.data()); }

RoughSegment rough_segment(const XCurve& curve) {
  return rough_of(curve.source(), curve.target(), *curve.data().begin());
}

namespace {

/// The point of segment pq (p.x < q.x) at x, exact at once: a leaf holding its rationals (as a
/// lazy expression it would hold a DAG of seven nodes over p and q until evaluated, and the
/// strips' clipped copies were a third of a round's memory).
Point2 at_x(const Point2& p, const Point2& q, const FT& x) {
  const auto &ep = CGAL::exact(p), &eq = CGAL::exact(q);
  const mpq_class& ex = CGAL::exact(x);
  mpq_class y = (ex - ep.x()) / (eq.x() - ep.x());
  y *= eq.y() - ep.y();
  y += ep.y();
  return Point2(Kernel::Exact_kernel::Point_2(ex, y));
}

}  // namespace

/// `c` clipped to the strip x0 <= x <= x1; false when nothing of it enters the strip's inside.
bool clip_to_strip(const Curve& c, const FT& x0, const FT& x1, Curve& out) {
  // Segments run from their lexicographically smaller end, so source().x() <= target().x().
  Point2 p = c.source(), q = c.target();
  if (CGAL::compare_xy(p, q) == CGAL::LARGER) std::swap(p, q);
  if (q.x() <= x0 || p.x() >= x1) {
    // Outside, or touching a side at one point, or lying on a side: the walk never crosses
    // the sides, so such a segment changes nothing inside.
    return false;
  }
  const Point2 a = p.x() < x0 ? at_x(p, q, x0) : p;
  const Point2 b = q.x() > x1 ? at_x(p, q, x1) : q;
  out = Curve(SegmentTraits::Curve_2(a, b), c.data());
  return true;
}

/// As sum over vertices of x_a (y_(a+1) - y_(a-1)): n products instead of 2n, each term a
/// fraction added over one running denominator and the sum normalised once (each of GMP's
/// rational products and sums takes gcds; one gcd of the longer numbers costs less).
mpq_class exact_polygon_area(const Polygon2& cell) {
  const std::size_t n = cell.size();
  mpq_class dy;
  mpz_class sum_n(0), sum_d(1), tn, td;
  for (std::size_t a = 0; a < n; ++a) {
    const auto& p = CGAL::exact(cell[a]);
    const auto& next = CGAL::exact(cell[a + 1 == n ? 0 : a + 1]);
    const auto& prev = CGAL::exact(cell[a == 0 ? n - 1 : a - 1]);
    dy = next.y() - prev.y();
    const mpq_srcptr x = p.x().get_mpq_t();
    mpz_mul(tn.get_mpz_t(), mpq_numref(x), mpq_numref(dy.get_mpq_t()));
    mpz_mul(td.get_mpz_t(), mpq_denref(x), mpq_denref(dy.get_mpq_t()));
    // sum += tn / td over the running denominator, not normalised
    sum_n *= td;
    mpz_addmul(sum_n.get_mpz_t(), tn.get_mpz_t(), sum_d.get_mpz_t());
    sum_d *= td;
  }
  sum_d *= 2;
  mpq_class area;
  mpq_set_num(area.get_mpq_t(), sum_n.get_mpz_t());
  mpq_set_den(area.get_mpq_t(), sum_d.get_mpz_t());
  mpq_canonicalize(area.get_mpq_t());
  return area;
}

FaceMap assemble(std::vector<StripMap>& strips, SunHoursFace face, const mpq_class& scale, std::size_t levels) {
  FaceMap out;
  std::map<mpq_class, std::vector<const std::vector<mpq_class>*>> hour_area;
  std::vector<std::vector<const std::vector<mpq_class>*>> level_area(levels + 1);
  mpq_class dropped(0);
  for (StripMap& s : strips) {
    for (SunHoursCell& c : s.cells) {
      c.region_id += out.regions;
      out.cells.push_back(std::move(c));
    }
    out.regions += s.regions;
    s.cells = {};
    for (SunHoursCell& c : s.level_cells) {
      c.region_id += out.level_regions;
      out.level_cells.push_back(std::move(c));
    }
    out.level_regions += s.level_regions;
    s.level_cells = {};
    for (const auto& [hours, areas] : s.hour_area) hour_area[hours].push_back(&areas);
    for (std::size_t k = 0; k < s.level_area.size() && k <= levels; ++k) level_area[k].push_back(&s.level_area[k]);
    dropped += s.dropped;
  }
  face.dropped_area = area_3d_mpq(dropped, scale);
  for (const auto& [hours, parts] : hour_area)
    face.areas.push_back({exact::round_mpq_to_double(hours.get_mpq_t()), area_3d_of_sum(parts, scale)});
  // At least level k: the cells of the levels k and above, summed exactly.
  std::vector<const std::vector<mpq_class>*> at_least;
  face.level_areas.assign(levels, 0.0);
  for (std::size_t k = levels; k >= 1; --k) {
    at_least.insert(at_least.end(), level_area[k].begin(), level_area[k].end());
    face.level_areas[k - 1] = area_3d_of_sum(at_least, scale);
  }
  out.face = std::move(face);
  strips.clear();
  return out;
}

void LevelRounds::plan(const std::vector<std::size_t>& order, const std::vector<std::size_t>& band_ends,
                       const std::vector<Curve>& curves, const std::vector<std::size_t>& which,
                       const mpq_class& whole) {
  std::vector<RoughSegment> rough;
  for (std::size_t c : which) rough.push_back(rough_segment(curves[c]));
  std::vector<std::size_t> all(rough.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  plan(order, band_ends, rough, all, whole);
}

}  // namespace shadow::sunmap
